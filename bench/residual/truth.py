"""The ground-truth residual of issue 32, computed here in numpy from float renders written by
`al-refine render --npy` (independent of the evaluator's code, which it checks):

  O = pixels where |rgb_before - rgb_ideal| > 0.1 (Euclidean, RGB clamped to [0, 1]);
  a view's residual = mean over O of min(1, |rgb_after - rgb_ideal| / |rgb_before - rgb_ideal|);
  the scene's residual = mean over the views with |O| >= 64 (None when there is none).

before = the full scene, after = without the removal, ideal = without the whole target; every
camera of the scene is used (the evaluator scores the views whose object mask is not empty)."""
import os

import numpy as np

FOOTPRINT = 0.1
MIN_PIXELS = 64


def _rgb(folder, view):
    a = np.load(os.path.join(folder, f"{view}_rgb.npy")).astype(np.float64)
    return np.clip(np.nan_to_num(a, nan=0.0, posinf=0.0, neginf=0.0), 0.0, 1.0)


def view_residual(before, after, ideal):
    signal = np.linalg.norm(before - ideal, axis=2)
    footprint = signal > FOOTPRINT
    if footprint.sum() < MIN_PIXELS:
        return None
    left = np.linalg.norm(after - ideal, axis=2)[footprint] / signal[footprint]
    return float(np.minimum(1.0, left).mean())


def scene_residual(before_dir, after_dir, ideal_dir, views):
    values = [view_residual(_rgb(before_dir, v), _rgb(after_dir, v), _rgb(ideal_dir, v)) for v in views]
    values = [v for v in values if v is not None]
    return float(np.mean(values)) if values else None


def views_of(render_dir):
    return sorted(f[: -len("_rgb.npy")] for f in os.listdir(render_dir) if f.endswith("_rgb.npy"))
