"""The module's surface: stubs, evaluate's records, the three-line example from build/."""
import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import al_refine as al


def test_stubs_declare_exactly_the_public_names():
    stub = Path(al.__file__).with_name("al_refine.pyi")
    tree = ast.parse(stub.read_text())
    declared = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    declared |= {t.id for n in tree.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                 for t in (n.targets if isinstance(n, ast.Assign) else [n.target]) if isinstance(t, ast.Name)}
    public = {name for name in dir(al) if not name.startswith("_")}
    declared = {name for name in declared if not name.startswith("__")}
    assert public <= declared, public - declared
    assert declared - public <= {"OptionValue", "ArrayLike"}, declared - public


def test_evaluate_gives_records_a_data_frame_takes(synth, tmp_path):
    refined = al.refine(synth.scene, synth.removed["fgs"], labels=synth.labels, object_id=synth.target_id)
    result = al.evaluate(synth.scene, synth.cameras, synth.removed["fgs"], {"bk": refined.refined},
                         labels=synth.labels, object_id=synth.target_id, label="fgs", out=str(tmp_path / "e"))
    summary, views = result["summary"], result["views"]
    assert [c["label"] for c in summary] == ["fgs", "fgs+bk"]
    assert summary[1]["added"] == len(refined.added)
    scalar = (int, float, str, bool, type(None))
    for record in summary + views:
        assert all(isinstance(v, scalar) for v in record.values())
    assert len({frozenset(v) for v in views}) == 1 and len(views) == len(synth.cameras)
    report = json.loads((tmp_path / "e" / "report.json").read_text())
    assert report["metrics"]["columns"][0]["depth"]["mean_acc_delta_depth"] == \
        summary[0]["depth.mean_acc_delta_depth"]
    csv_header = (tmp_path / "e" / "metrics.csv").read_text().splitlines()[0].split(",")
    assert set(views[0]) == set(csv_header)
    assert (tmp_path / "e" / "report.html").is_file()


def test_evaluate_without_out_keeps_nothing(synth):
    result = al.evaluate(synth.scene, synth.cameras[:1], synth.removed["gc"], labels=synth.labels,
                         object_id=synth.target_id)
    assert result["out"] is None and len(result["views"]) == 1


def test_three_lines_from_the_build_folder():
    build = Path(al.__file__).parent
    code = ("import al_refine as al; s = al.synth('room', 20000, seed=1, views=2); "
            "r = al.refine(s.scene, s.removed['fgs'], labels=s.labels, object_id=s.target_id); "
            "print(r.summary['added'], r.summary['gt_f1_after'])")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run([sys.executable, "-c", code], cwd=build, env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    added, f1 = out.stdout.split()
    assert int(added) > 0 and 0.0 < float(f1) <= 1.0


def test_evaluate_scores_the_feature_metrics_and_takes_their_options(synth):
    perfect = synth.labels == synth.target_id
    args = (synth.scene, synth.cameras, perfect)
    kw = dict(labels=synth.labels, object_id=synth.target_id)
    on = al.evaluate(*args, {"half": perfect & (np.arange(perfect.size) % 2 == 0)}, **kw)["summary"]
    # Everything of the target removed: nothing of it is segmented after; half of it removed: some is.
    assert on[0]["feature.mean_residual"] < 0.05 and on[0]["feature.mean_iou_after"] < 0.05
    assert on[1]["feature.mean_residual"] > on[0]["feature.mean_residual"]
    assert on[0]["feature.mean_iou_drop"] > 0.5
    # What is left of the object, by the ground truth: nothing, and some of it for the half removal.
    assert on[0]["residual_gt.mean"] == 0.0 and on[1]["residual_gt.mean"] > 0.1
    assert al.evaluate(*args, px_colour_tol=0.05, **kw)["report"]["params"]["residual"]["px_colour_tol"] == 0.05
    tuned = al.evaluate(*args, feature_min_sim=0.6, feature_channels=8, **kw)["report"]["params"]["feature"]
    assert tuned["feature_min_sim"] == 0.6 and tuned["feature_channels"] == 8
    off = al.evaluate(*args, feature_metrics="off", **kw)
    assert not any(k.startswith("feature.") for k in off["summary"][0])
    with pytest.raises(al.UsageError, match="feature_min_sim"):
        al.evaluate(*args, feature_min_sim=2, **kw)
