// Cut pursuit outer loop, split, connected components, reduced graph and merge (CUT_PURSUIT.md §3-8,
// §12 determinism rules: canonical component numbering, per-component seeded generators, fixed-order
// sums, parallelism only over independent components).
#include "solvers/cut_pursuit/cut_pursuit.hpp"

#include <omp.h>

#include <algorithm>
#include <parallel/algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>

#include "al/core/block_sum.hpp"
#include "al/core/error.hpp"
#include "al/core/timer.hpp"
#include "solvers/cut_pursuit/cp_context.hpp"
#include "solvers/cut_pursuit/pfdr.hpp"
#include "solvers/level_sets/level_set_partition.hpp"

namespace al::cp {
namespace {

// An increase of F worth a warning: above 1e-6 relative. Smaller ones are the reduced solves'
// tolerance (the 3M room scene: 22086.432098 -> 22086.434475, 1e-7); they are still counted
// (non_monotone_steps) and the best iterate is still returned.
bool BeyondRounding(double now, double before) { return now - before > 1e-6 * std::max(std::fabs(before), 1.0); }

void Validate(const SimplexProblemView& pb) {
  const std::int64_t V = pb.num_nodes();
  if (pb.D < 1) throw Error("cut pursuit: D must be >= 1");
  if (V < 0) throw Error("cut pursuit: first_edge must hold V + 1 entries");
  const std::int64_t E = static_cast<std::int64_t>(pb.adj_vertices.size());
  if (pb.first_edge[0] != 0 || pb.first_edge[V] != E || pb.edge_weights.size() != pb.adj_vertices.size())
    throw Error("cut pursuit: inconsistent CSR graph (first_edge / adj_vertices / edge_weights)");
  for (std::int64_t v = 0; v < V; ++v)
    if (pb.first_edge[v + 1] < pb.first_edge[v]) throw Error("cut pursuit: first_edge is not monotone");
  for (std::int64_t e = 0; e < E; ++e) {
    if (pb.adj_vertices[e] < 0 || pb.adj_vertices[e] >= V) throw Error("cut pursuit: edge endpoint out of range");
    if (!std::isfinite(pb.edge_weights[e]) || pb.edge_weights[e] < 0.0)
      throw Error("cut pursuit: edge weights must be finite and >= 0");
  }
  if (static_cast<std::int64_t>(pb.y.size()) != V * pb.D) throw Error("cut pursuit: y must hold V x D values");
  for (double y : pb.y)
    if (!std::isfinite(y) || y < 0.0 || y > 1.0) throw Error("cut pursuit: observations must lie in [0, 1]");
  if (!pb.node_weights.empty()) {
    if (static_cast<std::int64_t>(pb.node_weights.size()) != V) throw Error("cut pursuit: node_weights must hold V values");
    for (double w : pb.node_weights)
      if (!std::isfinite(w) || w < 0.0) throw Error("cut pursuit: node weights must be finite and >= 0");
  }
  if (!pb.metric.empty()) {
    if (static_cast<int>(pb.metric.size()) != pb.D) throw Error("cut pursuit: metric must hold D values");
    for (double m : pb.metric)
      if (!std::isfinite(m) || m < 0.0) throw Error("cut pursuit: metric must be finite and >= 0");
  }
  if (!(pb.loss >= 0.0 && pb.loss <= 1.0)) throw Error("cut pursuit: loss s must lie in [0, 1]");
}

// Canonical lists: the vertices of each component in increasing index order.
void ComponentLists(const std::vector<std::int32_t>& comp, std::int32_t rV, std::vector<std::int64_t>& first,
                    std::vector<std::int32_t>& list) {
  first.assign(rV + 1, 0);
  for (std::int32_t c : comp) ++first[c + 1];
  for (std::int32_t c = 0; c < rV; ++c) first[c + 1] += first[c];
  list.resize(comp.size());
  std::vector<std::int64_t> pos(first.begin(), first.end() - 1);
  for (std::size_t v = 0; v < comp.size(); ++v) list[pos[comp[v]]++] = static_cast<std::int32_t>(v);
}

// al-refine extension of §7 (the spec saturates only components whose cut activates no edge). With
// D = 2 the two candidate directions span the whole tangent cone, so one min cut already is the best
// two-direction (first-order) split of a component at its value (for D > 2 with K = 2 the rule is a heuristic). When
// that split leaves a remainder (the final component holding most of the old vertices and no others)
// whose value then moved by at most cp_dif_tol, re-cutting it next iteration only answers the changed
// boundary: on the 100k benchmark a balanced max-flow over ~86k nodes (0.7 s) that splits off ~13
// nodes or none at all (pieces merged back). Such a remainder is saturated; the §7 rule desaturates it
// once its value moves by more than cp_dif_tol or it merges with another component. Returns the count.
int SaturateSplitRemainders(double tol, int D, const std::vector<char>& did_split, const std::vector<std::int64_t>& cfirst,
                            const std::vector<std::int32_t>& origin, const std::vector<std::int64_t>& csize,
                            const std::vector<std::int32_t>& piece_final, const std::vector<double>& rX,
                            const std::vector<double>& old_rX, std::vector<char>& new_sat) {
  const std::size_t nrv = new_sat.size();
  std::vector<std::int32_t> source(nrv, -2);  // the one old component of a final one, -1 if several
  std::vector<std::int64_t> size(nrv, 0);
  for (std::size_t c = 0; c < origin.size(); ++c) {
    const std::int32_t f = piece_final[c];
    source[f] = source[f] == -2 || source[f] == origin[c] ? origin[c] : -1;
    size[f] += csize[c];
  }
  int count = 0;
  for (std::size_t f = 0; f < nrv; ++f) {
    const std::int32_t o = source[f];
    if (o < 0 || !did_split[o] || new_sat[f] || 2 * size[f] <= cfirst[o + 1] - cfirst[o]) continue;
    double moved = 0.0;
    for (int d = 0; d < D; ++d) moved += std::fabs(rX[f * D + d] - old_rX[static_cast<std::size_t>(o) * D + d]);
    if (moved <= tol) {
      new_sat[f] = 1;
      ++count;
    }
  }
  return count;
}


// The piecewise-constant iterate: the component of each vertex, the components' values, and which
// components are saturated (not offered to the next split).
struct Iterate {
  std::vector<std::int32_t> comp;
  std::int32_t rV = 1;
  std::vector<double> rX;
  std::vector<char> saturated;
  // Every component is connected (level-set pieces; merged pieces after an iteration). A warm
  // start's components may not be, nor the single initial one.
  bool connected = false;
};

// Buffers every split round reuses.
struct SplitBuffers {
  std::vector<std::int64_t> cfirst;
  std::vector<std::int32_t> clist, local;
  std::vector<char> label;
  std::vector<MaxFlow> networks;  // one reusable flow network per thread
};

struct SplitRound {
  std::vector<char> did_split;
  bool any_split = false;
  std::int64_t cut_nodes = 0;  // vertices of the non-saturated components offered to the split
};

Context MakeContext(const SimplexProblemView& pb, const CutPursuitOptions& opt) {
  const int D = pb.D;
  const std::int64_t V = pb.num_nodes();
  Context cx{pb, opt, D, V, Loss{pb.loss, D}, std::numeric_limits<double>::epsilon(), {}, {}, {}};
  if (opt.cp_dif_tol > 0.0 && opt.cp_dif_tol < cx.eps) cx.eps = opt.cp_dif_tol;
  cx.nw = pb.node_weights.empty() ? std::vector<double>(V, 1.0)
                                  : std::vector<double>(pb.node_weights.begin(), pb.node_weights.end());
  cx.m = pb.metric.empty() ? std::vector<double>(D, 1.0) : std::vector<double>(pb.metric.begin(), pb.metric.end());
  return cx;
}

PfdrOptions MakePfdrOptions(const CutPursuitOptions& opt, double eps, int threads) {
  PfdrOptions popt;
  popt.rho = opt.pfdr_rho;
  popt.cond_min = opt.pfdr_cond_min;
  popt.dif_rcd = opt.pfdr_dif_rcd;
  popt.dif_tol = opt.pfdr_dif_tol >= 0.0 ? opt.pfdr_dif_tol : 1e-2 * opt.cp_dif_tol;
  popt.it_max = opt.pfdr_it_max;
  popt.eps = eps;
  popt.num_threads = threads;
  return popt;
}

// One component with the closed-form value (§3.1).
Iterate InitialIterate(const Context& cx) {
  const int D = cx.D;
  Iterate it{std::vector<std::int32_t>(cx.V, 0), 1, std::vector<double>(D), std::vector<char>(1, 0)};
  std::vector<double> ybar(D, 0.0);
  double W = 0.0;
  for (std::int64_t v = 0; v < cx.V; ++v) {
    W += cx.nw[v];
    for (int d = 0; d < D; ++d) ybar[d] += cx.nw[v] * cx.pb.y[static_cast<std::size_t>(v) * D + d];
  }
  for (int d = 0; d < D; ++d) ybar[d] = W > 0.0 ? ybar[d] / W : 1.0 / D;
  ClosedFormValue(cx.loss, D, ybar.data(), it.rX.data());
  return it;
}

// The warm start's iterate (WarmStart): components numbered by their smallest vertex (§12), a new
// node alone at its closed form, saturation kept only where nothing new touches a component.
Iterate WarmIterate(const Context& cx, const WarmStart& w) {
  const int D = cx.D;
  const auto n_old = static_cast<std::int64_t>(w.values.size()) / D;
  if (static_cast<std::int64_t>(w.comp.size()) != cx.V || static_cast<std::int64_t>(w.values.size()) != n_old * D ||
      (!w.saturated.empty() && static_cast<std::int64_t>(w.saturated.size()) != n_old))
    throw Error("cut pursuit: warm start sizes do not match the problem");
  for (double x : w.values)
    if (!(x >= 0.0 && x <= 1.0)) throw Error("cut pursuit: warm start values must lie in [0, 1]");
  Iterate it{std::vector<std::int32_t>(cx.V, -1), 0, {}, {}};
  std::vector<std::int32_t> id_of(static_cast<std::size_t>(n_old), -1);
  std::vector<double> x(D);
  for (std::int64_t v = 0; v < cx.V; ++v) {
    const std::int32_t c = w.comp[v];
    if (c >= n_old) throw Error("cut pursuit: warm start component out of range");
    if (c >= 0 && id_of[c] >= 0) {
      it.comp[v] = id_of[c];
      continue;
    }
    if (c >= 0) std::copy_n(&w.values[static_cast<std::size_t>(c) * D], D, x.begin());
    else ClosedFormValue(cx.loss, D, &cx.pb.y[static_cast<std::size_t>(v) * D], x.data());
    it.comp[v] = it.rV++;
    if (c >= 0) id_of[c] = it.comp[v];
    it.rX.insert(it.rX.end(), x.begin(), x.end());
    it.saturated.push_back(c >= 0 && !w.saturated.empty() ? w.saturated[c] : 0);
  }
  for (std::int64_t v = 0; v < cx.V; ++v) {
    if (w.comp[v] >= 0) continue;
    for (std::int64_t k = cx.adj.first[v]; k < cx.adj.first[v + 1]; ++k) it.saturated[it.comp[cx.adj.nbr[k]]] = 0;
  }
  return it;
}

// The D = 2 cold start (Init::kLevelSets): the level-set partition of §11 down to intervals of
// init_epsilon. Its pieces are connected and ordered exactly as the optimum's values; a piece whose
// level cut gained nothing is an optimal plateau and starts saturated (§7 desaturates it if its
// value moves), the others start at their best constant and are split by the loop.
Iterate LevelSetIterate(const Context& cx, std::vector<MaxFlow>& networks, int threads, CutPursuitResult& res) {
  Timer timer;
  // No adjacency passed: the level-set run builds its own, keeps only its renumbered copy, and the
  // context's is built after it (the two at once were 100 MB of peak RSS at 685k nodes / 4M edges).
  const levelset::TwoLabelTv tv{cx.pb.first_edge, cx.pb.adj_vertices, cx.pb.edge_weights, cx.pb.y, cx.nw,
                                cx.m[0] + cx.m[1], cx.loss, nullptr};
  levelset::Options lopt;
  lopt.epsilon = cx.opt.init_epsilon > 0.0 ? cx.opt.init_epsilon : 0.5 * cx.opt.cp_dif_tol;
  lopt.num_threads = threads;
  lopt.max_flow = cx.opt.max_flow;
  levelset::Partition part = levelset::SolveLevelSets(tv, lopt, &networks);
  Iterate it{std::move(part.piece), static_cast<std::int32_t>(part.value.size()), {}, {}, true};
  it.rX.resize(2 * part.value.size());
  it.saturated.resize(part.value.size());
  for (std::size_t c = 0; c < part.value.size(); ++c) {
    it.rX[2 * c] = part.value[c];
    it.rX[2 * c + 1] = 1.0 - part.value[c];
    // Every node's optimum lies in [lo, hi]: no split can move it by more than 2 (hi - lo) in l1.
    it.saturated[c] = part.plateau[c] || 2.0 * (part.hi[c] - part.lo[c]) <= cx.opt.cp_dif_tol;
    res.init_plateaus += part.plateau[c];
  }
  res.init_max_flows = part.max_flows;
  res.init_pieces = it.rV;
  res.init_seconds = timer.Seconds();
  return it;
}

// Splits every non-saturated component (parallel over independent components, largest first for
// load balance; each writes only its own vertices' labels), then saturates the ones that did not split.
SplitRound SplitAll(const Context& cx, Iterate& it, SplitBuffers& buf, int threads) {
  ComponentLists(it.comp, it.rV, buf.cfirst, buf.clist);
  const auto& cfirst = buf.cfirst;
  for (std::int32_t c = 0; c < it.rV; ++c)
    for (std::int64_t k = cfirst[c]; k < cfirst[c + 1]; ++k) buf.local[buf.clist[k]] = static_cast<std::int32_t>(k - cfirst[c]);
  std::fill(buf.label.begin(), buf.label.end(), 0);
  SplitRound round;
  round.did_split.assign(it.rV, 0);
  std::vector<std::int32_t> order(it.rV);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return cfirst[a + 1] - cfirst[a] > cfirst[b + 1] - cfirst[b];
  });
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::int32_t oi = 0; oi < it.rV; ++oi) {
    const std::int32_t c = order[oi];
    if (it.saturated[c]) continue;
    std::vector<std::int32_t> verts(buf.clist.begin() + cfirst[c], buf.clist.begin() + cfirst[c + 1]);
    round.did_split[c] =
        SplitComponent(cx, c, it.comp, it.rX, verts, buf.local, buf.label, buf.networks[omp_get_thread_num()]) ? 1 : 0;
  }
  for (std::int32_t c = 0; c < it.rV; ++c) {
    if (!it.saturated[c] && cfirst[c + 1] - cfirst[c] > 1) round.cut_nodes += cfirst[c + 1] - cfirst[c];
    if (!it.saturated[c] && !round.did_split[c]) it.saturated[c] = 1;
    round.any_split = round.any_split || round.did_split[c];
  }
  return round;
}

