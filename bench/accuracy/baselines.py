"""The three numpy baselines of issue 13, run beside al-refine as comparators (never shipped).

Common ground (as the issue states it): features are centred (rows L2-normalised, the scene mean
subtracted, normalised again); the prototype is the normalised mean centred feature of the removed
set R; kNN is k = 10 on positions over the whole scene (self excluded by index).

B1 kNN vote     add a kept Gaussian when >= 60 % of its neighbours are removed and its cosine to the
                prototype is >= the 20th percentile of R's own cosines; restore symmetrically: a
                removed Gaussian returns when >= 60 % of its neighbours are kept and its cosine is
                below that percentile. One pass.
B2 region grow  from R over kNN edges no longer than 3x the median kNN length (over the scene),
                through Gaussians whose cosine is >= median - 1.48 MAD of R's cosines. Add-only.
B3 min cut      the kNN graph over R dilated by 2 hops; unary 1 for leaving the mask's label,
                pairwise lam * exp(-d^2/sigma^2) * max(0, cos(f_u, f_v)) (centred features, sigma =
                the median kNN length over the graph's edges); exact min cut (scipy max flow on
                capacities scaled to integers). Two-sided. lam is chosen on the tuning seeds.
"""
import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components, maximum_flow
from scipy.spatial import cKDTree

K = 10


def unit(a):
    n = np.linalg.norm(a, axis=1, keepdims=True)
    return a / np.maximum(n, 1e-12)


def centred(features):
    f = unit(features)
    return unit(f - f.mean(0, keepdims=True))


class SceneGraph:
    """Positions, centred features and the scene-wide kNN (k = 10), computed once per scene."""

    def __init__(self, pos, feats):
        self.pos = pos
        self.f = centred(feats)
        tree = cKDTree(pos)
        d, idx = tree.query(pos, k=K + 1)
        own = idx == np.arange(len(pos))[:, None]
        # drop the query point itself (by index; a duplicate centre may come first)
        keep = ~own
        keep[np.where(~own.any(1))[0], -1] = False
        self.nbr = idx[keep].reshape(len(pos), K)
        self.dist = d[keep].reshape(len(pos), K)


def prototype_cos(g, removed):
    proto = g.f[removed].mean(0)
    proto /= max(np.linalg.norm(proto), 1e-12)
    return g.f @ proto


def b1_knn_vote(g, removed, share=0.6, pct=20):
    if not removed.any():
        return removed.copy()
    cos = prototype_cos(g, removed)
    thr = np.percentile(cos[removed], pct)
    frac_removed = removed[g.nbr].mean(1)
    add = ~removed & (frac_removed >= share) & (cos >= thr)
    restore = removed & (1.0 - frac_removed >= share) & (cos < thr)
    return (removed | add) & ~restore


def _knn_edges(g, nodes_mask=None, max_len=np.inf):
    n = len(g.pos)
    rows = np.repeat(np.arange(n), K)
    cols = g.nbr.ravel()
    d = g.dist.ravel()
    ok = d <= max_len
    if nodes_mask is not None:
        ok &= nodes_mask[rows] & nodes_mask[cols]
    return rows[ok], cols[ok], d[ok]


def b2_region_growing(g, removed, mad_factor=1.48, len_factor=3.0):
    if not removed.any():
        return removed.copy()
    cos = prototype_cos(g, removed)
    c = cos[removed]
    med = np.median(c)
    thr = med - mad_factor * np.median(np.abs(c - med))
    allowed = removed | (cos >= thr)
    rows, cols, _ = _knn_edges(g, allowed, len_factor * np.median(g.dist))
    n = len(g.pos)
    adj = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)).tocsr()
    _, comp = connected_components(adj, directed=False)
    seeded = np.zeros(comp.max() + 1, bool)
    seeded[comp[removed]] = True
    return removed | (allowed & seeded[comp])


def _dilate(g, mask, hops):
    out = mask.copy()
    n = len(g.pos)
    rows = np.repeat(np.arange(n), K)
    cols = g.nbr.ravel()
    for _ in range(hops):
        grown = out.copy()
        grown[cols[out[rows]]] = True   # i in set -> its neighbours
        grown[rows[out[cols]]] = True   # j in set -> whoever has j as a neighbour
        out = grown
    return out


def b3_min_cut(g, removed, lam=1.0, hops=2, scale=1000.0):
    if not removed.any():
        return removed.copy()
    cand = _dilate(g, removed, hops)
    ids = np.where(cand)[0]
    local = -np.ones(len(g.pos), np.int64)
    local[ids] = np.arange(len(ids))
    rows, cols, d = _knn_edges(g, cand)
    sigma = np.median(d[d > 0]) if np.any(d > 0) else 1.0
    sim = np.maximum(0.0, np.sum(g.f[rows] * g.f[cols], 1))
    w = lam * np.exp(-(d / sigma) ** 2) * sim
    n = len(ids)
    s, t = n, n + 1
    u, v = local[rows], local[cols]
    y = removed[ids]
    cap_e = np.round(w * scale).astype(np.int64)
    src_rows = np.concatenate([u, v, np.full(y.sum(), s), np.where(~y)[0]])
    src_cols = np.concatenate([v, u, np.where(y)[0], np.full((~y).sum(), t)])
    caps = np.concatenate([cap_e, cap_e, np.full(y.sum(), int(scale)), np.full((~y).sum(), int(scale))])
    cap = coo_matrix((caps, (src_rows, src_cols)), shape=(n + 2, n + 2)).tocsr()
    cap.sum_duplicates()
    cap = csr_matrix(cap, dtype=np.int32)
    res = maximum_flow(cap, s, t, method="dinic")
    resid = (cap - res.flow).tocsr()
    resid.data[resid.data < 0] = 0
    resid.eliminate_zeros()
    reach = breadth_first_order(resid, s, directed=True, return_predecessors=False)
    src_side = np.zeros(n + 2, bool)
    src_side[reach] = True
    out = removed.copy()
    out[ids] = src_side[:n]
    return out


BASELINES = {"B1": b1_knn_vote, "B2": b2_region_growing, "B3": b3_min_cut}
