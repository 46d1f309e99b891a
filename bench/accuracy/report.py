"""Tables, targets and the dF1-per-scene plot of the accuracy bench (docs/accuracy.md)."""
import csv
import datetime
import gzip
import io
import json
import os
import shutil
import subprocess
import tempfile

import numpy as np

COLUMNS = ("scenes", "mean dF1", "raised", "lowered >0.01", "worst dF1", "misses recovered",
           "precision added", "added", "restored", "precision restored", "over-removed restored", "s")


def _mean(xs):
    xs = [x for x in xs if x is not None]
    return float(np.mean(xs)) if xs else None


def _ratio(num, den):
    return num / den if den else None


def stats(recs):
    """One table row: scene means (dF1, misses recovered, seconds) and pooled precisions."""
    ok = [r for r in recs if r["status"] != "error"]
    d = [r["dF1"] for r in ok]
    return {
        "scenes": len(ok), "errors": len(recs) - len(ok),
        "mean dF1": _mean(d), "worst dF1": min(d) if d else None,
        "raised": _ratio(sum(r["raised"] for r in ok), len(ok)),
        "lowered >0.01": sum(r["lowered_001"] for r in ok),
        "misses recovered": _mean([r["misses_recovered"] for r in ok]),
        "precision added": _ratio(sum(r["added_true"] for r in ok), sum(r["added"] for r in ok)),
        "added": _mean([r["added"] for r in ok]),
        "restored": _mean([r["restored"] for r in ok]),
        "precision restored": _ratio(sum(r["restored_true"] for r in ok), sum(r["restored"] for r in ok)),
        "over-removed restored": _mean([r["over_removed_restored"] for r in ok]),
        "s": _mean([r["seconds"] for r in ok]),
    }


def group(records, keys):
    out = {}
    for r in records:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def fmt(v, key):
    if v is None:
        return "-"
    if key in ("scenes", "lowered >0.01"):
        return str(int(v))
    if key in ("raised", "misses recovered", "precision added", "precision restored", "over-removed restored"):
        return f"{100 * v:.0f} %"
    if key in ("added", "restored"):
        return f"{v:.0f}"
    if key == "s":
        return f"{v:.2f}"
    return f"{v:+.4f}"


def run_label(r):
    return r["config"] if r["solver"] == "-" else f"{r['config']} {r['solver']}"


def table(recs, first="run"):
    lines = ["| " + first + " | " + " | ".join(COLUMNS) + " |", "|---" * (len(COLUMNS) + 1) + "|"]
    rows = group(recs, ("config", "solver"))
    order = sorted(rows, key=lambda k: (k[1] == "-", k[0] != "default", k[0] != "auto", k))
    for key in order:
        s = stats(rows[key])
        lines.append(f"| {run_label(rows[key][0])} | " + " | ".join(fmt(s[c], c) for c in COLUMNS) + " |")
    return "\n".join(lines)


def summary_text(records):
    out = []
    for (half, source, mask), recs in sorted(group(records, ("half", "source", "mask")).items()):
        out.append(f"\n### {half} half, {source}, {mask}\n\n{table(recs)}")
    return "\n".join(out)


