// Both directions of a forward-star graph (level_set_partition.hpp, SymmetricAdjacency). Every
// node's list is in the order of one sequential pass over the stored edges (source ascending, then
// edge): the level-set run numbers nodes by a breadth-first walk of these lists, so their order is
// part of the result. The refine problem's graphs store each edge at its smaller endpoint; for them
// the lists are built in parallel, in that same order.
#include "solvers/level_sets/level_set_partition.hpp"

#include "al/core/range_scatter.hpp"

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

// The parallel build (edges stored at their smaller end): a node's reverse entries, scattered by
// ranges of sources (RangeScatter), then its own stored edges.
SymmetricAdjacency ParallelAdjacency(std::span<const std::int64_t> first_edge,
                                     std::span<const std::int32_t> adj_vertices, std::span<const double> weights,
                                     int parts) {
  const std::int64_t V = static_cast<std::int64_t>(first_edge.size()) - 1;
  SymmetricAdjacency a;
  a.first.assign(V + 1, 0);
  RangeScatter scatter(V, std::size_t(V), parts);
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t) {
    const auto [u0, u1] = scatter.Range(t);
    for (std::int64_t e = first_edge[u0]; e < first_edge[u1]; ++e) scatter.Count(t, std::size_t(adj_vertices[e]));
  }
  for (std::int64_t w = 0; w < V; ++w)
    a.first[w + 1] = a.first[w] + scatter.Total(std::size_t(w)) + (first_edge[w + 1] - first_edge[w]);
  SizeEntries(a, weights);
#pragma omp parallel for schedule(static, 1) num_threads(parts)
  for (int t = 0; t < parts; ++t) {
    const auto [u0, u1] = scatter.Range(t);
    for (std::int64_t u = u0; u < u1; ++u) {
      // u's own edges follow all its reverse entries (every source of one is below u).
      std::int64_t own = a.first[u + 1] - (first_edge[u + 1] - first_edge[u]);
      for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) {
        const std::int32_t v = adj_vertices[e];
        SetEntry(a, weights, own++, v, e);
        SetEntry(a, weights, a.first[v] + scatter.Next(t, std::size_t(v)), static_cast<std::int32_t>(u), e);
      }
    }
  }
  return a;
}

}  // namespace

SymmetricAdjacency BuildSymmetricAdjacency(std::span<const std::int64_t> first_edge,
                                           std::span<const std::int32_t> adj_vertices,
                                           std::span<const double> edge_weights) {
  const int threads = RangeScatter::DefaultParts();
  if (threads < 2 || adj_vertices.size() < (1u << 16) || !StoredAtSmallerEnd(first_edge, adj_vertices))
    return SequentialAdjacency(first_edge, adj_vertices, edge_weights);
  return ParallelAdjacency(first_edge, adj_vertices, edge_weights, threads);
}

}  // namespace al::levelset