// Connected components over edges whose ends share their old component and their split label,
// numbered by smallest vertex (§5, §12); origin[c] = the old component of new component c. A
// connected old component that did not split stays whole without a search.
std::int32_t BoundComponents(const Context& cx, const Iterate& old, const SplitRound& round, const SplitBuffers& buf,
                             std::vector<std::int32_t>& cc, std::vector<std::int32_t>& origin) {
  cc.assign(cx.V, -1);
  std::vector<std::int32_t> queue;
  std::int32_t nc = 0;
  for (std::int64_t s = 0; s < cx.V; ++s) {
    if (cc[s] >= 0) continue;
    const std::int32_t o = old.comp[s];
    origin.push_back(o);
    if (old.connected && !round.did_split[o]) {
      for (std::int64_t k = buf.cfirst[o]; k < buf.cfirst[o + 1]; ++k) cc[buf.clist[k]] = nc;
      ++nc;
      continue;
    }
    cc[s] = nc;
    queue.assign(1, static_cast<std::int32_t>(s));
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const std::int32_t v = queue[h];
      for (std::int64_t k = cx.adj.first[v]; k < cx.adj.first[v + 1]; ++k) {
        const std::int32_t u = cx.adj.nbr[k];
        if (cc[u] >= 0 || old.comp[u] != o || buf.label[u] != buf.label[v]) continue;
        cc[u] = nc;
        queue.push_back(u);
      }
    }
    ++nc;
  }
  return nc;
}

