#!/usr/bin/env python3
"""Residual validity bench (issue 32): does each residual-like figure of `al-refine eval` say how
much of the object a removal left? Measured against the ground-truth residual (truth.py: the
definition of the issue, computed in numpy from `al-refine render --npy` renders) on removals of
both scene generators, each kind of leftover (removals.py) on every scene.

  /usr/bin/python3 bench/residual/run.py [--half report|tune] [--bin build/al-refine] [--jobs 2]
                                         [--px-grid] [--write] [--cache DIR] [--work DIR]
  /usr/bin/python3 bench/residual/run.py --from-results     (docs and plot from the saved records)

Scenes (bench/accuracy/scenes.py's cache and generators, 60,000 Gaussians):
  tune    gen d16 seed 1, gen clip128 seed 2, synth room seed 1, synth counter seed 2 — where
          residual_px's tolerances were chosen (--px-grid prints the grid);
  report  gen d16 seed 21, gen clip128 seed 22, gen d32 seed 23, synth room 8, counter 9, garden 10
          — the published numbers.
--write (report half only): bench/results/residual_validity.json, the tables in docs/eval.md and
README.md and docs/eval_residual_validity.png. Each removal: `refine` with its preset (the default refinement,
for residual_est), `eval --labels --refined` (every figure), `render --npy` (the truth)."""
import argparse
import concurrent.futures as futures
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "bench", "accuracy"))
import plyio  # noqa: E402
import scenes  # noqa: E402
import removals  # noqa: E402
import truth  # noqa: E402
import validity  # noqa: E402

HALVES = {
    "tune": [("gen", "d16", 1), ("gen", "clip128", 2), ("synth", "room", 1), ("synth", "counter", 2)],
    "report": [("gen", "d16", 21), ("gen", "clip128", 22), ("gen", "d32", 23), ("synth", "room", 8),
               ("synth", "counter", 9), ("synth", "garden", 10)],
}
N = 60000


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--half", choices=sorted(HALVES), default="report")
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "al-refine"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cache", default=os.environ.get("AL_ACCURACY_CACHE", os.path.join(REPO, "build", "accuracy-scenes")))
    ap.add_argument("--work", default="", help="keep the renders and reports here (default: a temporary folder)")
    ap.add_argument("--px-grid", action="store_true", help="also score residual_px over a grid of tolerances")
    ap.add_argument("--write", action="store_true", help="publish (report half only)")
    ap.add_argument("--from-results", action="store_true",
                    help="no runs: rewrite the docs and the plot from bench/results/residual_validity.json")
    args = ap.parse_args()
    if args.write and args.half != "report":
        ap.error("--write publishes the report half only")
    return args


def run(cmd, ok=(0,)):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode not in ok:
        raise RuntimeError(f"{' '.join(cmd)}: exit {proc.returncode}: {proc.stderr[-1500:]}")


def render(args, folder, removed_path, out):
    cmd = [args.bin, "render", "--scene", os.path.join(folder, "scene.ply"), "--cameras",
           os.path.join(folder, "cameras.json"), "--npy", "--out", out]
    run(cmd + (["--removed", removed_path] if removed_path else []))


def scene_removals(folder, scene, seed):
    """{kind: (removed mask, refine preset)} of one scene: its method masks and the leftovers."""
    labels = np.load(os.path.join(folder, "labels.npy"))
    with open(os.path.join(folder, "target.json")) as fh:
        target = labels == json.load(fh)["object_id"]
    v = plyio.read_vertices(os.path.join(folder, "scene.ply"))
    out = {k: (m, "fgs") for k, m in removals.leftovers(target, plyio.positions(v), plyio.features(v), seed).items()}
    for mask in scene.masks():
        out[mask] = (np.load(scene.mask_path(folder, mask)).astype(bool), removals.METHOD_PRESET[mask])
    return out


def eval_removal(args, folder, work, kind, preset, px_grid):
    """refine + eval + render of one removal (its mask already in work/kind/removed.npy)."""
    d = os.path.join(work, kind)
    removed = os.path.join(d, "removed.npy")
    run([args.bin, "refine", "--scene", os.path.join(folder, "scene.ply"), "--removed", removed, "--method", preset,
         "--removed-is", "removed", "--out", os.path.join(d, "refine"), "--quiet"], ok=(0, 3))  # 3: empty graph
    base = [args.bin, "eval", "--scene", os.path.join(folder, "scene.ply"), "--removed", removed, "--cameras",
            os.path.join(folder, "cameras.json"), "--labels", os.path.join(folder, "labels.npy"), "--no-images",
            "--quiet"]
    run(base + ["--refined", os.path.join(d, "refine", "refined.npy"), "--out", os.path.join(d, "eval")])
    render(args, folder, removed, os.path.join(d, "after"))
    grid = {}
    for colour, depth in px_grid:
        out = os.path.join(d, f"px_{colour}_{depth}")
        run(base + ["--feature-metrics", "off", "--px-colour-tol", str(colour), "--px-depth-tol", str(depth),
                    "--out", out])
        with open(os.path.join(out, "report.json")) as fh:
            grid[f"{colour}/{depth}"] = json.load(fh)["metrics"]["columns"][0]["residual_px"]["mean"]
        shutil.rmtree(out)
    return grid


