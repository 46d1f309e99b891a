#!/usr/bin/env python3
"""An independent, literal re-implementation of the released Remove360 evaluator's per-image
formulas as ../shared/spec/METRICS.md describes them (semantic §2, acc_Δdepth 8-bit §4), in numpy,
following that text literally and sharing no code with al-refine. Images are read with Pillow's convert("L") as the
released code does, and the depth difference uses numpy's own uint8 arithmetic, so the wraparound
of `-depth1` happens here exactly as it does there.

Used by tests/cli/metrics_oracle.sh: `compare` generates scenes in the released folder layout
(depth holes before / after / both, missing files, absent detector folders, a 16-bit depth PNG,
object masks of another size), runs `al-refine metrics --dir` and compares every per-image figure
to 1e-6.

  released_reference.py compare AL_REFINE_BINARY WORK_DIR [--seed S]
  released_reference.py score SCENE_DIR [--depth-holes before|both]   (prints JSON)
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np
from PIL import Image

# ---------------------------------------------------------------- common (METRICS.md §1)


def load_l(path):
    """8-bit luma as PIL convert("L") (16-bit grey is clipped to 255)."""
    return np.array(Image.open(path).convert("L"))


def resize_nearest(img, out_h, out_w, rule):
    """Nearest-neighbour resize with the 'floor' (torch nearest) or 'exact' (nearest-exact) rule."""
    in_h, in_w = img.shape

    def src(n_in, n_out):
        d = np.arange(n_out, dtype=np.float64)
        if rule == "floor":
            return np.floor(d * n_in / n_out).astype(np.int64)
        return np.minimum(np.floor((d + 0.5) * n_in / n_out).astype(np.int64), n_in - 1)

    return img[src(in_h, out_h)][:, src(in_w, out_w)]


def iou(a, b):
    union = np.logical_or(a, b).sum()
    return float(np.logical_and(a, b).sum()) / float(union) if union > 0 else 0.0


def acc_in(obj, pred):
    n = obj.sum()
    return float(np.logical_and(obj, pred).sum()) / float(n) if n > 0 else 0.0


# ---------------------------------------------------------------- semantic (METRICS.md §2)


def semantic_scene(scene):
    records = []
    mask_dir = os.path.join(scene, "masks")
    for name in sorted(f for f in os.listdir(mask_dir) if f.endswith(".png")):
        stem = name[:-4]
        obj = load_l(os.path.join(mask_dir, name))
        dets = []
        for side in ("before", "after"):
            p = os.path.join(scene, "gsam2", side, "mask", stem + ".png")
            dets.append(load_l(p) if os.path.isfile(p) else None)  # missing detection: empty mask
        h = max([obj.shape[0]] + [d.shape[0] for d in dets if d is not None])
        w = max([obj.shape[1]] + [d.shape[1] for d in dets if d is not None])
        o = resize_nearest(obj, h, w, "floor") > 0
        pre, post = [resize_nearest(d, h, w, "floor") > 0 if d is not None else np.zeros((h, w), bool)
                     for d in dets]
        ib, ia = iou(o, pre), iou(o, post)
        n = o.sum()
        acc_after = float(np.logical_and(o, ~post).sum()) / float(n) if n > 0 else 0.0
        ab = acc_in(o, pre)
        records.append({"image_name": name, "iou_before": ib, "iou_after": ia, "iou_drop": ib - ia,
                        "acc_before": ab, "acc_after": acc_after, "acc_diff": acc_after - ab})
    return records


# ---------------------------------------------------------------- acc_Δdepth (METRICS.md §4)


def gray_r_lut():
    lut = np.array([int(255.0 * (1.0 - i * (1.0 / 255.0))) for i in range(256)], dtype=np.uint8)
    odd = [i for i in range(256) if lut[i] != 255 - i]
    assert odd == [43, 59, 75, 91, 107, 123, 133, 140, 141, 149, 156, 157, 165, 172, 173, 181, 188, 189,
                   197, 198, 204, 205, 206, 213, 214, 220, 221, 222, 229, 230, 236, 237, 238, 245, 246,
                   252, 253, 254], odd
    assert all(lut[i] == 254 - i for i in odd)
    return lut


def ght(n, nu=1000.0, tau=300.0, kappa=0.0, omega=0.0):
    """Generalized Histogram Thresholding (Barron 2020), cumulative-sum form; bin centres 0..255."""
    x = np.arange(256, dtype=np.float64)
    n = n.astype(np.float64)
    csum = lambda z: np.cumsum(z)[:-1]
    dsum = lambda z: np.cumsum(z[::-1])[-2::-1]
    clip = lambda z: np.maximum(1e-30, z)
    w0, w1 = clip(csum(n)), clip(dsum(n))
    p0, p1 = w0 / (w0 + w1), w1 / (w0 + w1)
    mu0, mu1 = csum(n * x) / w0, dsum(n * x) / w1
    d0 = csum(n * x * x) - w0 * (mu0 * mu0)
    d1 = dsum(n * x * x) - w1 * (mu1 * mu1)
    v0 = clip(((p0 * nu) * tau ** 2 + d0) / (p0 * nu + w0))
    v1 = clip(((p1 * nu) * tau ** 2 + d1) / (p1 * nu + w1))
    f0 = -d0 / v0 - w0 * np.log(v0) + 2 * (w0 + kappa * omega) * np.log(w0)
    f1 = -d1 / v1 - w1 * np.log(v1) + 2 * (w1 + kappa * (1 - omega)) * np.log(w1)
    f = f0 + f1
    return float(np.mean(x[:-1][f == np.max(f)]))


def depth_pair(d1, d2, holes):
    """Step 1: |Δ| in float32. The released test `diff == -depth1` negates a uint8 array (wraps)."""
    diff = d2.astype(np.float32) - d1.astype(np.float32)
    neg = np.negative(d1) if holes == "before" else -d1.astype(np.float32)  # "both": the patched line
    diff[(diff == d2) | (diff == neg)] = 0
    a = np.abs(diff)
    # Step 2: min-max, colormap index, inverted grey bytes.
    lo, hi = a.min(), a.max()
    if hi == lo:
        img = np.full(a.shape, 255, np.uint8)
    else:
        r = (a - lo) / (hi - lo)
        idx = np.minimum(np.trunc(np.float32(256) * r).astype(np.int64), 255)
        img = gray_r_lut()[idx]
    # Steps 3-5: histogram, GHT, strict byte < t, constant mask = no change.
    t = ght(np.bincount(img.ravel(), minlength=256))
    changed = img < t
    if changed.all() or not changed.any():
        changed = np.zeros_like(changed)
    return changed, t


def depth_scene(scene, holes):
    records = []
    before_dir, after_dir = os.path.join(scene, "depth", "before"), os.path.join(scene, "depth", "after")
    for name in sorted(f for f in os.listdir(before_dir) if f.endswith(".png")):
        stem = name[:-4]
        if not os.path.isfile(os.path.join(after_dir, name)):
            continue
        changed, t = depth_pair(load_l(os.path.join(before_dir, name)), load_l(os.path.join(after_dir, name)), holes)
        mp = os.path.join(scene, "masks", name)
        obj = load_l(mp) > 0 if os.path.isfile(mp) else np.zeros(changed.shape, bool)
        if obj.shape != changed.shape:
            changed = resize_nearest(changed.astype(np.uint8), obj.shape[0], obj.shape[1], "exact") > 0
        records.append({"image": stem, "acc_delta_depth": acc_in(obj, changed), "iou": iou(obj, changed),
                        "ght_threshold": t})
    return records


# ---------------------------------------------------------------- generated scenes


def save(path, arr):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    Image.fromarray(arr).save(path)


def blob(rng, h, w, frac):
    """A random filled ellipse covering roughly `frac` of the image."""
    yy, xx = np.mgrid[0:h, 0:w]
    cy, cx = rng.uniform(0.2, 0.8) * h, rng.uniform(0.2, 0.8) * w
    ry, rx = max(1.0, np.sqrt(frac) * h * rng.uniform(0.5, 1.0)), max(1.0, np.sqrt(frac) * w * rng.uniform(0.5, 1.0))
    return ((yy - cy) / ry) ** 2 + ((xx - cx) / rx) ** 2 <= 1.0


def depth_image_pair(rng, h, w, obj, kind):
    """Before/after 8-bit depths: a ramp background, the object closer before; `kind` chooses holes."""
    yy, xx = np.mgrid[0:h, 0:w]
    bg = (60 + 120 * yy / h + 40 * xx / w + rng.integers(0, 3, (h, w))).astype(np.int64)
    d1 = bg.copy()
    d1[obj] = np.maximum(bg[obj] - rng.integers(20, 90), 1)
    d2 = bg.copy()
    other = blob(rng, h, w, 0.05) & ~obj  # an unrelated change elsewhere
    d2[other] = np.clip(bg[other] + rng.integers(-50, 50), 1, 255)
    if kind in ("after", "both"):  # removed with nothing behind: no depth after
        d2[obj & (rng.random((h, w)) < 0.7)] = 0
        d2[blob(rng, h, w, 0.03)] = 0
    if kind in ("before", "both"):  # no depth before (sky, outside the reconstruction)
        d1[blob(rng, h, w, 0.04)] = 0
        d1[rng.random((h, w)) < 0.02] = 0
    if kind == "both":
        both = blob(rng, h, w, 0.02)
        d1[both], d2[both] = 0, 0
    return d1.astype(np.uint8), d2.astype(np.uint8)


def make_scene(root, rng, with_detectors):
    kinds = ["none", "before", "after", "both"]
    for i in range(16):
        h, w = int(rng.integers(18, 40)), int(rng.integers(24, 56))
        stem = "img_%02d" % i
        obj = blob(rng, h, w, rng.choice([0.002, 0.05, 0.15]))
        d1, d2 = depth_image_pair(rng, h, w, obj, kinds[i % 4])
        save(os.path.join(root, "depth", "before", stem + ".png"), d1)
        if i == 5:  # a 16-bit depth PNG: convert("L") clips it
            Image.fromarray((d2.astype(np.uint16) * 3)).save(os.path.join(root, "depth", "after", stem + ".png"))
        else:
            save(os.path.join(root, "depth", "after", stem + ".png"), d2)
        if i == 7:
            continue  # no object mask: the depth metric counts it with acc 0
        m = (obj * 255).astype(np.uint8)
        if i == 9:  # object mask at another size: the change mask is resized with the exact rule
            m = resize_nearest(m, h + 7, w - 5, "floor")
        save(os.path.join(root, "masks", stem + ".png"), m)
        if with_detectors:
            if i != 3:
                save(os.path.join(root, "gsam2", "before", "mask", stem + ".png"),
                     ((obj | (rng.random((h, w)) < 0.05)) * 255).astype(np.uint8))
            if i != 4:
                after = blob(rng, h + 4, w, 0.03) if i % 3 else np.zeros((h + 4, w), bool)
                save(os.path.join(root, "gsam2", "after", "mask", stem + ".png"), (after * 200).astype(np.uint8))


def run_metrics(binary, scene, out, holes):
    cmd = [binary, "metrics", "--dir", scene, "--out", out, "--depth-holes", holes]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    load = lambda name: json.load(open(os.path.join(out, name)))
    return load("semantic.json"), load("depth.json"), load("report.json")


def compare_records(label, ours, ref, key, fields, tol=1e-6):
    if [r[key] for r in ours] != [r[key] for r in ref]:
        raise SystemExit("FAIL %s: images %s vs reference %s" % (label, [r[key] for r in ours], [r[key] for r in ref]))
    worst = 0.0
    for a, b in zip(ours, ref):
        for f in fields:
            d = abs(a[f] - b[f])
            worst = max(worst, d)
            if d > tol:
                raise SystemExit("FAIL %s %s %s: al-refine %r, reference %r" % (label, a[key], f, a[f], b[f]))
    return len(ours) * len(fields), worst


def compare(binary, work, seed):
    rng = np.random.default_rng(seed)
    figures, worst = 0, 0.0
    for with_detectors in (True, False):
        scene = os.path.join(work, "scene_det" if with_detectors else "scene_nodet")
        make_scene(scene, rng, with_detectors)
        for holes in ("before", "both"):
            sem, dep, rep = run_metrics(binary, scene, os.path.join(scene, "out_" + holes), holes)
            if rep["metrics"]["depth"]["depth_holes"] != holes:
                raise SystemExit("FAIL: report.json names depth_holes %r" % rep["metrics"]["depth"]["depth_holes"])
            n, w = compare_records(holes + " semantic", sem, semantic_scene(scene), "image_name",
                                   ["iou_before", "iou_after", "iou_drop", "acc_before", "acc_after", "acc_diff"])
            figures, worst = figures + n, max(worst, w)
            n, w = compare_records(holes + " depth", dep, depth_scene(scene, holes), "image",
                                   ["acc_delta_depth", "iou", "ght_threshold"])
            figures, worst = figures + n, max(worst, w)
        if not with_detectors and not any("detector" in x for x in rep.get("warnings", [])):
            raise SystemExit("FAIL: no warning about the absent detector folders")
    # The two hole rules must differ on these scenes, or the comparison proves nothing.
    d_before = json.load(open(os.path.join(work, "scene_det", "out_before", "depth.json")))
    d_both = json.load(open(os.path.join(work, "scene_det", "out_both", "depth.json")))
    if all(abs(a["acc_delta_depth"] - b["acc_delta_depth"]) < 1e-9 for a, b in zip(d_before, d_both)):
        raise SystemExit("FAIL: the depth-hole rules give the same figures: the cases do not test them")
    print("released reference: %d per-image figures agree (max |difference| %.3g)" % (figures, worst))


def main():
    p = argparse.ArgumentParser()
    sub = p.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("compare")
    c.add_argument("binary")
    c.add_argument("work")
    c.add_argument("--seed", type=int, default=16)
    s = sub.add_parser("score")
    s.add_argument("scene")
    s.add_argument("--depth-holes", default="before", choices=["before", "both"])
    a = p.parse_args()
    if a.cmd == "compare":
        compare(a.binary, a.work, a.seed)
    else:
        json.dump({"semantic": semantic_scene(a.scene), "depth": depth_scene(a.scene, a.depth_holes)},
                  sys.stdout, indent=1)


if __name__ == "__main__":
    main()
