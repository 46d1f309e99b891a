"""The removals of the residual validity bench: for one scene, the removal methods' own masks plus
leftovers built from the ground truth, so that every kind of "what stays" is represented:

  perfect     nothing of the target stays (removed = the target)
  none        nothing is removed
  slab25      a spatial slab of a quarter of the target stays (the Gaussians with the lowest
              projection on a direction drawn from the scene's seed)
  slab50      the same, half of the target
  random30    a random 30 % of the target's Gaussians stay (scattered)
  featoff20   the fifth of the target least like it in feature space stays (lowest cosine to the
              target's mean centred unit feature): what a feature-based removal misses
  <method>    each removal-method simulator's mask (gen: fgs_like, sags_like, gg_like; synth: fgs,
              sags, gg, gc), refined with that method's preset

Masks are numpy bool arrays over the scene's Gaussians (True = removed)."""
import numpy as np

LEFTOVER_KINDS = ("perfect", "none", "slab25", "slab50", "random30", "featoff20")
# The refine preset of each method mask (the leftover kinds are refined with fgs, as in issue 32).
METHOD_PRESET = {"fgs_like": "fgs", "sags_like": "sags", "gg_like": "gg", "fgs": "fgs", "sags": "sags", "gg": "gg",
                 "gc": "gc"}


def _unit(rows):
    norms = np.linalg.norm(rows, axis=1, keepdims=True)
    return rows / np.where(norms > 0, norms, 1.0)


def leftovers(target, positions, features, seed):
    """{kind: removed mask} for the leftover kinds of one scene."""
    n = target.size
    idx = np.flatnonzero(target)
    rng = np.random.default_rng(1000 + seed)
    out = {"perfect": target.copy(), "none": np.zeros(n, bool)}
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    along = positions[idx] @ direction
    order = idx[np.argsort(along, kind="stable")]
    for name, share in (("slab25", 0.25), ("slab50", 0.5)):
        removed = target.copy()
        removed[order[: int(round(share * idx.size))]] = False
        out[name] = removed
    removed = target.copy()
    removed[rng.choice(idx, int(round(0.3 * idx.size)), replace=False)] = False
    out["random30"] = removed
    if features is not None:
        unit = _unit(features - features.mean(axis=0))   # centred: CLIP-like features share one direction
        proto = unit[idx].mean(axis=0)
        cos = unit[idx] @ (proto / max(np.linalg.norm(proto), 1e-12))
        removed = target.copy()
        removed[idx[np.argsort(cos, kind="stable")[: int(round(0.2 * idx.size))]]] = False
        out["featoff20"] = removed
    return out
