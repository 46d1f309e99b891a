// The split of one component (CUT_PURSUIT.md §4): descent directions of its vertices, k-means++
// clustering of those directions into two candidates (§4.3), then a binary min cut between the two
// (§4.4). Deterministic: the generator is seeded by the component's smallest vertex (§12).
#include <algorithm>
#include <cmath>
#include <random>

#include "solvers/cut_pursuit/cp_context.hpp"

namespace al::cp {
namespace {

constexpr double kBigCap = 1e300;  // stands for an infeasible side in a unary

double Dot(const double* a, const double* b, int D) {
  double s = 0.0;
  for (int d = 0; d < D; ++d) s += a[d] * b[d];
  return s;
}

bool Feasible(const double* X, const double* s, int D, double eps) {
  for (int d = 0; d < D; ++d) {
    if (X[d] <= eps && s[d] < -eps) return false;
    if (X[d] >= 1.0 - eps && s[d] > eps) return false;
  }
  return true;
}

// The component's vertices with their gradient G (smooth part plus the TV derivative of cut edges,
// §4.1) and projected steepest-descent proposals S, and the costs the clustering and the cut use.
struct SplitGeometry {
  const Context& cx;
  const double* X;  // the component's value
  std::int32_t n;
  std::vector<double> G, S;

  std::size_t At(std::int32_t i) const { return static_cast<std::size_t>(i) * cx.D; }
  // <s, G_i> for a feasible direction s at X, else +infinity.
  double Cost(std::int32_t i, const double* s) const {
    return Feasible(X, s, cx.D, cx.eps) ? Dot(s, &G[At(i)], cx.D) : kInf;
  }
  // Direction of a cluster: projection of the mean of -G over its vertices; false when empty.
  bool Centre(const std::vector<char>& lab, int k, double* out) const {
    const int D = cx.D;
    std::vector<double> mean(D, 0.0);
    std::int64_t count = 0;
    for (std::int32_t i = 0; i < n; ++i)
      if (lab[i] == k) {
        ++count;
        for (int d = 0; d < D; ++d) mean[d] -= G[At(i) + d];
      }
    if (count == 0) return false;
    for (int d = 0; d < D; ++d) mean[d] /= static_cast<double>(count);
    ProjectDirection(X, mean.data(), D, cx.eps, cx.opt.emulate_upstream_projection_bug, out);
    return true;
  }
};

SplitGeometry MakeGeometry(const Context& cx, std::int32_t c, const std::vector<std::int32_t>& comp,
                           const std::vector<double>& rX, const std::vector<std::int32_t>& verts) {
  const int D = cx.D;
  SplitGeometry geo{cx, &rX[static_cast<std::size_t>(c) * D], static_cast<std::int32_t>(verts.size()), {}, {}};
  geo.G.resize(static_cast<std::size_t>(geo.n) * D);
  geo.S.resize(static_cast<std::size_t>(geo.n) * D);
  std::vector<double> neg(D);
  for (std::int32_t i = 0; i < geo.n; ++i) {
    const std::int32_t v = verts[i];
    double* g = &geo.G[geo.At(i)];
    for (int d = 0; d < D; ++d) g[d] = cx.nw[v] * cx.loss.Grad(cx.pb.y[static_cast<std::size_t>(v) * D + d], geo.X[d]);
    for (std::int64_t k = cx.adj.first[v]; k < cx.adj.first[v + 1]; ++k) {
      const std::int32_t u = cx.adj.nbr[k];
      if (comp[u] == c) continue;
      const double w = cx.pb.edge_weights[cx.adj.edge[k]];
      if (!(w > 0.0)) continue;
      const double* xu = &rX[static_cast<std::size_t>(comp[u]) * D];
      for (int d = 0; d < D; ++d) {
        const double diff = geo.X[d] - xu[d];
        if (diff > cx.eps) g[d] += w * cx.m[d];
        else if (diff < -cx.eps) g[d] -= w * cx.m[d];
      }
    }
    for (int d = 0; d < D; ++d) neg[d] = -g[d];
    ProjectDirection(geo.X, neg.data(), D, cx.eps, cx.opt.emulate_upstream_projection_bug, &geo.S[geo.At(i)]);
  }
  return geo;
}

// k-means++ weight of vertex i given the first k centres: 0 when its proposal already is a centre
// (as a point at distance 0), else its cost above the best one.
double SeedWeight(const SplitGeometry& geo, std::int32_t i, const std::vector<double>& centres, int k,
                  double min_cost, double gmin) {
  const int D = geo.cx.D;
  for (int j = 0; j < k; ++j) {
    double dist = 0.0;
    for (int d = 0; d < D; ++d) dist += std::fabs(geo.S[geo.At(i) + d] - centres[static_cast<std::size_t>(j) * D + d]);
    if (dist <= 1e-9) return 0.0;  // unit vectors: rounding-level differences are duplicates
  }
  return std::isfinite(min_cost) ? min_cost - gmin + geo.cx.eps : geo.cx.eps;
}

// k-means++ seeding (§4.3). With D = 2 the proposals take two or three values, and drawing a
// duplicate would collapse the clusters and wrongly saturate the component, hence SeedWeight.
std::vector<double> SeedCentres(const SplitGeometry& geo, std::mt19937_64& rng) {
  const int D = geo.cx.D;
  const std::int32_t n = geo.n;
  std::vector<double> centres;
  const std::int32_t first = std::uniform_int_distribution<std::int32_t>(0, n - 1)(rng);
  centres.insert(centres.end(), &geo.S[geo.At(first)], &geo.S[geo.At(first)] + D);
  for (int k = 1; k < geo.cx.opt.K; ++k) {
    std::vector<double> minc(n, kInf);
    double gmin = kInf;
    for (std::int32_t i = 0; i < n; ++i) {
      for (int j = 0; j < k; ++j) minc[i] = std::min(minc[i], geo.Cost(i, &centres[static_cast<std::size_t>(j) * D]));
      gmin = std::min(gmin, minc[i]);
    }
    double total = 0.0;
    for (std::int32_t i = 0; i < n; ++i) {
      minc[i] = SeedWeight(geo, i, centres, k, minc[i], gmin);
      total += minc[i];
    }
    if (!(total > 0.0)) break;  // every proposal is already a centre
    double r = std::uniform_real_distribution<double>(0.0, total)(rng);
    std::int32_t pick = -1;
    for (std::int32_t i = 0; i < n; ++i) {
      if (!(minc[i] > 0.0)) continue;
      pick = i;  // the last positive-weight vertex absorbs rounding
      r -= minc[i];
      if (r < 0.0) break;
    }
    centres.insert(centres.end(), &geo.S[geo.At(pick)], &geo.S[geo.At(pick)] + D);
  }
  return centres;
}

// Lloyd iterations from `centres` (updated in place); returns the total cost of the last assignment.
double Lloyd(const SplitGeometry& geo, std::vector<double>& centres, std::vector<char>& lab) {
  const int D = geo.cx.D;
  int K = static_cast<int>(centres.size()) / D;
  double total = 0.0;
  for (int iter = 0; iter <= geo.cx.opt.split_values_iter_num; ++iter) {
    total = 0.0;
    for (std::int32_t i = 0; i < geo.n; ++i) {
      int arg = 0;
      double bc = kInf;
      for (int k = 0; k < K; ++k) {
        const double ck = geo.Cost(i, &centres[static_cast<std::size_t>(k) * D]);
        if (ck < bc) { bc = ck; arg = k; }
      }
      lab[i] = static_cast<char>(arg);
      total += bc;
    }
    if (iter == geo.cx.opt.split_values_iter_num) break;
    std::vector<double> next;
    for (int k = 0; k < K; ++k) {
      std::vector<double> z(D);
      if (geo.Centre(lab, k, z.data())) next.insert(next.end(), z.begin(), z.end());
    }
    centres.swap(next);
    K = static_cast<int>(centres.size()) / D;
  }
  return total;
}

// The best clustering of split_values_init_num restarts; fewer than two centres means no split.
std::vector<double> BestCentres(const SplitGeometry& geo, std::int32_t smallest_vertex) {
  std::mt19937_64 rng(0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(smallest_vertex));
  std::vector<double> best_centres;
  double best_total = kInf;
  std::vector<char> lab(geo.n);
  for (int restart = 0; restart < std::max(1, geo.cx.opt.split_values_init_num); ++restart) {
    std::vector<double> centres = SeedCentres(geo, rng);
    const double total = Lloyd(geo, centres, lab);
    if (total < best_total || best_centres.empty()) {
      best_total = total;
      best_centres = centres;
    }
  }
  return best_centres;
}

// Binary min cut between directions s0 and s1 (§4.4, K = 2) in split_iter_num damped rounds;
// label 1 (sink side) takes s1.
std::vector<char> CutBetween(const SplitGeometry& geo, std::int32_t c, const std::vector<std::int32_t>& comp,
                             const std::vector<std::int32_t>& verts, const std::vector<std::int32_t>& local,
                             std::vector<double>& s0, std::vector<double>& s1, MaxFlow& mf) {
  const Context& cx = geo.cx;
  const std::int32_t n = geo.n;
  std::vector<char> cut_label(n, 0);
  const int rounds = std::max(1, cx.opt.split_iter_num);
  for (int round = 0; round < rounds; ++round) {
    const double damping = cx.opt.split_damp_ratio + (1.0 - cx.opt.split_damp_ratio) * (round + 1) / rounds;
    double diff_norm = 0.0;
    for (int d = 0; d < cx.D; ++d) diff_norm += cx.m[d] * std::fabs(s0[d] - s1[d]);
    mf.Reset(n);
    for (std::int32_t i = 0; i < n; ++i) {
      const double c0 = geo.Cost(i, s0.data()), c1 = geo.Cost(i, s1.data());
      mf.AddUnary(i, !std::isfinite(c1) ? kBigCap : !std::isfinite(c0) ? -kBigCap : c1 - c0);
      const std::int32_t v = verts[i];
      for (std::int64_t e = cx.pb.first_edge[v]; e < cx.pb.first_edge[v + 1]; ++e) {
        const std::int32_t u = cx.pb.adj_vertices[e];
        if (comp[u] != c || u == v) continue;
        const double cap = damping * cx.pb.edge_weights[e] * diff_norm;
        if (cap > 0.0) mf.AddEdge(i, local[u], cap, cap);
      }
    }
    mf.Solve();
    bool changed = false;
    for (std::int32_t i = 0; i < n; ++i) {
      const char l = mf.SourceSide(i) ? 0 : 1;
      if (l != cut_label[i]) changed = true;
      cut_label[i] = l;
    }
    if (round + 1 == rounds || (!changed && round > 0)) break;
    if (!geo.Centre(cut_label, 0, s0.data()) || !geo.Centre(cut_label, 1, s1.data())) break;
  }
  return cut_label;
}

}  // namespace

bool SplitComponent(const Context& cx, std::int32_t c, const std::vector<std::int32_t>& comp,
                    const std::vector<double>& rX, const std::vector<std::int32_t>& verts,
                    const std::vector<std::int32_t>& local, std::vector<char>& label, MaxFlow& mf) {
  const int D = cx.D;
  if (verts.size() < 2) return false;
  const SplitGeometry geo = MakeGeometry(cx, c, comp, rX, verts);
  const std::vector<double> centres = BestCentres(geo, verts[0]);
  if (static_cast<int>(centres.size()) / D < 2) return false;
  std::vector<double> s0(centres.begin(), centres.begin() + D), s1(centres.begin() + D, centres.begin() + 2 * D);
  if (std::equal(s0.begin(), s0.end(), s1.begin())) return false;
  const std::vector<char> cut_label = CutBetween(geo, c, comp, verts, local, s0, s1, mf);
  bool split = false;
  for (std::size_t i = 0; i < verts.size(); ++i) {
    label[verts[i]] = cut_label[i];
    if (cut_label[i] != cut_label[0]) split = true;
  }
  return split;
}

}  // namespace al::cp
