// BuildSymmetricAdjacency: every node's list in the order of one sequential pass over the stored
// edges (the level-set run's numbering walks these lists), whether it takes the parallel build
// (edges stored at their smaller endpoint, as the refine graph stores them) or the plain one.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <random>
#include <vector>

#include "solvers/level_sets/level_set_partition.hpp"

namespace al {
namespace {

struct Csr {
  std::vector<std::int64_t> first{0};
  std::vector<std::int32_t> adj;
};

// V nodes, about deg stored edges each, to random endpoints (above the source when upper).
Csr RandomCsr(std::int32_t V, int deg, bool upper, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Csr g;
  for (std::int32_t u = 0; u < V; ++u) {
    const int d = int(rng() % std::uint32_t(2 * deg + 1));
    for (int c = 0; c < d; ++c) {
      if (upper && u + 1 >= V) break;
      const std::int32_t lo = upper ? u + 1 : 0;
      g.adj.push_back(lo + std::int32_t(rng() % std::uint32_t(V - lo)));
    }
    g.first.push_back(std::int64_t(g.adj.size()));
  }
  return g;
}

// The definition: one pass over the stored edges, appending (v, e) to u's list and (u, e) to v's.
levelset::SymmetricAdjacency ByDefinition(const Csr& g) {
  const std::size_t V = g.first.size() - 1;
  std::vector<std::vector<std::pair<std::int32_t, std::int64_t>>> lists(V);
  for (std::size_t u = 0; u < V; ++u)
    for (std::int64_t e = g.first[u]; e < g.first[u + 1]; ++e) {
      lists[u].push_back({g.adj[std::size_t(e)], e});
      lists[std::size_t(g.adj[std::size_t(e)])].push_back({std::int32_t(u), e});
    }
  levelset::SymmetricAdjacency a;
  a.first.push_back(0);
  for (const auto& l : lists) {
    for (const auto& [v, e] : l) a.nbr.push_back(v), a.edge.push_back(e);
    a.first.push_back(std::int64_t(a.nbr.size()));
  }
  return a;
}

void ExpectSame(const levelset::SymmetricAdjacency& got, const levelset::SymmetricAdjacency& want) {
  EXPECT_EQ(got.first, want.first);
  EXPECT_EQ(got.nbr, want.nbr);
  EXPECT_EQ(got.edge, want.edge);
}

TEST(SymmetricAdjacency, ListsFollowOneSequentialPassForEveryThreadCount) {
  const int before = omp_get_max_threads();
  for (const bool upper : {true, false})
    for (const std::int32_t V : {0, 1, 7, 40000}) {
      const Csr g = RandomCsr(V, 5, upper, std::uint32_t(V) * 2 + upper);
      const levelset::SymmetricAdjacency want = ByDefinition(g);
      for (const int threads : {1, 2, 3, 8}) {
        omp_set_num_threads(threads);
        SCOPED_TRACE("V " + std::to_string(V) + " upper " + std::to_string(upper) + " threads " +
                     std::to_string(threads));
        ExpectSame(levelset::BuildSymmetricAdjacency(g.first, g.adj), want);
        // With weights: the same neighbours, each entry carrying its edge's weight, no edge ids.
        std::vector<double> weights(g.adj.size());
        for (std::size_t e = 0; e < weights.size(); ++e) weights[e] = 0.25 + double(e % 97);
        const levelset::SymmetricAdjacency w = levelset::BuildSymmetricAdjacency(g.first, g.adj, weights);
        EXPECT_EQ(w.first, want.first);
        EXPECT_EQ(w.nbr, want.nbr);
        EXPECT_TRUE(w.edge.empty());
        ASSERT_EQ(w.weight.size(), want.edge.size());
        for (std::size_t k = 0; k < w.weight.size(); ++k) ASSERT_EQ(w.weight[k], weights[want.edge[k]]) << k;
      }
    }
  omp_set_num_threads(before);
}

TEST(SymmetricAdjacency, SelfLoopsAndRepeatedEdgesKeepTheirPlaces) {
  Csr g;  // 0-0 (self), 0-2 twice, 1-0 (stored at the larger end), 2-1
  g.adj = {0, 2, 2, 0, 1};
  g.first = {0, 3, 4, 5};
  ExpectSame(levelset::BuildSymmetricAdjacency(g.first, g.adj), ByDefinition(g));
}

}  // namespace
}  // namespace al
