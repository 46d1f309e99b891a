"""One accuracy run: al-refine (a subprocess, as a user runs it) or a numpy baseline, on one
scene and one removal mask, turned into a metrics record."""
import json
import os
import shutil
import subprocess
import tempfile
import time

import numpy as np

import baselines
import metrics
import plyio


class SceneData:
    """Labels and target of a scene folder; the baselines' graph is built on first use."""

    def __init__(self, folder):
        self.folder = folder
        labels = np.load(os.path.join(folder, "labels.npy"))
        with open(os.path.join(folder, "target.json")) as fh:
            self.target = labels == json.load(fh)["object_id"]
        self._graph = None

    def graph(self):
        if self._graph is None:
            v = plyio.read_vertices(os.path.join(self.folder, "scene.ply"))
            self._graph = baselines.SceneGraph(plyio.positions(v), plyio.features(v))
        return self._graph


def run_al_refine(al_bin, data, mask_path, method, solver, flags, timeout=1800):
    """al-refine with the issue's command (--k 10 --delta 0.8) plus `flags`; returns a record."""
    out = tempfile.mkdtemp(prefix="al-acc-")
    try:
        cmd = [al_bin, "refine", "--scene", os.path.join(data.folder, "scene.ply"), "--removed", mask_path,
               "--method", method, "--k", "10", "--delta", "0.8", "--solver", solver,
               "--labels", os.path.join(data.folder, "labels.npy"), "--out", out, "--quiet"] + list(flags)
        # One thread per run: the bench runs --jobs runs side by side on a shared machine, where
        # OpenMP barriers of a 2-thread solve under contention cost more than they save.
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("AL_ACCURACY_THREADS", "1"))
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
        seconds = time.perf_counter() - t0
        removed = np.load(mask_path)
        if proc.returncode not in (0, 3):   # 3 = empty graph: the output equals the input
            return {"status": "error", "exit_code": proc.returncode, "stderr": proc.stderr[-2000:],
                    "command": " ".join(cmd), "seconds": seconds}
        refined = np.load(os.path.join(out, "refined.npy"))
        rec = metrics.record(removed, refined, data.target)
        with open(os.path.join(out, "report.json")) as fh:
            report = json.load(fh)
        rec.update({"status": report.get("status", "ok"), "seconds": seconds,
                    "warnings": report.get("warnings", []), "params": _params_of(report)})
        return rec
    finally:
        shutil.rmtree(out, ignore_errors=True)


def _params_of(report):
    p = report.get("params", {})
    keep = ("k", "delta", "lambda", "restore", "feature_source", "hops")
    out = {k: p[k] for k in keep if k in p}
    g = report.get("graph", {})
    if "lambda" in g:
        out["lambda_applied"] = g["lambda"]  # params.lambda may say "auto"
    if "prior" in g:
        out["prior"] = g["prior"]
        out["rounds"] = g.get("rounds")
        out["candidates"] = g.get("nodes")
    if "auto" in report:
        out["auto_chosen"] = {k: report["auto"]["chosen"][k] for k in ("k", "delta", "lambda")}
        # Every grid point as [k, delta, lambda, score, gt_f1, added, restored, neighbours]: enough to
        # study another criterion or sub-grid from the records (work folder only; write_raw drops it).
        out["auto_candidates"] = [[c["k"], c["delta"], c["lambda"], c["score"], c.get("gt_f1"), c["added"],
                                   c["restored"], c.get("neighbours", [])] for c in report["auto"]["candidates"]]
    return out


def run_baseline(name, data, mask_path, params):
    removed = np.load(mask_path)
    graph = data.graph()       # reading the PLY and the scene kNN are not timed (shared by B1-B3)
    t0 = time.perf_counter()
    refined = baselines.BASELINES[name](graph, removed, **params)
    seconds = time.perf_counter() - t0
    rec = metrics.record(removed, refined, data.target)
    rec.update({"status": "ok", "seconds": seconds, "params": params})
    return rec