// Reduced edges (§3.4): the summed weight of the edges between each pair of components, sorted.
void ReducedEdges(const Context& cx, const std::vector<std::int32_t>& cc, ReducedProblem& rp) {
  const SimplexProblemView& pb = cx.pb;
  using CutEdge = std::tuple<std::int32_t, std::int32_t, std::int64_t>;
  // Collected per block of source nodes on both threads and sorted in parallel: the key (a, b, e)
  // is unique, so the sorted list (and every sum below) is the same for any schedule.
  constexpr std::int64_t kBlock = std::int64_t{1} << 15;
  const std::int64_t blocks = (cx.V + kBlock - 1) / kBlock;
  std::vector<std::vector<CutEdge>> per_block(static_cast<std::size_t>(blocks));
#pragma omp parallel for schedule(dynamic, 1) if (blocks > 1)
  for (std::int64_t b = 0; b < blocks; ++b)
    for (std::int64_t u = b * kBlock; u < std::min(cx.V, (b + 1) * kBlock); ++u)
      for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e) {
        const std::int32_t v = pb.adj_vertices[e];
        if (cc[u] == cc[v] || !(pb.edge_weights[e] > 0.0)) continue;
        per_block[static_cast<std::size_t>(b)].emplace_back(std::min(cc[u], cc[v]), std::max(cc[u], cc[v]), e);
      }
  std::vector<CutEdge> cut;
  for (const auto& part : per_block) cut.insert(cut.end(), part.begin(), part.end());
  __gnu_parallel::sort(cut.begin(), cut.end());
  for (std::size_t i = 0; i < cut.size(); ++i) {
    const auto& [a, b, e] = cut[i];
    if (i == 0 || a != rp.ea.back() || b != rp.eb.back()) {
      rp.ea.push_back(a);
      rp.eb.push_back(b);
      rp.omega.push_back(0.0);
    }
    rp.omega.back() += pb.edge_weights[e];
  }
}

