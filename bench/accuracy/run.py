#!/usr/bin/python3
"""Accuracy benchmark of refinement (issue 13): does al-refine recover what a removal method left
behind, on scenes it was never tuned on? See docs/accuracy.md for what it measures and the results.

usage: bench/accuracy/run.py [--quick] [--today-bin OLD_AL_REFINE] [--halves report|tune|check|check2|tune,report] [--sources gen,synth]
                             [--styles d16,...] [--masks gg_like,...] [--solvers bk,cp] [--configs default,auto]
                             [--config NAME=FLAGS ...] [--baselines B1,B2,B3|none] [--n 60000]
                             [--max-seeds N] [--seeds 28-40] [--bin build/al-refine] [--cache DIR] [--work DIR] [--jobs N]
                             [--no-write] [--summary] [--write-only]

Runs al-refine (the issue's command `--method M --k 10 --delta 0.8`, with the default flags and with
--auto, solvers bk and cp) and the numpy baselines B1-B3 on every scene and removal mask; records
per run dF1, raised, misses recovered, precision of the added, restored count and precision,
seconds. Records are appended to WORK/records.jsonl as they finish (a rerun skips what is done);
at the end bench/results/accuracy.json.gz + accuracy.csv.gz and docs/accuracy.md (report.py) are rewritten,
unless --no-write (exploration on the tuning half). --summary prints the table to stdout.
"""
import argparse
import hashlib
import json
import os
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report  # noqa: E402
import runner  # noqa: E402
import scenes  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILTIN_CONFIGS = {"default": [], "auto": ["--auto"]}
# B3's one parameter, chosen on the tuning half (docs/accuracy.md); B1 and B2 use the issue's values.
BASELINE_PARAMS = {"B1": {}, "B2": {}, "B3": {"lam": 1.0}}


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--halves", default="report",
                    help="report (published), tune (defaults are chosen on it), check / check2 (held-out seeds "
                         "41-80 / 81-120 for a rule chosen with the reporting half in view; need --no-write); "
                         "comma-separated")
    ap.add_argument("--sources", default="gen,synth")
    ap.add_argument("--styles", default="")
    ap.add_argument("--masks", default="", help="only these removal masks (e.g. gg_like,gg); default: all")
    ap.add_argument("--solvers", default="bk,cp")
    ap.add_argument("--configs", default="default,auto")
    ap.add_argument("--config", action="append", default=[], help="NAME=FLAGS (extra al-refine flags)")
    ap.add_argument("--baselines", default="B1,B2,B3")
    ap.add_argument("--n", type=int, default=60000)
    ap.add_argument("--max-seeds", type=int, default=0, help="at most this many seeds per style and half")
    ap.add_argument("--seeds", default="", help="only these seeds, e.g. 28-40 or 8,9,28-30 (with the other filters)")
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "al-refine"))
    ap.add_argument("--today-bin", default=os.environ.get("AL_ACCURACY_TODAY_BIN", ""),
                    help="an al-refine built before issue 13 (e.g. commit 0a8b341): adds the config "
                         "'today' = its default flags, the comparison of the synth targets")
    ap.add_argument("--cache", default=os.environ.get("AL_ACCURACY_CACHE", os.path.join(REPO, "build", "accuracy-scenes")))
    ap.add_argument("--work", default="")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--summary", action="store_true")
    ap.add_argument("--write-only", action="store_true",
                    help="run nothing: write the reports from every record in the work folder (e.g. "
                         "records of several partial runs concatenated)")
    args = ap.parse_args()
    known = sorted({half for halves in scenes.HALVES.values() for half in halves})
    unknown = [h for h in args.halves.split(",") if h not in known]
    if unknown:
        ap.error(f"--halves {','.join(unknown)}: not a half (known: {', '.join(known)})")
    held_out = [h for h in args.halves.split(",") if h.startswith("check")]
    if held_out and not args.no_write:
        ap.error(f"--halves {held_out[0]} needs --no-write: the held-out scenes are not published "
                 "(bench/accuracy/scenes.py)")
    return args


def plan(args):
    """(scene, mask, method, runner-kind, name, solver, flags-or-params) for every run asked for."""
    configs = {}
    for name in filter(None, args.configs.split(",")):
        configs[name] = BUILTIN_CONFIGS[name]
    if args.today_bin:
        # A mask is the removed set (that binary read gg's bool masks as the remaining set).
        configs["today"] = ["--removed-is", "removed"]
    for item in args.config:
        name, _, flags = item.partition("=")
        configs[name] = flags.split()
    # "B3" runs with BASELINE_PARAMS; "B3:lam=0.5" with that value (tuning), recorded under that name.
    bls = []
    for item in ([] if args.baselines == "none" else [b for b in args.baselines.split(",") if b]):
        name, _, kv = item.partition(":")
        params = dict(BASELINE_PARAMS[name])
        if kv:
            key, _, val = kv.partition("=")
            params[key] = float(val)
        bls.append((item, name, params))
    styles = [s for s in args.styles.split(",") if s]
    masks = [m for m in args.masks.split(",") if m]
    todo = []
    for sc in scenes.scene_list(args.halves.split(","), args.quick, args.sources.split(","), styles,
                                 args.max_seeds, parse_seeds(args.seeds)):
        for mask, method in sc.masks().items():
            if masks and mask not in masks:
                continue
            for cname, flags in configs.items():
                for solver in args.solvers.split(","):
                    todo.append((sc, mask, method, "al", cname, solver, flags))
            for label, name, params in bls:
                todo.append((sc, mask, method, "baseline", label, "-", params))
    return todo


