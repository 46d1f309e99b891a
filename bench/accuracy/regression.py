#!/usr/bin/python3
"""The gen_scenes.py half of ctest's accuracy regression (tests/cli/accuracy_gen_scenes.sh; the
al-refine synth half is tests/refine/refine_accuracy_test.cpp). Small scenes of three styles are
generated at test time (fixed seeds from the reporting half, 12,000 Gaussians) and refined with the
default flags, bk and cp; the properties the accuracy bench reports (docs/accuracy.md) must hold:

  every run      F1 lowered by at most 0.01
  fgs_like       F1 raised on every scene; >= 30 % of the misses recovered on average; precision of
                 the added >= 0.9 (pooled)
  gg_like        over-removed Gaussians restored at precision >= 0.9 (pooled); F1 raised on every scene
  bk vs cp       the same F1 within 0.02 per run
  d16 seed 33    sags_like: a drop beyond 0.01 comes with the feature-group warning; with
                 --feature-group-bound on no drop beyond 0.01; at 60,000 Gaussians (the
                 reporting scene) none by default either

usage: regression.py AL_REFINE GEN_SCENES_PY WORK_DIR
Exit 0 = pass, 1 = a property failed (each failure printed).
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics  # noqa: E402
import runner  # noqa: E402

SCENES = [("d16", 16, "plain", 21), ("d32", 32, "plain", 22), ("clip128", 128, "clip", 23)]
# SAGS takes a touching ball's near side with a target it takes whole (docs/refine.md items 13,
# 14). At 12,000 Gaussians the default completes the ball whole (F1 lowered by 0.033 / 0.060 with
# bk / cp): nothing of it is left beyond the additions, so item 14 does not bound them, and the
# default must say so in `warnings`; --feature-group-bound on must keep the drop within 0.01. At
# 60,000 the additions are a layer of the ball and the default bounds them.
FEATURE_GROUP_SCENE = ("d16", 16, "plain", 33)
FEATURE_GROUP_LAYER_N = 60000
GROUP_WARNING = "group of other features taken in part"
N = 12000
MASKS = {"fgs_like": "fgs", "sags_like": "sags", "gg_like": "gg"}


def generate(gen_script, work, style, dim, kind, seed, n=N):
    folder = os.path.join(work, f"{style}-{seed}-n{n}")
    subprocess.run(["/usr/bin/python3", gen_script, "--out", folder, "--seed", str(seed), "--n-gaussians", str(n),
                    "--feature-dim", str(dim), "--feature-style", kind], check=True, stdout=subprocess.DEVNULL)
    return runner.SceneData(folder)


def check_feature_group_bound(al_bin, gen_script, work):
    """The warning by default, the bound on request (FEATURE_GROUP_SCENE); returns failures."""
    style, dim, kind, seed = FEATURE_GROUP_SCENE
    data = generate(gen_script, work, style, dim, kind, seed)
    path = os.path.join(data.folder, "removed_sags_like.npy")
    failures = []
    for solver in ("bk", "cp"):
        name = f"{style}-{seed} sags_like {solver}"
        default = runner.run_al_refine(al_bin, data, path, "sags", solver, [])
        bounded = runner.run_al_refine(al_bin, data, path, "sags", solver, ["--feature-group-bound", "on"])
        if "error" in (default["status"], bounded["status"]):
            failures.append(f"{name}: al-refine failed")
            continue
        print(f"{name}: F1 {default['f1_before']:.4f} -> {default['f1_after']:.4f} (default), "
              f"{bounded['f1_after']:.4f} (--feature-group-bound on)")
        if default["dF1"] < -0.01 and not any(GROUP_WARNING in w for w in default["warnings"]):
            failures.append(f"{name}: F1 lowered by {-default['dF1']:.4f} without the feature-group warning")
        if bounded["dF1"] < -0.01:
            failures.append(f"{name}: --feature-group-bound on still lowers F1 by {-bounded['dF1']:.4f}")
    return failures + check_feature_group_layer(al_bin, gen_script, work)


def check_feature_group_layer(al_bin, gen_script, work):
    """FEATURE_GROUP_SCENE at FEATURE_GROUP_LAYER_N: the default bounds the layer; returns failures."""
    style, dim, kind, seed = FEATURE_GROUP_SCENE
    data = generate(gen_script, work, style, dim, kind, seed, FEATURE_GROUP_LAYER_N)
    path = os.path.join(data.folder, "removed_sags_like.npy")
    failures = []
    for solver in ("bk", "cp"):
        name = f"{style}-{seed} (n {FEATURE_GROUP_LAYER_N}) sags_like {solver}"
        r = runner.run_al_refine(al_bin, data, path, "sags", solver, [])
        if r["status"] == "error":
            failures.append(f"{name}: al-refine failed")
            continue
        print(f"{name}: F1 {r['f1_before']:.4f} -> {r['f1_after']:.4f} (default)")
        if r["dF1"] < -0.01:
            failures.append(f"{name}: the default lowers F1 by {-r['dF1']:.4f}")
    return failures


def main(al_bin, gen_script, work):
    os.makedirs(work, exist_ok=True)
    failures, recs = check_feature_group_bound(al_bin, gen_script, work), []
    for style, dim, kind, seed in SCENES:
        data = generate(gen_script, work, style, dim, kind, seed)
        for mask, method in MASKS.items():
            path = os.path.join(data.folder, f"removed_{mask}.npy")
            by_solver = {}
            for solver in ("bk", "cp"):
                r = runner.run_al_refine(al_bin, data, path, method, solver, [])
                name = f"{style}-{seed} {mask} {solver}"
                if r["status"] == "error":
                    failures.append(f"{name}: al-refine failed: {r.get('stderr', '')}")
                    continue
                r.update(name=name, mask=mask)
                recs.append(r)
                by_solver[solver] = r
                print(f"{name}: F1 {r['f1_before']:.4f} -> {r['f1_after']:.4f}, added {r['added']} "
                      f"({r['added_true']} object), restored {r['restored']} ({r['restored_true']} background)")
                if r["dF1"] < -0.01:
                    failures.append(f"{name}: F1 lowered by {-r['dF1']:.4f}")
                if mask in ("fgs_like", "gg_like") and not r["raised"]:
                    failures.append(f"{name}: F1 not raised")
            if len(by_solver) == 2 and abs(by_solver["bk"]["f1_after"] - by_solver["cp"]["f1_after"]) > 0.02:
                failures.append(f"{style}-{seed} {mask}: bk and cp differ by more than 0.02 F1")
    fgs = [r for r in recs if r["mask"] == "fgs_like"]
    gg = [r for r in recs if r["mask"] == "gg_like"]
    recovered = float(np.mean([r["misses_recovered"] or 0.0 for r in fgs])) if fgs else 0.0
    prec_add = sum(r["added_true"] for r in fgs) / max(1, sum(r["added"] for r in fgs))
    prec_rest = sum(r["restored_true"] for r in gg) / max(1, sum(r["restored"] for r in gg))
    print(f"fgs_like: misses recovered {recovered:.3f}, precision of the added {prec_add:.3f}; "
          f"gg_like: precision of the restored {prec_rest:.3f}")
    if recovered < 0.30:
        failures.append(f"fgs_like: misses recovered {recovered:.3f} < 0.30")
    if prec_add < 0.9:
        failures.append(f"fgs_like: precision of the added {prec_add:.3f} < 0.9")
    if prec_rest < 0.9:
        failures.append(f"gg_like: precision of the restored {prec_rest:.3f} < 0.9")
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