// Reduced observations: the weighted mean of y per component (components of zero total weight
// carry no data: their unweighted mean). csize = vertices per component.
void ReducedValues(const Context& cx, const std::vector<std::int32_t>& cc, ReducedProblem& rp,
                   std::vector<std::int64_t>& csize) {
  const int D = cx.D;
  const std::int32_t nc = rp.rV;
  const std::span<const double> y = cx.pb.y;
  rp.W.assign(nc, 0.0);
  rp.Ybar.assign(static_cast<std::size_t>(nc) * D, 0.0);
  csize.assign(nc, 0);
  for (std::int64_t v = 0; v < cx.V; ++v) {
    const std::int32_t c = cc[v];
    ++csize[c];
    rp.W[c] += cx.nw[v];
    for (int d = 0; d < D; ++d) rp.Ybar[static_cast<std::size_t>(c) * D + d] += cx.nw[v] * y[static_cast<std::size_t>(v) * D + d];
  }
  std::vector<double> umean;
  for (std::int32_t c = 0; c < nc; ++c) {
    double* ybar = &rp.Ybar[static_cast<std::size_t>(c) * D];
    if (rp.W[c] > 0.0) {
      for (int d = 0; d < D; ++d) ybar[d] /= rp.W[c];
      continue;
    }
    if (umean.empty()) {
      umean.assign(static_cast<std::size_t>(nc) * D, 0.0);
      for (std::int64_t v = 0; v < cx.V; ++v)
        for (int d = 0; d < D; ++d) umean[static_cast<std::size_t>(cc[v]) * D + d] += y[static_cast<std::size_t>(v) * D + d];
    }
    for (int d = 0; d < D; ++d) ybar[d] = umean[static_cast<std::size_t>(c) * D + d] / csize[c];
  }
}