def style_table(records):
    """Mean dF1 per gen style x mask for every run kind (the breakdown behind the source rows)."""
    gen = [r for r in records if r["source"] == "gen"]
    styles = sorted({r["style"] for r in gen}, key=lambda s: (s.startswith("clip"), len(s), s))
    lines = ["| mask | run | " + " | ".join(styles) + " |", "|---|---|" + "---|" * len(styles)]
    for (mask, cfg, solver), recs in sorted(group(gen, ("mask", "config", "solver")).items()):
        by = group(recs, ("style",))
        cells = [fmt(stats(by[(s,)])["mean dF1"], "d") if (s,) in by else "-" for s in styles]
        lines.append(f"| {mask} | {run_label(recs[0])} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _gzip_text(path):
    """A text file gzip-compressed with no timestamp, so the same records give the same bytes."""
    return io.TextIOWrapper(gzip.GzipFile(path, "wb", mtime=0), encoding="utf-8", newline="")


def _without_auto_grid(record):
    """The record without --auto's per-point grid (27 points per run would double the file)."""
    params = record.get("params")
    if not isinstance(params, dict) or "auto_candidates" not in params:
        return record
    return dict(record, params={k: v for k, v in params.items() if k != "auto_candidates"})


def write_raw(records, results_dir, meta):
    os.makedirs(results_dir, exist_ok=True)
    # gzip: 4,500 records with their prior statistics are several MB of JSON and 1.2 MB of CSV, 0.5
    # and 0.3 MB compressed (committed files stay under 1 MiB); `gzip -dc bench/results/accuracy.csv.gz`
    # or Python's gzip module reads them.
    published = [_without_auto_grid(r) for r in records]
    with _gzip_text(os.path.join(results_dir, "accuracy.json.gz")) as fh:
        json.dump({"meta": meta, "records": published}, fh, separators=(",", ":"))
    cols = ["id", "source", "style", "seed", "half", "mask", "method", "config", "solver", "n", "status",
            "f1_before", "f1_after", "dF1", "raised", "lowered_001", "removed", "target", "misses", "over_removed",
            "added", "added_true", "misses_recovered", "precision_added", "restored", "restored_true",
            "over_removed_restored", "precision_restored", "seconds"]
    with _gzip_text(os.path.join(results_dir, "accuracy.csv.gz")) as fh:
        w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(records)


def plot(records, png):
    """dF1 per scene, one panel per source x mask, one series per run kind (gnuplot)."""
    panels = sorted(group(records, ("source", "mask")).items())
    series = sorted({run_label(r) for r in records})
    tmp = tempfile.mkdtemp(prefix="al-acc-plot-")   # the data files are not kept beside the picture
    cmds = [f"set terminal pngcairo noenhanced size 1400,{360 * ((len(panels) + 3) // 4)} font ',9'",
            f"set output '{png}'",
            f"set multiplot layout {(len(panels) + 3) // 4},4", "set key bottom right font ',7'",
            "set grid ytics", "set xlabel 'scene (sorted by dF1 of each run)'", "set ylabel 'dF1'"]
    for (source, mask), recs in panels:
        dat = os.path.join(tmp, f"{source}_{mask}.dat")
        present = []
        with open(dat, "w") as fh:
            for s in series:
                ys = sorted(r["dF1"] for r in recs if run_label(r) == s and r["status"] != "error")
                if ys:
                    present.append(f"{s} ({len(ys)})")
                    fh.write(f"# {s}\n" + "".join(f"{i} {y:.6f}\n" for i, y in enumerate(ys)) + "\n\n")
        plots = ", ".join(f"'{dat}' index {i} with linespoints pt 7 ps 0.4 title '{s}'" for i, s in enumerate(present))
        cmds += [f"set title '{source} {mask}'", f"plot {plots}"]
    cmds.append("unset multiplot")
    try:
        subprocess.run(["gnuplot"], input="\n".join(cmds), text=True, check=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def write_all(records, repo, quick=False):
    results = os.path.join(repo, "bench", "results")
    meta = {"date_utc": datetime.datetime.utcnow().strftime("%Y-%m-%dT%H:%M:%SZ"), "quick": quick,
            "commit": subprocess.run(["git", "-C", repo, "rev-parse", "--short", "HEAD"], capture_output=True,
                                     text=True).stdout.strip()}
    name = "accuracy_quick" if quick else "accuracy"
    write_raw(records, results, meta) if not quick else None
    if quick:
        with open(os.path.join(results, name + ".json"), "w") as fh:
            json.dump({"meta": meta, "records": [_without_auto_grid(r) for r in records]}, fh, indent=1)
        return
    os.makedirs(os.path.join(repo, "docs", "accuracy"), exist_ok=True)
    plot([r for r in records if r["half"] == "report"], os.path.join(repo, "docs", "accuracy", "dF1_per_scene.png"))
    import accuracy_doc  # the prose lives beside the numbers it explains
    accuracy_doc.write(records, meta, os.path.join(repo, "docs", "accuracy.md"))
