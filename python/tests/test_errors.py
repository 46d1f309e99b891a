"""One exception class per CLI exit code, with the library's message."""
import subprocess
import sys

import numpy as np
import pytest

import al_refine as al
from conftest import run_cli


def test_categories_match_the_cli_exit_codes():
    for cls, code, category in [(al.UsageError, 1, "usage"), (al.BadInputError, 2, "bad_input"),
                                (al.EmptyGraphError, 3, "empty_graph"), (al.InternalError, 4, "internal")]:
        assert issubclass(cls, al.Error) and cls.exit_code == code and cls.category == category


def test_usage_error_carries_the_cli_message(cli, synth, synth_dir, tmp_path):
    with pytest.raises(al.UsageError) as e:
        al.refine(synth.scene, synth.removed["fgs"], method="nope")
    proc = run_cli(cli, "refine", "--scene", synth_dir / "scene.ply", "--removed", synth_dir / "removed_fgs.npy",
                   "--method", "fgs", "--solver", "nope", "--out", tmp_path / "x", check=False)
    assert proc.returncode == al.UsageError.exit_code
    with pytest.raises(al.UsageError) as same:
        al.refine(synth.scene, synth.removed["fgs"], solver="nope")
    assert str(same.value) in proc.stderr
    assert "method" in str(e.value)


def test_usage_errors_name_the_option(synth):
    with pytest.raises(al.UsageError, match="'k' = 0 must be in \\[1, 1000\\]"):
        al.refine(synth.scene, synth.removed["fgs"], k=0)
    with pytest.raises(al.UsageError, match="unknown option 'no_such_option'.*graph: k, delta"):
        al.refine(synth.scene, synth.removed["fgs"], no_such_option=1)
    with pytest.raises(al.UsageError, match="must be a number"):
        al.refine(synth.scene, synth.removed["fgs"], delta="wide")


def test_huge_integers_are_usage_errors(synth):
    with pytest.raises(al.UsageError, match="'k'"):
        al.refine(synth.scene, synth.removed["fgs"], k=2**70)
    with pytest.raises(al.UsageError, match="object_id"):
        al.refine(synth.scene, synth.removed["fgs"], labels=synth.labels, object_id=2**70)


def test_labels_are_read_as_the_cli_reads_them(cli, synth, synth_dir, tmp_path):
    with pytest.raises(al.BadInputError, match="integer"):
        al.refine(synth.scene, synth.removed["fgs"], labels=synth.labels.astype(np.float32),
                  object_id=synth.target_id)
    absent = int(synth.labels.max()) + 7
    with pytest.raises(al.BadInputError, match="not among the labels"):
        al.refine(synth.scene, synth.removed["fgs"], labels=synth.labels, object_id=absent)
    with pytest.raises(al.BadInputError, match="not among the labels"):
        al.evaluate(synth.scene, synth.cameras[:1], synth.removed["fgs"], labels=synth.labels, object_id=absent)
    proc = run_cli(cli, "refine", "--scene", synth_dir / "scene.ply", "--removed", synth_dir / "removed_fgs.npy",
                   "--labels", synth_dir / "labels.npy", "--object-id", absent, "--out", tmp_path / "x", check=False)
    assert proc.returncode == al.BadInputError.exit_code and "not among the labels" in proc.stderr
    floats = tmp_path / "float_labels.npy"
    np.save(floats, synth.labels.astype(np.float32))
    proc = run_cli(cli, "refine", "--scene", synth_dir / "scene.ply", "--removed", synth_dir / "removed_fgs.npy",
                   "--labels", floats, "--out", tmp_path / "y", check=False)
    assert proc.returncode == al.BadInputError.exit_code and "integer" in proc.stderr


def test_bad_input_error_carries_the_cli_message(cli, synth, synth_dir, tmp_path):
    with pytest.raises(al.BadInputError, match="mask length 5 does not match the scene's 20000 Gaussians"):
        al.refine(synth.scene, np.zeros(5, dtype=bool))
    missing = str(tmp_path / "missing.ply")
    with pytest.raises(al.BadInputError) as e:
        al.Scene.load(missing)
    proc = run_cli(cli, "refine", "--scene", missing, "--removed", synth_dir / "removed_fgs.npy", "--out",
                   tmp_path / "y", check=False)
    assert proc.returncode == al.BadInputError.exit_code
    assert str(e.value) in proc.stderr


def test_empty_graph_error_holds_the_result(synth):
    with pytest.raises(al.EmptyGraphError, match="empty graph") as e:
        al.refine(synth.scene, synth.removed["fgs"], delta=0.0, delta_mode="distance")
    assert e.value.result.status == "empty_graph"
    assert np.array_equal(e.value.result.refined, synth.removed["fgs"])


def test_internal_error_for_exhausted_memory():
    # In a child whose address space is capped (so the machine is never at risk), a render of a
    # 20000 x 20000 view needs ~5 GB and fails cleanly: InternalError "out of memory", as the
    # CLI's exit code 4.
    code = """
import resource, al_refine as al
s = al.synth('room', 2000, seed=1, views=1, width=16, height=12)
c = s.cameras[0]
huge = al.Camera('huge', 20000, 20000, c.fx * 1250, c.fy * 1250, c.R, c.t)
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
try:
    al.render(s.scene, huge)
except al.InternalError as e:
    print(type(e).__name__, e.exit_code, e.category, e)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.stdout.strip() == "InternalError 4 internal out of memory", (out.stdout, out.stderr)