ReducedProblem ReduceGraph(const Context& cx, const std::vector<std::int32_t>& cc, std::int32_t nc,
                           std::vector<std::int64_t>& csize) {
  ReducedProblem rp;
  rp.rV = nc;
  rp.D = cx.D;
  rp.metric = cx.m;
  rp.loss = cx.loss;
  ReducedEdges(cx, cc, rp);
  ReducedValues(cx, cc, rp, csize);
  return rp;
}

// Union of reduced neighbours whose values differ by at most cp_dif_tol relative to their size
// (§7): afterwards parent[c] is c's root, the lowest index of its group; merged[root] marks roots
// that absorbed another.
void UnionCloseNeighbours(const Context& cx, const ReducedProblem& rp, const std::vector<double>& X,
                          std::vector<std::int32_t>& parent, std::vector<char>& merged) {
  const int D = cx.D;
  auto find = [&](std::int32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t e = 0; e < rp.ea.size(); ++e) {
    std::int32_t a = find(rp.ea[e]), b = find(rp.eb[e]);
    if (a == b) continue;
    const double* xa = &X[static_cast<std::size_t>(a) * D];
    const double* xb = &X[static_cast<std::size_t>(b) * D];
    double dist = 0.0, na = 0.0, nb = 0.0;
    for (int d = 0; d < D; ++d) {
      dist += cx.m[d] * std::fabs(xa[d] - xb[d]);
      na += cx.m[d] * std::fabs(xa[d]);
      nb += cx.m[d] * std::fabs(xb[d]);
    }
    if (dist <= cx.opt.cp_dif_tol * std::max({na, nb, cx.eps})) {
      if (b < a) std::swap(a, b);
      parent[b] = a;
      merged[a] = 1;
    }
  }
  // Every parent has a smaller index than its child, so one ascending pass points each at its root.
  for (std::size_t c = 0; c < parent.size(); ++c) parent[c] = parent[parent[c]];
}

