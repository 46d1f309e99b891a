#!/usr/bin/env python3
"""What the residuals cost (issue 32: an eval with residual_est at most 1.3x today's eval of the
same views): `al-refine eval` of this build against the binary of the commit before the residuals
(--base-bin), interleaved in one run (old and new alternate, the order flipping each repetition),
on the demo's scene (synth room, 200,000 Gaussians, 12 views 320x240) with the FGS removal and
the GC removal as the refinement (--refined: residual_est's ideal shares that column's render).

  /usr/bin/python3 bench/residual/speed.py --base-bin OLD/al-refine [--bin build/al-refine]
                                           [--reps 5] [--gaussians 200000] [--write]

Cases: "masks" (--object-masks: residual_est and residual_px, no labels — the real-scene case) and
"labels" (--labels: residual_gt too, one more incremental render per view). Wall time of the whole
command and eval's own timings_s; medians and new/old ratios. --write: bench/results/residual_speed.json."""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "al-refine"))
    ap.add_argument("--base-bin", required=True, help="al-refine built at the commit before the residuals")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--gaussians", type=int, default=200000)
    ap.add_argument("--write", action="store_true")
    return ap.parse_args()


def load():
    with open("/proc/loadavg") as fh:
        return float(fh.read().split()[0])


def eval_once(binary, scene, case, out):
    cmd = [binary, "eval", "--scene", f"{scene}/scene.ply", "--removed", f"{scene}/removed_fgs.npy", "--refined",
           f"{scene}/removed_gc.npy", "--cameras", f"{scene}/cameras.json", "--quiet", "--out", out]
    cmd += ["--object-masks", f"{scene}/masks"] if case == "masks" else ["--labels", f"{scene}/labels.npy"]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    with open(os.path.join(out, "report.json")) as fh:
        timings = json.load(fh)["timings_s"]
    shutil.rmtree(out)
    return {"wall": wall, "render": timings.get("render"), "metrics": timings.get("metrics"), "io": timings.get("io")}


def main():
    args = parse_args()
    work = tempfile.mkdtemp(prefix="al-residual-speed-")
    try:
        scene = os.path.join(work, "scene")
        subprocess.run([args.bin, "synth", "--preset", "room", "--gaussians", str(args.gaussians), "--seed", "1",
                        "--views", "12", "--quiet", "--out", scene], check=True, stdout=subprocess.DEVNULL)
        runs = {(case, who): [] for case in ("masks", "labels") for who in ("old", "new")}
        loads = [load()]
        for rep in range(args.reps):
            for case in ("masks", "labels"):
                order = ("old", "new") if rep % 2 == 0 else ("new", "old")
                for who in order:
                    binary = args.base_bin if who == "old" else args.bin
                    runs[(case, who)].append(eval_once(binary, scene, case, os.path.join(work, "out")))
            loads.append(load())
    finally:
        shutil.rmtree(work, ignore_errors=True)
    result = {"gaussians": args.gaussians, "views": 12, "reps": args.reps, "load_average": loads, "cases": {}}
    for case in ("masks", "labels"):
        med = {who: {k: statistics.median(r[k] for r in runs[(case, who)]) for k in ("wall", "render", "metrics", "io")}
               for who in ("old", "new")}
        result["cases"][case] = {"median": med, "ratio_wall": med["new"]["wall"] / med["old"]["wall"],
                                 "ratio_render": med["new"]["render"] / med["old"]["render"],
                                 "runs": {who: runs[(case, who)] for who in ("old", "new")}}
        print(f"{case:6s} wall old {med['old']['wall']:.2f} s new {med['new']['wall']:.2f} s  ratio "
              f"{result['cases'][case]['ratio_wall']:.3f} | render old {med['old']['render']:.2f} new "
              f"{med['new']['render']:.2f} ratio {result['cases'][case]['ratio_render']:.3f} | metrics old "
              f"{med['old']['metrics']:.2f} new {med['new']['metrics']:.2f}")
    print(f"load average during the run: {min(loads):.1f}-{max(loads):.1f}")
    if args.write:
        with open(os.path.join(REPO, "bench", "results", "residual_speed.json"), "w") as fh:
            json.dump(result, fh, indent=1)


if __name__ == "__main__":
    main()
