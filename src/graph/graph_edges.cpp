// The graph's edges from its kNN lists (SPEC §4.4-4.6): unique pairs at the smaller node, their
// feature distances (reused across growth rounds), the gate and the weights. Parallel loops write
// per-node slots only; counts are summed in node order: thread-count independent.
#include <algorithm>
#include <cmath>

#include "al/core/first_touch.hpp"
#include "al/core/range_scatter.hpp"
#include "src/graph/graph_internal.hpp"

namespace al::graph_internal {
namespace {

double FeatureDistance(const RowMatXf& nf, std::int64_t u, std::int64_t v) {
  const float* fu = nf.row(u).data();
  const float* fv = nf.row(v).data();
  double df2 = 0;
  for (Eigen::Index d = 0; d < nf.cols(); ++d) {
    const double t = double(fu[d]) - double(fv[d]);
    df2 += t * t;
  }
  return df2;
}

// The previous round's distance of the pair (a, b), a < b in its numbering; NaN when it had no such pair.
double Cached(const PairCache& previous, std::int32_t a, std::int32_t b) {
  const auto first = previous.other.begin() + previous.row_start[std::size_t(a)];
  const auto last = previous.other.begin() + previous.row_start[std::size_t(a) + 1];
  const auto it = std::lower_bound(first, last, b);
  return it != last && *it == b ? previous.df2[std::size_t(it - previous.other.begin())] : std::nan("");
}

// The kNN entries scattered to the row of their smaller end (each row's entries unsorted, with
// repeats) in `all`, rows starting at `start`, by ranges of rows on all threads (RangeScatter).
void ScatterToSmallerEnd(const KnnResult& knn, std::size_t V, std::vector<std::int64_t>& start,
                         std::vector<std::int32_t>& all) {
  const int K = knn.k;
  RangeScatter scatter(std::int64_t(V), V, RangeScatter::DefaultParts());
  // Each kNN entry (u, v) of range t's rows, as (its row, the other end).
  auto for_each_entry = [&](int t, const auto& f) {
    const auto [u0, u1] = scatter.Range(t);
    for (auto u = std::size_t(u0); u < std::size_t(u1); ++u)
      for (int c = 0; c < K; ++c)
        if (const std::int32_t v = knn.neighbors[u * std::size_t(K) + std::size_t(c)]; v >= 0)
          f(std::min<std::size_t>(u, std::size_t(v)), std::int32_t(std::max<std::size_t>(u, std::size_t(v))));
  };
#pragma omp parallel for schedule(static, 1) num_threads(scatter.parts())
  for (int t = 0; t < scatter.parts(); ++t) for_each_entry(t, [&](std::size_t w, std::int32_t) { scatter.Count(t, w); });
  start.assign(V + 1, 0);
  for (std::size_t w = 0; w < V; ++w) start[w + 1] = start[w] + scatter.Total(w);
  ReserveFirstTouched(all, std::size_t(start[V]));  // big arrays: pages faulted on all threads (first_touch.hpp)
  all.resize(std::size_t(start[V]));
#pragma omp parallel for schedule(static, 1) num_threads(scatter.parts())
  for (int t = 0; t < scatter.parts(); ++t)
    for_each_entry(t, [&](std::size_t w, std::int32_t other) { all[std::size_t(start[w] + scatter.Next(t, w))] = other; });
}

}  // namespace

PairCache UniquePairs(const KnnResult& knn, std::size_t V) {
  PairCache pc{std::vector<std::int64_t>(V + 1, 0), {}, {}};
  std::vector<std::int64_t> start;
  std::vector<std::int32_t> all;
  ScatterToSmallerEnd(knn, V, start, all);
  std::vector<std::int64_t> count(V, 0);
  const auto vv = static_cast<std::int64_t>(V);
#pragma omp parallel for schedule(dynamic, 2048)
  for (std::int64_t u = 0; u < vv; ++u) {
    auto* b = all.data() + start[u];
    auto* e = all.data() + start[u + 1];
    std::sort(b, e);
    count[u] = std::unique(b, e) - b;
  }
  for (std::size_t u = 0; u < V; ++u) pc.row_start[u + 1] = pc.row_start[u] + count[u];
  ReserveFirstTouched(pc.other, std::size_t(pc.row_start[V]));
  pc.other.resize(std::size_t(pc.row_start[V]));
#pragma omp parallel for schedule(static)
  for (std::int64_t u = 0; u < vv; ++u)
    std::copy_n(all.begin() + start[u], count[u], pc.other.begin() + pc.row_start[u]);
  return pc;
}

namespace {

// Squared feature distances of row u to rows v[0..4), four sums side by side: each still adds its
// dimensions in order (the same double as FeatureDistance), but the four chains overlap instead
// of waiting on one another.
void FeatureDistances4(const RowMatXf& nf, std::int64_t u, const std::int32_t* v, double* out) {
  const float* fu = nf.row(u).data();
  const float* f[4] = {nf.row(v[0]).data(), nf.row(v[1]).data(), nf.row(v[2]).data(), nf.row(v[3]).data()};
  double s[4] = {0, 0, 0, 0};
  for (Eigen::Index d = 0; d < nf.cols(); ++d)
    for (int j = 0; j < 4; ++j) {
      const double t = double(fu[d]) - double(f[j][d]);
      s[j] += t * t;
    }
  for (int j = 0; j < 4; ++j) out[j] = s[j];
}

// The pairs of row u that need a distance computed (both ends with a feature, no cached value),
// four at a time.
void ComputeRow(PairCache& pc, const RowMatXf& nf, std::int64_t u, std::vector<std::int64_t>& todo) {
  std::size_t t = 0;
  for (; t + 4 <= todo.size(); t += 4) {
    std::int32_t v[4];
    double d[4];
    for (int j = 0; j < 4; ++j) v[j] = pc.other[std::size_t(todo[t + std::size_t(j)])];
    FeatureDistances4(nf, u, v, d);
    for (int j = 0; j < 4; ++j) pc.df2[std::size_t(todo[t + std::size_t(j)])] = d[j];
  }
  for (; t < todo.size(); ++t) pc.df2[std::size_t(todo[t])] = FeatureDistance(nf, u, pc.other[std::size_t(todo[t])]);
  todo.clear();
}

}  // namespace

void PairDistances(PairCache& pc, const RowMatXf& nf, const std::vector<std::uint8_t>& zero_norm,
                   const PairCache* previous, const std::vector<std::int32_t>* old_of) {
  const auto V = static_cast<std::int64_t>(pc.row_start.size()) - 1;
  ReserveFirstTouched(pc.df2, pc.other.size());
  pc.df2.resize(pc.other.size());
#pragma omp parallel
  {
    std::vector<std::int64_t> todo;
#pragma omp for schedule(dynamic, 2048)
    for (std::int64_t u = 0; u < V; ++u) {
      for (std::int64_t e = pc.row_start[u]; e < pc.row_start[u + 1]; ++e) {
        const std::int32_t v = pc.other[std::size_t(e)];
        if (zero_norm[std::size_t(u)] || zero_norm[std::size_t(v)]) {
          pc.df2[std::size_t(e)] = -1.0;
          continue;
        }
        double d = std::nan("");
        if (previous && (*old_of)[std::size_t(u)] >= 0 && (*old_of)[std::size_t(v)] >= 0)
          d = Cached(*previous, (*old_of)[std::size_t(u)], (*old_of)[std::size_t(v)]);
        if (std::isnan(d)) todo.push_back(e);
        else pc.df2[std::size_t(e)] = d;
      }
      ComputeRow(pc, nf, u, todo);
    }
  }
}

void GateAndWeigh(const PairCache& pc, const std::vector<float>& node_xyz, double gate, const GraphOptions& options,
                  RefineProblem& P, GraphStats& st) {
  const std::size_t V = P.node_ids.size();
  const double sf2 = st.sigma_f * st.sigma_f, sx2 = st.sigma_x * st.sigma_x;
  std::vector<std::int64_t> kept(V, 0);
  const auto vv = static_cast<std::int64_t>(V);
#pragma omp parallel for schedule(dynamic, 2048)
  for (std::int64_t u = 0; u < vv; ++u)
    for (std::int64_t e = pc.row_start[u]; e < pc.row_start[u + 1]; ++e)
      kept[u] += pc.df2[std::size_t(e)] >= 0.0 && std::sqrt(pc.df2[std::size_t(e)]) <= gate;
  P.first_edge.assign(V + 1, 0);
  for (std::size_t u = 0; u < V; ++u) P.first_edge[u + 1] = P.first_edge[u] + kept[u];
  st.edges_knn = pc.other.size();
  ReserveFirstTouched(P.adj_vertices, std::size_t(P.first_edge[V]));
  ReserveFirstTouched(P.edge_weights, std::size_t(P.first_edge[V]));
  P.adj_vertices.resize(std::size_t(P.first_edge[V]));
  P.edge_weights.resize(std::size_t(P.first_edge[V]));
#pragma omp parallel for schedule(dynamic, 2048)
  for (std::int64_t u = 0; u < vv; ++u) {
    std::int64_t at = P.first_edge[u];
    for (std::int64_t e = pc.row_start[u]; e < pc.row_start[u + 1]; ++e) {
      const double df2 = pc.df2[std::size_t(e)];
      if (!(df2 >= 0.0 && std::sqrt(df2) <= gate)) continue;
      const std::int32_t v = pc.other[std::size_t(e)];
      // Both kernels in one exponential (4M edges at 3M: two calls were half the gate's time).
      double exponent = sf2 > 0 ? -df2 / sf2 : 0.0;
      if (options.spatial && sx2 > 0) exponent -= SquaredDistance(node_xyz, std::size_t(u), std::size_t(v)) / sx2;
      const double w = options.Lambda() * std::exp(exponent);
      P.adj_vertices[std::size_t(at)] = v;
      P.edge_weights[std::size_t(at++)] = w;
    }
  }
  st.edges = P.adj_vertices.size();
}

}  // namespace al::graph_internal