// Per piece of the split (c < nc): the old component it came from, its size, and after the merge
// the final component it belongs to.
struct Pieces {
  std::vector<std::int32_t> origin, cc;
  std::vector<std::int64_t> csize;
  std::vector<std::int32_t> final_of;
};

// The merged iterate (§7): values of the roots; a root is saturated iff it is exactly one previous
// saturated component whose value did not move by more than cp_dif_tol.
Iterate MergePieces(const Context& cx, const ReducedProblem& rp, const std::vector<double>& X, const Iterate& old,
                    const std::vector<std::int64_t>& cfirst, Pieces& pieces) {
  const int D = cx.D;
  const std::int32_t nc = rp.rV;
  std::vector<std::int32_t> parent(nc);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> merged(nc, 0);
  UnionCloseNeighbours(cx, rp, X, parent, merged);
  std::vector<std::int32_t> final_id(nc, -1);
  Iterate next;
  next.rV = 0;
  next.connected = true;  // connected pieces, merged only across reduced edges
  for (std::int32_t c = 0; c < nc; ++c)
    if (parent[c] == c) final_id[c] = next.rV++;
  next.rX.resize(static_cast<std::size_t>(next.rV) * D);
  next.saturated.assign(next.rV, 0);
  for (std::int32_t c = 0; c < nc; ++c) {
    if (parent[c] != c) continue;
    const std::int32_t f = final_id[c], o = pieces.origin[c];
    std::copy(&X[static_cast<std::size_t>(c) * D], &X[static_cast<std::size_t>(c) * D] + D, &next.rX[static_cast<std::size_t>(f) * D]);
    if (merged[c] || !old.saturated[o] || pieces.csize[c] != cfirst[o + 1] - cfirst[o]) continue;
    double moved = 0.0;
    for (int d = 0; d < D; ++d) moved += std::fabs(X[static_cast<std::size_t>(c) * D + d] - old.rX[static_cast<std::size_t>(o) * D + d]);
    next.saturated[f] = moved <= cx.opt.cp_dif_tol ? 1 : 0;
  }
  pieces.final_of.resize(nc);
  for (std::int32_t c = 0; c < nc; ++c) pieces.final_of[c] = final_id[parent[c]];
  next.comp.resize(cx.V);
  for (std::int64_t v = 0; v < cx.V; ++v) next.comp[v] = pieces.final_of[pieces.cc[v]];
  return next;
}

