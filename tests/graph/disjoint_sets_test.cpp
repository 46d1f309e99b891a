// ConcurrentDisjointSets against the sequential DisjointSets: the same roots (each set's smallest
// member) for unions made by 1-8 threads in any interleaving.
#include "al/graph/disjoint_sets.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <random>
#include <utility>
#include <vector>

namespace al {
namespace {

std::vector<std::pair<std::int32_t, std::int32_t>> RandomEdges(std::int32_t n, std::size_t m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::int32_t> node(0, n - 1);
  std::vector<std::pair<std::int32_t, std::int32_t>> edges(m);
  for (auto& e : edges) e = {node(rng), node(rng)};
  return edges;
}

std::vector<std::int32_t> SequentialRoots(std::int32_t n, const std::vector<std::pair<std::int32_t, std::int32_t>>& edges) {
  DisjointSets sets{static_cast<std::size_t>(n)};
  for (const auto& [a, b] : edges) sets.Unite(a, b);
  std::vector<std::int32_t> root(static_cast<std::size_t>(n));
  for (std::int32_t v = 0; v < n; ++v) root[std::size_t(v)] = sets.Find(v);
  return root;
}

TEST(ConcurrentDisjointSets, SameRootsAsSequentialForAnyThreadCount) {
  // Sparse (many sets), near the giant-component threshold, and dense (one set).
  for (const std::size_t per_node : {0u, 1u, 3u}) {
    const std::int32_t n = 20000;
    const auto edges = RandomEdges(n, std::size_t(n) / 2 * (per_node + 1), 7 + unsigned(per_node));
    const std::vector<std::int32_t> expected = SequentialRoots(n, edges);
    for (const int threads : {1, 2, 3, 8}) {
      ConcurrentDisjointSets sets{static_cast<std::size_t>(n)};
      const auto m = static_cast<std::int64_t>(edges.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
      for (std::int64_t e = 0; e < m; ++e) sets.Unite(edges[std::size_t(e)].first, edges[std::size_t(e)].second);
      std::vector<std::int32_t> root(static_cast<std::size_t>(n));
#pragma omp parallel for num_threads(threads)
      for (std::int32_t v = 0; v < n; ++v) root[std::size_t(v)] = sets.Find(v);
      EXPECT_EQ(root, expected) << threads << " threads, " << edges.size() << " edges";
    }
  }
}

TEST(ConcurrentDisjointSets, RootIsTheSmallestMemberAndSelfUnionsAreNoOps) {
  ConcurrentDisjointSets sets(6);
  sets.Unite(5, 5);
  sets.Unite(5, 3);
  sets.Unite(4, 5);
  sets.Unite(1, 1);
  EXPECT_EQ(sets.Find(4), 3);
  EXPECT_EQ(sets.Find(5), 3);
  EXPECT_EQ(sets.Find(1), 1);
  EXPECT_EQ(sets.Find(0), 0);
  sets.Unite(4, 0);
  for (const std::int32_t v : {0, 3, 4, 5}) EXPECT_EQ(sets.Find(v), 0);
}

}  // namespace
}  // namespace al