def parse_seeds(text):
    """'28-40,3' -> {3, 28, ..., 40}; '' -> None (every seed)."""
    seeds = set()
    for part in filter(None, text.split(",")):
        lo, _, hi = part.partition("-")
        seeds.update(range(int(lo), int(hi or lo) + 1))
    return seeds or None


def binary_id(path):
    """A run is reused only with the same binary: its content hash is part of the run id."""
    if not path or not os.path.exists(path):
        return "-"
    with open(path, "rb") as fh:
        return hashlib.sha1(fh.read()).hexdigest()[:12]


def run_id(item, n, bins):
    sc, mask, _, kind, name, solver, flags = item
    extra = " ".join(flags) if kind == "al" else json.dumps(flags, sort_keys=True)
    binary = "" if kind != "al" else f"|bin={bins['today' if name.startswith('today') else 'al']}"
    return f"{sc.name}|n={n}|{mask}|{name}|{solver}|{extra}{binary}"


def main():
    args = parse_args()
    work = args.work or os.path.join(args.cache, "runs")
    os.makedirs(work, exist_ok=True)
    log = os.path.join(work, "records.jsonl")
    done = {}
    if os.path.exists(log):
        with open(log) as fh:
            for line in fh:
                try:
                    r = json.loads(line)
                    if r.get("status") != "error":   # failed runs are tried again
                        done[r["id"]] = r
                except (json.JSONDecodeError, KeyError):
                    pass   # a line cut off by a kill: that run is redone
    if args.write_only:
        records = [r for r in done.values() if "half" in r]
        report.write_all(records, REPO, quick=args.quick)
        print(f"accuracy: wrote the reports from {len(records)} records", file=sys.stderr)
        return 0
    todo = plan(args)
    gen_script = os.path.join(REPO, "..", "shared", "scenes", "gen_scenes.py")
    data_by_scene = {}
    bins = {"al": binary_id(args.bin), "today": binary_id(args.today_bin)}
    pending = [it for it in todo if run_id(it, args.n, bins) not in done]
    print(f"accuracy: {len(todo)} runs, {len(todo) - len(pending)} done earlier", file=sys.stderr)

    def one(item):
        sc, mask, method, kind, name, solver, flags = item
        data = data_by_scene[sc.name]
        path = sc.mask_path(data.folder, mask)
        if kind == "al":
            binary = args.today_bin if name.startswith("today") else args.bin  # today, today_*: the old binary
            rec = runner.run_al_refine(binary, data, path, method, solver, flags)
        else:
            rec = runner.run_baseline(name.partition(":")[0], data, path, flags)
        rec.update({"id": run_id(item, args.n, bins), "source": sc.source, "style": sc.style, "seed": sc.seed, "half": sc.half,
                    "mask": mask, "method": method, "config": name, "solver": solver, "n": args.n})
        return rec

    # Scenes one after another (generation and the baselines' graph are per scene); runs of a
    # scene in parallel when --jobs > 1.
    by_scene = {}
    for it in pending:
        by_scene.setdefault(it[0].name, []).append(it)
    with open(log, "a") as fh, ThreadPoolExecutor(max(1, args.jobs)) as pool:
        for k, (name, items) in enumerate(by_scene.items()):
            # Generated and loaded here, before the runs of the scene go to the pool.
            sc = items[0][0]
            data_by_scene[name] = runner.SceneData(scenes.ensure_scene(sc, args.cache, args.n, args.bin, gen_script))
            if any(it[3] == "baseline" for it in items):
                data_by_scene[name].graph()
            for rec in pool.map(one, items):
                fh.write(json.dumps(rec) + "\n")
                fh.flush()
                done[rec["id"]] = rec
            data_by_scene.pop(name, None)
            print(f"accuracy: scene {k + 1}/{len(by_scene)} {name}", file=sys.stderr)
    records = [done[run_id(it, args.n, bins)] for it in todo]
    errors = [r for r in records if r["status"] == "error"]
    for r in errors[:5]:
        print(f"accuracy: error in {r['id']}: {r.get('stderr', '')}", file=sys.stderr)
    if args.summary or args.no_write:
        print(report.summary_text(records))
    if not args.no_write:
        report.write_all(records, REPO, quick=args.quick)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
