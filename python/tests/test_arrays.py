"""Zero copy where the layout allows, a CopyWarning where it does not."""
import warnings

import numpy as np
import pytest

import al_refine as al


def arrays(s):
    sc = s.scene
    return dict(xyz=np.array(sc.xyz), opacity=np.array(sc.opacity), scales=np.array(sc.scales),
                rotations=np.array(sc.rotations), sh=np.array(sc.sh))


def test_float32_features_are_used_in_place(synth):
    features = np.array(synth.scene.features, dtype=np.float32)  # the caller's own, writable array
    with warnings.catch_warnings():
        warnings.simplefilter("error", al.CopyWarning)
        scene = al.Scene.from_arrays(**arrays(synth), features=features)
    assert scene.features is features
    assert "features" not in scene.copied
    # The library reads the caller's memory: a change there changes the refinement's input.
    a = al.refine(scene, synth.removed["fgs"])
    assert a.report["counts"]["edges"] > 0
    features[:] = 0.0  # zero-norm features get no semantic edges: nothing is left to refine
    with pytest.raises(al.EmptyGraphError) as e:
        al.refine(scene, synth.removed["fgs"])
    assert e.value.result.report["graph"]["zero_norm_features"] == e.value.result.report["counts"]["candidates"]


def test_other_layouts_are_copied_with_a_warning(synth):
    f64 = np.asarray(synth.scene.features, dtype=np.float64)
    with pytest.warns(al.CopyWarning, match="features"):
        scene = al.Scene.from_arrays(**arrays(synth), features=f64)
    assert "features" in scene.copied
    assert not np.shares_memory(scene.features, f64)
    reference = al.Scene.from_arrays(**arrays(synth), features=np.asarray(synth.scene.features, np.float32))
    mask = synth.removed["fgs"]
    assert np.array_equal(al.refine(scene, mask).refined, al.refine(reference, mask).refined)
    with pytest.warns(al.CopyWarning, match="removed"):
        al.refine(reference, np.ascontiguousarray(np.stack([mask, mask], 1))[:, 0])


def test_scene_columns_are_read_only_views(synth):
    xyz = synth.scene.xyz
    assert not xyz.flags.owndata and not xyz.flags.writeable
    assert np.shares_memory(xyz, synth.scene.xyz)  # two views of one buffer, no copy per access
    with pytest.raises(ValueError):
        xyz[0, 0] = 1.0


def test_render_arrays_own_the_renderer_memory(synth):
    img = al.render(synth.scene, synth.cameras[0])
    assert img["rgb"].shape == (synth.cameras[0].height, synth.cameras[0].width, 3)
    assert img["rgb"].dtype == np.float32 and not img["rgb"].flags.owndata  # a capsule owns it: no copy
    removed = al.render(synth.scene, synth.cameras[0], synth.removed["gc"])
    assert not np.array_equal(img["depth"], removed["depth"])