// Mean l1 change of the vertex values between two iterates (§8), fixed-order sum.
double Evolution(const Context& cx, const Iterate& now, const Iterate& before) {
  const int D = cx.D;
  double total = 0.0;
  for (std::int64_t v = 0; v < cx.V; ++v) {
    const double* a = &now.rX[static_cast<std::size_t>(now.comp[v]) * D];
    const double* b = &before.rX[static_cast<std::size_t>(before.comp[v]) * D];
    for (int d = 0; d < D; ++d) total += std::fabs(a[d] - b[d]);
  }
  return total / static_cast<double>(cx.V);
}
}  // namespace

// Each node's data term and its stored edges' TV, summed on all threads (BlockSum2: the same
// double for any thread count; one serial pass was 0.025 s at 685k nodes, twice per solve).
double SimplexObjective(const SimplexProblemView& pb, const std::vector<std::int32_t>& comp, const std::vector<double>& rX) {
  const int D = pb.D;
  const Loss loss{pb.loss, D};
  return BlockSum2(pb.num_nodes(), [&](std::int64_t u, double& data, double& tv) {
    const double w = pb.node_weights.empty() ? 1.0 : pb.node_weights[u];
    const double* xu = &rX[static_cast<std::size_t>(comp[u]) * D];
    double s = 0.0;
    for (int d = 0; d < D; ++d) s += loss.Value(pb.y[static_cast<std::size_t>(u) * D + d], xu[d]);
    data += w * s;
    for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e) {
      const std::int32_t v = pb.adj_vertices[e];
      if (comp[u] == comp[v]) continue;
      const double* xv = &rX[static_cast<std::size_t>(comp[v]) * D];
      double m = 0.0;
      for (int d = 0; d < D; ++d) m += (pb.metric.empty() ? 1.0 : pb.metric[d]) * std::fabs(xu[d] - xv[d]);
      tv += pb.edge_weights[e] * m;
    }
  });
}

namespace {

SplitBuffers MakeSplitBuffers(std::int64_t V, int threads, MaxFlow::Algorithm algorithm) {
  SplitBuffers buf;
  buf.local.resize(V);
  buf.label.resize(V);
  // No THP advice (max_flow.hpp): the first cuts of the level-set start fill each network to its
  // largest size at once; advised, those first touches waited on compaction (685k problem, 3 runs
  // interleaved: 2.03-3.06 s with, 1.93-1.97 s without; 3M refine median 7.01 -> 6.19 s, -25 MiB).
  buf.networks.reserve(std::size_t(threads));
  for (int t = 0; t < threads; ++t) buf.networks.emplace_back(false);
  for (MaxFlow& network : buf.networks) network.set_algorithm(algorithm);
  return buf;
}

// One outer iteration from `it` (§3): split, reduce, solve the reduced problem, merge; appends the
// round's diagnostics, evolution and objective to res. Returns the new iterate.
Iterate OuterIteration(const Context& cx, const PfdrOptions& popt, Iterate& it, SplitBuffers& buf, int threads,
                       CutPursuitResult& res, bool& any_split) {
  Timer phase;
  const SplitRound round = SplitAll(cx, it, buf, threads);
  any_split = round.any_split;
  res.split_nodes.push_back(round.cut_nodes);
  res.split_seconds.push_back(phase.Seconds());
  phase.Reset();
  Pieces pieces;
  const std::int32_t nc = BoundComponents(cx, it, round, buf, pieces.cc, pieces.origin);
  const ReducedProblem rp = ReduceGraph(cx, pieces.cc, nc, pieces.csize);
  res.reduce_seconds.push_back(phase.Seconds());
  phase.Reset();
  std::vector<double> X;
  if (cx.D == 2 && cx.opt.reduced_solver == CutPursuitOptions::Reduced::kLevelSets) {
    res.reduced_max_flows.push_back(SolveReducedLevelSets(rp, {1e-10, threads, cx.opt.max_flow}, buf.networks, X));
    res.pfdr_iterations.push_back(0);
  } else {
    res.pfdr_iterations.push_back(SolveReduced(rp, popt, X));
    res.reduced_max_flows.push_back(0);
  }
  res.pfdr_seconds.push_back(phase.Seconds());
  phase.Reset();
  Iterate next = MergePieces(cx, rp, X, it, buf.cfirst, pieces);
  res.dif_history.push_back(Evolution(cx, next, it));
  if (cx.opt.saturate_split_remainders)
    res.remainder_saturations += SaturateSplitRemainders(cx.opt.cp_dif_tol, cx.D, round.did_split, buf.cfirst,
                                                         pieces.origin, pieces.csize, pieces.final_of, next.rX,
                                                         it.rX, next.saturated);
  ++res.iterations;
  const double obj = SimplexObjective(cx.pb, next.comp, next.rX);
  res.non_monotone_steps += obj > res.objective_history.back();
  if (BeyondRounding(obj, res.objective_history.back()))
    res.warnings.push_back("cut pursuit: objective increased at iteration " + std::to_string(res.iterations) +
                           " (" + std::to_string(res.objective_history.back()) + " -> " + std::to_string(obj) + ")");
  res.objective_history.push_back(obj);
  res.merge_seconds.push_back(phase.Seconds());
  return next;
}

}  // namespace

