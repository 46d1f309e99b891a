"""How well each residual-like figure of the evaluator follows the ground-truth residual: Spearman
rho, mean absolute error and worst error per generator and overall, the mean per kind of leftover,
the Markdown table of docs/eval.md and a scatter plot (gnuplot)."""
import os
import shutil
import subprocess
import tempfile

import numpy as np
from scipy.stats import spearmanr

# (key in a record, what the evaluator reports and how it is read as "share of the object left")
FIGURES = (
    ("acc8", "1 − acc_Δdepth (8-bit, the paper's)"),
    ("accf", "1 − acc_Δdepth (float)"),
    ("iou_feat", "1 − IoU_drop_feat / IoU_before_feat"),
    ("residual_feat", "residual_feat"),
    ("residual_px", "residual_px (masks only)"),
    ("residual_est", "residual_est (ideal = default refinement)"),
    ("residual_gt", "residual_gt (eval, with labels)"),
)


def figure_stats(records, key):
    pairs = [(r["truth"], r[key]) for r in records if r.get(key) is not None and r["truth"] is not None]
    if len(pairs) < 3:
        return {"n": len(pairs), "rho": None, "mae": None, "worst": None}
    t, f = np.array(pairs).T
    rho = spearmanr(t, f).correlation if np.ptp(f) > 0 and np.ptp(t) > 0 else float("nan")
    err = np.abs(f - t)
    return {"n": len(pairs), "rho": float(rho), "mae": float(err.mean()), "worst": float(err.max())}


def summary(records):
    groups = {"gen": [r for r in records if r["source"] == "gen"], "synth": [r for r in records if r["source"] == "synth"],
              "all": records}
    return {g: {key: figure_stats(recs, key) for key, _ in FIGURES} for g, recs in groups.items()}


def by_kind(records):
    kinds = sorted({r["kind_group"] for r in records})
    out = {}
    for k in kinds:
        recs = [r for r in records if r["kind_group"] == k and r["truth"] is not None]
        out[k] = {"n": len(recs), "truth": float(np.mean([r["truth"] for r in recs]))}
        for key, _ in FIGURES:
            vals = [r[key] for r in recs if r.get(key) is not None]
            out[k][key] = float(np.mean(vals)) if vals else None
    return out


def _num(v, digits=2):
    return "–" if v is None or (isinstance(v, float) and np.isnan(v)) else f"{v:.{digits}f}"


def markdown(records, stats, kinds):
    lines = ["| figure (read as share left) | ρ gen | ρ synth | ρ all | MAE gen | MAE synth | MAE all | "
             "worst gen | worst synth | worst all |", "|---|" + "---:|" * 9]
    for key, name in FIGURES:
        row = [name]
        for metric in ("rho", "mae", "worst"):
            row += [_num(stats[g][key][metric]) for g in ("gen", "synth", "all")]
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", "Mean per kind of leftover (truth = residual_gt by the definition, computed in numpy):", "",
              "| kind | removals | truth | " + " | ".join(k for k, _ in FIGURES) + " |",
              "|---|---:|---:|" + "---:|" * len(FIGURES)]
    for kind, row in kinds.items():
        lines.append(f"| {kind} | {row['n']} | {_num(row['truth'])} | " +
                     " | ".join(_num(row[k]) for k, _ in FIGURES) + " |")
    return "\n".join(lines) + "\n"


def plot(records, png):
    """One panel per figure: the figure against the truth, one point series per generator, y = x."""
    tmp = tempfile.mkdtemp(prefix="al-residual-plot-")
    cmds = ["set terminal pngcairo noenhanced size 1400,720 font ',9'", f"set output '{png}'",
            "set multiplot layout 2,4", "set xrange [-0.05:1.05]", "set yrange [-0.05:1.05]", "set size ratio -1",
            "set grid", "set key top left font ',8'", "set xlabel 'residual_gt (definition)'"]
    for key, name in FIGURES:
        dat = os.path.join(tmp, f"{key}.dat")
        with open(dat, "w") as fh:
            for source in ("gen", "synth"):
                fh.write(f"# {source}\n")
                for r in records:
                    if r["source"] == source and r.get(key) is not None and r["truth"] is not None:
                        fh.write(f"{r['truth']:.6f} {r[key]:.6f}\n")
                fh.write("\n\n")
        title = name.replace("'", "’")   # gnuplot strings are single-quoted here
        cmds += [f"set title '{title}'", "set ylabel 'figure'",
                 f"plot x notitle lc rgb '#999999', '{dat}' index 0 pt 7 ps 0.6 title 'gen', "
                 f"'{dat}' index 1 pt 5 ps 0.6 title 'synth'"]
    cmds.append("unset multiplot")
    try:
        subprocess.run(["gnuplot"], input="\n".join(cmds), text=True, check=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


# What each figure is for (README's short table); the measured numbers are put beside them.
USE = {"residual_gt": "synthetic scenes (labels): the truth",
       "residual_est": "real scenes (headline without labels); reads low where refinement misses leftovers",
       "residual_px": "object masks only; reads high where a look-alike surface is just behind",
       "residual_feat": "feature field; blind to leftovers whose features are off",
       "iou_feat": "feature field; same blind spot", "acc8": "parity with the paper only", "accf": "parity only"}


def readme_table(stats):
    lines = ["| figure | for | Spearman ρ | mean error | worst error |", "|---|---|---:|---:|---:|"]
    for key, name in FIGURES[::-1]:
        s = stats["all"][key]
        lines.append(f"| {name} | {USE[key]} | {_num(s['rho'])} | {_num(s['mae'])} | {_num(s['worst'])} |")
    return "\n".join(lines) + "\n"


def update_doc(path, table, marker="residual validity"):
    begin, end = f"<!-- {marker}: bench/residual/run.py -->", f"<!-- /{marker} -->"
    with open(path) as fh:
        text = fh.read()
    if begin not in text or end not in text:
        raise SystemExit(f"{path}: no '{begin}' ... '{end}' block to update")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(path, "w") as fh:
        fh.write(head + begin + "\n" + table + end + tail)
