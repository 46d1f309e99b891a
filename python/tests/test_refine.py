"""refine from arrays agrees with the CLI on the same input; options come from the tables."""
import numpy as np
import pytest

import al_refine as al
from conftest import run_cli


def scene_from_arrays(s):
    sc = s.scene
    return al.Scene.from_arrays(np.array(sc.xyz), np.array(sc.opacity), np.array(sc.scales),
                                np.array(sc.rotations), np.array(sc.sh), np.array(sc.features))


def test_synth_in_memory_is_the_written_scene(synth, synth_dir):
    loaded = al.Scene.load(str(synth_dir / "scene.ply"))
    assert len(loaded) == len(synth.scene)
    for name in ("xyz", "opacity", "scales", "rotations", "sh", "features"):
        assert np.array_equal(getattr(loaded, name), getattr(synth.scene, name)), name
    assert np.array_equal(np.load(synth_dir / "removed_fgs.npy"), synth.removed["fgs"])
    assert np.array_equal(np.load(synth_dir / "labels.npy"), synth.labels)


@pytest.mark.parametrize("solver,extra", [("bk", []), ("cp", ["--threshold", "0.4", "--lambda", "2"])])
def test_refine_from_arrays_matches_cli(cli, synth, synth_dir, tmp_path, solver, extra):
    out = tmp_path / "cli"
    run_cli(cli, "refine", "--scene", synth_dir / "scene.ply", "--removed", synth_dir / "removed_fgs.npy",
            "--method", "fgs", "--solver", solver, "--labels", synth_dir / "labels.npy", *extra, "--quiet",
            "--out", out)
    cli_mask = np.load(out / "refined.npy")
    options = {"threshold": 0.4, "lambda_": 2} if extra else {}
    r = al.refine(scene_from_arrays(synth), synth.removed["fgs"], method="fgs", solver=solver,
                  labels=synth.labels, object_id=synth.target_id, **options)
    assert r.refined.dtype == np.bool_ and r.refined.shape == (len(synth.scene),)
    assert np.array_equal(r.refined, cli_mask)
    added = np.flatnonzero(r.refined & ~synth.removed["fgs"])
    assert len(added) > 0, "the comparison must cover a refinement that changes something"
    assert np.array_equal(r.added, added)
    assert np.array_equal(r.restored, np.flatnonzero(synth.removed["fgs"] & ~r.refined))
    cli_report = __import__("json").loads((out / "report.json").read_text())
    assert r.report["counts"] == cli_report["counts"]
    assert r.report["gt"] == cli_report["gt"]
    assert r.summary["added"] == len(added) and r.summary["status"] == "ok"


def test_refine_writes_the_cli_outputs(synth, tmp_path):
    r = al.refine(synth.scene, np.flatnonzero(synth.removed["fgs"]), out=str(tmp_path / "r"))
    assert np.array_equal(np.load(tmp_path / "r" / "refined.npy"), r.refined)
    for name in ("refined.txt", "added.txt", "remaining.ply", "report.json"):
        assert (tmp_path / "r" / name).is_file(), name


def test_indices_and_mask_give_the_same_refinement(synth):
    mask = synth.removed["fgs"]
    a = al.refine(synth.scene, mask)
    b = al.refine(synth.scene, np.flatnonzero(mask))
    assert np.array_equal(a.refined, b.refined)


def test_table_options_reach_the_library(synth):
    # Every value differs from its default (restore and centre are on by default).
    r = al.refine(synth.scene, synth.removed["fgs"], k=6, delta=1.0, spatial=False, threshold="percentile:90",
                  restore=False, kl_smoothing=0.2, grow_rounds=0, centre=False, prior_weight=0.25,
                  min_segment_share=0.5)
    p = r.report["params"]
    assert (p["k"], p["delta"], p["spatial"], p["threshold"], p["restore"], p["kl_smoothing"]) == \
        (6, 1.0, False, "percentile:90", "off", 0.2)
    assert (p["grow_rounds"], p["centre"], p["prior_weight"], p["min_segment_share"]) == (0, "off", 0.25, 0.5)
    assert r.report["graph"]["rounds"] == 1
    cp = al.refine(synth.scene, synth.removed["fgs"], solver="cp", cp_it_max=3)
    assert cp.report["params"]["solver_options"] == {"cp_it_max": 3}


def test_help_teaches_every_table_field():
    doc = al.refine.__doc__
    for field in ("k (", "delta (", "lambda (", "kl_smoothing (", "threshold (", "min_segment_share (",
                  "restore (auto|on|off, default auto)", "spatial (on|off, default on)", "grow_rounds (",
                  "centre (auto|on|off|shared, default auto)", "prior_weight (",
                  "cp_dif_tol (", "pivot ("):
        assert field in doc, field


def test_defaults_are_the_clis(cli, synth, synth_dir, tmp_path):
    # The call: the same flags both ways, every other option left to its default.
    for name, flags, kwargs in [("fgs", ["--method", "fgs", "--k", "10", "--delta", "0.8"],
                                 {"method": "fgs", "k": 10, "delta": 0.8}),
                                ("bare", [], {})]:
        out = tmp_path / name
        run_cli(cli, "refine", "--scene", synth_dir / "scene.ply", "--removed", synth_dir / "removed_fgs.npy",
                *flags, "--quiet", "--out", out)
        r = al.refine(synth.scene, synth.removed["fgs"], **kwargs)
        cli_report = __import__("json").loads((out / "report.json").read_text())
        assert r.report["solver"]["name"] == cli_report["solver"]["name"], name
        assert r.report["params"]["method"] == cli_report["params"]["method"], name
        assert np.array_equal(r.refined, np.load(out / "refined.npy")), name
        assert len(r.added) + len(r.restored) > 0, "the comparison must cover a refinement that changes something"