CutPursuitResult RunCutPursuit(const SimplexProblemView& pb, const CutPursuitOptions& opt, const WarmStart* warm) {
  if (pb.first_edge.empty()) throw Error("cut pursuit: first_edge must hold V + 1 entries");
  Validate(pb);
  opt.Check();
  Context cx = MakeContext(pb, opt);
  const int threads = opt.num_threads > 0 ? opt.num_threads : omp_get_max_threads();
  const PfdrOptions popt = MakePfdrOptions(opt, cx.eps, threads);
  CutPursuitResult res;
  if (cx.V == 0) {
    res.converged = true;
    res.objective_history.push_back(0.0);
    return res;
  }
  SplitBuffers buf = MakeSplitBuffers(cx.V, threads, opt.max_flow);
  const bool level_sets = !warm && cx.D == 2 && opt.init == CutPursuitOptions::Init::kLevelSets;
  Iterate it = level_sets ? LevelSetIterate(cx, buf.networks, threads, res) : Iterate{};
  cx.adj = levelset::BuildSymmetricAdjacency(pb.first_edge, pb.adj_vertices);
  if (!level_sets) it = warm ? WarmIterate(cx, *warm) : InitialIterate(cx);
  res.objective_history.push_back(SimplexObjective(pb, it.comp, it.rX));
  Iterate best = it;
  double best_obj = res.objective_history[0];
  bool stalled = false;
  while (res.iterations < opt.cp_it_max && (res.dif_history.empty() || res.dif_history.back() > opt.cp_dif_tol)) {
    bool any_split = false;
    it = OuterIteration(cx, popt, it, buf, threads, res, any_split);
    if (res.objective_history.back() < best_obj) {
      best_obj = res.objective_history.back();
      best = it;
    }
    if (!any_split) {
      stalled = true;
      break;
    }
  }
  res.converged = stalled || (!res.dif_history.empty() && res.dif_history.back() <= opt.cp_dif_tol);
  if (res.objective_history.back() > best_obj) {
    if (BeyondRounding(res.objective_history.back(), best_obj))
      res.warnings.push_back("cut pursuit: returning the best iterate (F = " + std::to_string(best_obj) +
                             ") instead of the last one (F = " + std::to_string(res.objective_history.back()) + ")");
    it = std::move(best);
    it.rV = static_cast<std::int32_t>(it.rX.size() / cx.D);
  }
  res.num_components = it.rV;
  res.saturated = it.saturated;
  res.comp_assign = std::move(it.comp);
  res.rX = std::move(it.rX);
  res.objective = std::min(best_obj, res.objective_history.back());
  return res;
}

}  // namespace al::cp
