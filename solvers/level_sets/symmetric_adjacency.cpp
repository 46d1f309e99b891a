// Both directions of a forward-star graph (level_set_partition.hpp, SymmetricAdjacency). Every
// node's list is in the order of one sequential pass over the stored edges (source ascending, then
// edge): the level-set run numbers nodes by a breadth-first walk of these lists, so their order is
// part of the result. The refine problem's graphs store each edge at its smaller endpoint; for them
// the lists are built in parallel, in that same order.
#include "solvers/level_sets/level_set_partition.hpp"

#include <omp.h>

#include <algorithm>
#include <utility>

namespace al::levelset {
namespace {

// Entry k of `a` reached through stored edge e: its edge id, or its weight when built with weights.
void SetEntry(SymmetricAdjacency& a, std::span<const double> weights, std::int64_t k, std::int32_t v, std::int64_t e) {
  a.nbr[std::size_t(k)] = v;
  if (weights.empty()) a.edge[std::size_t(k)] = e;
  else a.weight[std::size_t(k)] = weights[std::size_t(e)];
}

void SizeEntries(SymmetricAdjacency& a, std::span<const double> weights) {
  const auto m = std::size_t(a.first.back());
  a.nbr.resize(m);
  if (weights.empty()) a.edge.resize(m);
  else a.weight.resize(m);
}

SymmetricAdjacency SequentialAdjacency(std::span<const std::int64_t> first_edge,
                                       std::span<const std::int32_t> adj_vertices, std::span<const double> weights) {
  const std::int64_t V = static_cast<std::int64_t>(first_edge.size()) - 1;
  SymmetricAdjacency a;
  a.first.assign(V + 1, 0);
  for (std::int64_t u = 0; u < V; ++u)
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
      ++a.first[u + 1];
      ++a.first[adj_vertices[e] + 1];
    }
  for (std::int64_t v = 0; v < V; ++v) a.first[v + 1] += a.first[v];
  SizeEntries(a, weights);
  std::vector<std::int64_t> pos(a.first.begin(), a.first.end() - 1);
  for (std::int64_t u = 0; u < V; ++u)
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
      const std::int32_t v = adj_vertices[e];
      SetEntry(a, weights, pos[u]++, v, e);
      SetEntry(a, weights, pos[v]++, static_cast<std::int32_t>(u), e);
    }
  return a;
}

// Every edge stored at its smaller endpoint: then node w's list is its reverse entries (sources
// below w, ascending) followed by its own stored edges, which the parallel build reproduces.
bool StoredAtSmallerEnd(std::span<const std::int64_t> first_edge, std::span<const std::int32_t> adj_vertices) {
  const std::int64_t V = static_cast<std::int64_t>(first_edge.size()) - 1;
  bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
  for (std::int64_t u = 0; u < V; ++u)
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) ok = ok && adj_vertices[e] > u;
  return ok;
}

// The parallel build: the sources in `parts` ranges, each range's reverse entries into a node after
// those of the ranges below it (per-range counts give the offsets).
SymmetricAdjacency ParallelAdjacency(std::span<const std::int64_t> first_edge,
                                     std::span<const std::int32_t> adj_vertices, std::span<const double> weights,
                                     int parts) {
  const std::int64_t V = static_cast<std::int64_t>(first_edge.size()) - 1;
  SymmetricAdjacency a;
  a.first.assign(V + 1, 0);
  std::vector<std::vector<std::int64_t>> at(std::size_t(parts), std::vector<std::int64_t>(std::size_t(V), 0));
  auto range = [&](int t) { return std::pair{V * t / parts, V * (t + 1) / parts}; };
  // A loop over the ranges (not over thread ids): every range is done even with fewer threads.
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t) {
    const auto [u0, u1] = range(t);
    std::vector<std::int64_t>& mine = at[std::size_t(t)];
    for (std::int64_t e = first_edge[u0]; e < first_edge[u1]; ++e) ++mine[std::size_t(adj_vertices[e])];
  }
  // Node w's reverse entries start at first[w]; range t's after those of the ranges below t.
  for (std::int64_t w = 0; w < V; ++w) {
    std::int64_t reverse = 0;
    for (auto& counts : at) reverse += std::exchange(counts[std::size_t(w)], reverse);
    a.first[w + 1] = a.first[w] + reverse + (first_edge[w + 1] - first_edge[w]);
  }
  SizeEntries(a, weights);
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t) {
    const auto [u0, u1] = range(t);
    std::vector<std::int64_t>& offset = at[std::size_t(t)];
    for (std::int64_t u = u0; u < u1; ++u) {
      // u's own edges follow all its reverse entries (every source of one is below u).
      std::int64_t own = a.first[u + 1] - (first_edge[u + 1] - first_edge[u]);
      for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
        const std::int32_t v = adj_vertices[e];
        SetEntry(a, weights, own++, v, e);
        SetEntry(a, weights, a.first[v] + offset[std::size_t(v)]++, static_cast<std::int32_t>(u), e);
      }
    }
  }
  return a;
}

}  // namespace

SymmetricAdjacency BuildSymmetricAdjacency(std::span<const std::int64_t> first_edge,
                                           std::span<const std::int32_t> adj_vertices,
                                           std::span<const double> edge_weights) {
  const int threads = std::min(omp_get_max_threads(), 8);
  if (threads < 2 || adj_vertices.size() < (1u << 16) || !StoredAtSmallerEnd(first_edge, adj_vertices))
    return SequentialAdjacency(first_edge, adj_vertices, edge_weights);
  return ParallelAdjacency(first_edge, adj_vertices, edge_weights, threads);
}

}  // namespace al::levelset