def figures(report):
    """The residual-like figures of the removal's column, each read as "share of the object left"."""
    c = report["metrics"]["columns"][0]
    rec = {"residual_gt": c["residual_gt"]["mean"], "residual_px": c["residual_px"]["mean"],
           "residual_est": c.get("residual_est", {}).get("mean"),
           "acc8": 1 - c["depth"]["mean_acc_delta_depth"], "accf": 1 - c["depth_float"]["mean_acc_delta_depth"]}
    f = c.get("feature")
    if f:
        rec["residual_feat"] = f["mean_residual"] if f["n_residual_views"] else None
        before = f["mean_iou_before"]
        rec["iou_feat"] = min(1.0, max(0.0, 1 - f["mean_iou_drop"] / before)) if before > 0 else None
    rec["gt_f1"] = c["gt"]["f1"]
    return rec


def do_scene(args, item, work_root, px_grid):
    source, style, seed = item
    scene = scenes.Scene(source, style, seed, args.half, 0)
    gen = os.path.join(REPO, "..", "shared", "scenes", "gen_scenes.py")
    folder = scenes.ensure_scene(scene, args.cache, N, args.bin, gen)
    work = os.path.join(work_root, scene.name)
    os.makedirs(work, exist_ok=True)
    target_path = os.path.join(work, "target.npy")
    masks = scene_removals(folder, scene, seed)
    np.save(target_path, masks["perfect"][0])
    render(args, folder, None, os.path.join(work, "before"))
    render(args, folder, target_path, os.path.join(work, "ideal"))
    views = truth.views_of(os.path.join(work, "before"))
    records = []
    for kind, (mask, preset) in masks.items():
        os.makedirs(os.path.join(work, kind), exist_ok=True)
        np.save(os.path.join(work, kind, "removed.npy"), mask)
        grid = eval_removal(args, folder, work, kind, preset, px_grid)
        with open(os.path.join(work, kind, "eval", "report.json")) as fh:
            rec = figures(json.load(fh))
        rec.update({"scene": scene.name, "source": source, "style": style, "seed": seed, "kind": kind,
                    "kind_group": kind if kind in removals.LEFTOVER_KINDS else f"method {kind}", "preset": preset,
                    "truth": truth.scene_residual(os.path.join(work, "before"), os.path.join(work, kind, "after"),
                                                  os.path.join(work, "ideal"), views), "px_grid": grid})
        records.append(rec)
        print(f"{scene.name} {kind:10s} truth {validity._num(rec['truth'], 3)} gt {validity._num(rec['residual_gt'], 3)} "
              f"est {validity._num(rec['residual_est'], 3)} px {validity._num(rec['residual_px'], 3)} "
              f"1-acc8 {validity._num(rec['acc8'], 3)} feat {validity._num(rec.get('residual_feat'), 3)}", flush=True)
    return records


def px_grid_table(records, grid):
    print("\nresidual_px tolerance grid (colour/depth): MAE and Spearman against the truth")
    for colour, depth in grid:
        key = f"{colour}/{depth}"
        s = validity.figure_stats([dict(r, px=r["px_grid"][key]) for r in records], "px")
        print(f"  {key:10s} n {s['n']:3d}  MAE {validity._num(s['mae'], 3)}  rho {validity._num(s['rho'], 3)}")


def publish(records, stats, table):
    """docs/eval.md's table, README's short table and the scatter plot."""
    validity.update_doc(os.path.join(REPO, "docs", "eval.md"), table)
    validity.update_doc(os.path.join(REPO, "README.md"), validity.readme_table(stats), "residual trust")
    validity.plot(records, os.path.join(REPO, "docs", "eval_residual_validity.png"))


def main():
    args = parse_args()
    results = os.path.join(REPO, "bench", "results", "residual_validity.json")
    if args.from_results:
        with open(results) as fh:
            saved = json.load(fh)
        records = saved["records"]
        publish(records, saved["summary"], validity.markdown(records, saved["summary"], saved["by_kind"]))
        return
    grid = [(c, d) for c in (0.05, 0.1, 0.2) for d in (0.01, 0.02, 0.05)] if args.px_grid else []
    work_root = args.work or tempfile.mkdtemp(prefix="al-residual-")
    try:
        with futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            parts = list(pool.map(lambda item: do_scene(args, item, work_root, grid), HALVES[args.half]))
    finally:
        if not args.work:
            shutil.rmtree(work_root, ignore_errors=True)
    records = [r for part in parts for r in part]
    stats, kinds = validity.summary(records), validity.by_kind(records)
    table = validity.markdown(records, stats, kinds)
    print(f"\n{len(records)} removals, half {args.half}\n\n{table}")
    if grid:
        px_grid_table(records, grid)
    if args.write:
        meta = {"date_utc": datetime.datetime.utcnow().strftime("%Y-%m-%dT%H:%M:%SZ"), "half": args.half,
                "scenes": HALVES[args.half], "gaussians": N}
        with open(results, "w") as fh:
            json.dump({"meta": meta, "summary": stats, "by_kind": kinds, "records": records}, fh, indent=1)
        publish(records, stats, table)


if __name__ == "__main__":
    main()
