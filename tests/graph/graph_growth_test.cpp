// A later round of candidate growth (GrowRefineGraph, KnnWithAddedPoints) must give the graph a
// fresh build gives: the same nodes, edges, weights and observations, bit for bit, on scenes with
// duplicates, huge spheres, zero-norm features, non-finite rows, far-away seeds and ties, and for
// 1 and 2 threads.
#include <omp.h>

#include <algorithm>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "al/graph/graph.hpp"
#include "al/graph/knn.hpp"
#include "graph_test_util.hpp"

namespace {

void ExpectSameGraph(const al::GraphResult& a, const al::GraphResult& b) {
  const al::RefineProblem &p = a.problem, &q = b.problem;
  ASSERT_EQ(p.node_ids, q.node_ids);
  EXPECT_EQ(p.first_edge, q.first_edge);
  EXPECT_EQ(p.adj_vertices, q.adj_vertices);
  EXPECT_EQ(p.edge_weights, q.edge_weights);  // bit-identical
  EXPECT_EQ(p.y_remove, q.y_remove);
  EXPECT_EQ(a.zero_norm, b.zero_norm);
  EXPECT_EQ(a.stats.edges_knn, b.stats.edges_knn);
  EXPECT_EQ(a.stats.components, b.stats.components);
  EXPECT_EQ(a.stats.added_per_hop, b.stats.added_per_hop);
  EXPECT_EQ(a.stats.huge_spheres, b.stats.huge_spheres);
  EXPECT_EQ(a.stats.sigma_x, b.stats.sigma_x);
  EXPECT_EQ(a.stats.prior.ToJson(), b.stats.prior.ToJson());
  EXPECT_EQ(a.stats.second_object.ToJson(), b.stats.second_object.ToJson());
}

// Every `stride`-th kept candidate of the graph, as extra seeds on top of `seeds`.
std::vector<std::uint8_t> MoreSeeds(const al::GraphResult& g, const std::vector<bool>& removed,
                                    std::vector<std::uint8_t> seeds, int stride) {
  int t = 0;
  for (std::int64_t id : g.problem.node_ids)
    if (!removed[std::size_t(id)] && ++t % stride == 0) seeds[std::size_t(id)] = 1;
  return seeds;
}

TEST(GraphGrowth, TwoRoundsEqualFreshBuilds) {
  al::test::GraphScene g = al::test::MakeGraphScene(4000, 21, 8, 3, 40);
  al::GraphOptions o;
  al::GraphResult grown = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  std::vector<std::uint8_t> seeds(g.removed.size(), 0);
  for (int round = 0; round < 3; ++round) {
    seeds = MoreSeeds(grown, g.removed, seeds, 5 - round);
    const al::GraphResult fresh = al::BuildRefineGraph(g.scene, g.features, g.removed, o, &seeds);
    grown = al::GrowRefineGraph(g.scene, g.features, g.removed, o, std::move(grown), seeds);
    ExpectSameGraph(grown, fresh);
    EXPECT_GT(grown.problem.num_nodes(), 0u);
  }
}

// NewCandidateRows (the refine stages' "few new candidates" stop) names exactly the nodes the
// grown graph adds, and changes nothing it is asked about.
TEST(GraphGrowth, NewCandidateRowsAreTheNodesGrowthAdds) {
  al::test::GraphScene g = al::test::MakeGraphScene(4000, 24, 8, 3, 40);
  al::GraphOptions o;
  al::GraphResult grown = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  std::vector<std::uint8_t> seeds(g.removed.size(), 0);
  EXPECT_TRUE(al::NewCandidateRows(grown, seeds)->empty());
  EXPECT_FALSE(al::NewCandidateRows(grown, std::vector<std::uint8_t>(3, 1)).has_value());  // wrong size
  for (int stride : {7, 2}) {
    seeds = MoreSeeds(grown, g.removed, seeds, stride);
    const std::vector<std::int64_t> rows = *al::NewCandidateRows(grown, seeds);
    EXPECT_EQ(*al::NewCandidateRows(grown, seeds), rows);
    std::vector<std::int64_t> before = grown.problem.node_ids;
    const al::GraphResult fresh = al::BuildRefineGraph(g.scene, g.features, g.removed, o, &seeds);
    grown = al::GrowRefineGraph(g.scene, g.features, g.removed, o, std::move(grown), seeds, &rows);  // not searched again
    ExpectSameGraph(grown, fresh);
    std::vector<std::int64_t> added;
    std::set_difference(grown.problem.node_ids.begin(), grown.problem.node_ids.end(), before.begin(), before.end(),
                        std::back_inserter(added));
    EXPECT_EQ(rows, added);
    EXPECT_FALSE(rows.empty());
    EXPECT_TRUE(al::NewCandidateRows(grown, seeds)->empty());  // nothing left to grow from them
  }
  al::GraphResult none;
  EXPECT_FALSE(al::NewCandidateRows(none, seeds).has_value());  // no growth state kept
}

TEST(GraphGrowth, ZeroNormNonFiniteDuplicatesAndAFarSeed) {
  al::test::GraphScene g = al::test::MakeGraphScene(3000, 22, 6, 2, 60);
  // A far cluster of exact duplicates that only a grown seed reaches, zero-norm and non-finite rows.
  for (int i = 2900; i < 3000; ++i) {
    g.scene.means.row(i) << 100.f, 100.f, float(i % 3);
    g.removed[std::size_t(i)] = false;
    if (i % 10 == 0) g.features.row(i).setZero();
  }
  g.scene.means(2950, 0) = NAN;
  for (int i = 0; i < 2900; i += 97) g.features.row(i).setZero();
  al::GraphOptions o;
  o.centre = al::Centring::kOn;
  const al::GraphResult first = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  std::vector<std::uint8_t> seeds = MoreSeeds(first, g.removed, std::vector<std::uint8_t>(3000, 0), 3);
  seeds[2901] = 1;  // not a candidate: it still grows the set (a caller's choice)
  const al::GraphResult fresh = al::BuildRefineGraph(g.scene, g.features, g.removed, o, &seeds);
  const al::GraphResult grown = al::GrowRefineGraph(g.scene, g.features, g.removed, o, first, seeds);
  ExpectSameGraph(grown, fresh);
  // `first` was copied, not consumed: growing from it again gives the same graph.
  ExpectSameGraph(al::GrowRefineGraph(g.scene, g.features, g.removed, o, first, seeds), fresh);
}

TEST(GraphGrowth, NoFreshSeedHopsAndThreads) {
  al::test::GraphScene g = al::test::MakeGraphScene(2500, 23);
  al::GraphOptions o;
  const al::GraphResult first = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  const std::vector<std::uint8_t> none(2500, 0);
  ExpectSameGraph(al::GrowRefineGraph(g.scene, g.features, g.removed, o, first, none), first);
  const std::vector<std::uint8_t> seeds = MoreSeeds(first, g.removed, none, 4);
  const al::GraphResult fresh = al::BuildRefineGraph(g.scene, g.features, g.removed, o, &seeds);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const al::GraphResult one = al::GrowRefineGraph(g.scene, g.features, g.removed, o, first, seeds);
  omp_set_num_threads(2);
  const al::GraphResult two = al::GrowRefineGraph(g.scene, g.features, g.removed, o, first, seeds);
  omp_set_num_threads(threads);
  ExpectSameGraph(one, fresh);
  ExpectSameGraph(two, fresh);
  o.hops = 2;  // not incremental: built anew, the same graph
  const al::GraphResult first2 = al::BuildRefineGraph(g.scene, g.features, g.removed, o);
  ExpectSameGraph(al::GrowRefineGraph(g.scene, g.features, g.removed, o, first2, seeds),
                  al::BuildRefineGraph(g.scene, g.features, g.removed, o, &seeds));
}

// Points on a small integer grid (many equal distances) with duplicates, grown in steps.
// n = 3000 searches one tree, n = 70000 two (KnnAmongPoints splits sets above 65,536 points).
TEST(KnnWithAddedPoints, EqualsAFreshSearchWithTiesAndDuplicates) {
  for (const int n : {3000, 70000}) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> cell(0, n > 3000 ? 40 : 12);
  std::vector<float> xyz;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) xyz.push_back(float(cell(rng)) * (a == 2 ? 1e-6f : 1.0f));
  for (int k : {1, 4, 10}) {
    al::KnnOptions ko;
    ko.k = k;
    // The old points: every index not divisible by 7 (or by 3 for the second case).
    for (int mod : {7, 3}) {
      std::vector<float> old_xyz;
      std::vector<std::int32_t> new_of_old, added;
      for (int i = 0; i < n; ++i) {
        if (i % mod == 0) { added.push_back(i); continue; }
        new_of_old.push_back(i);
        old_xyz.insert(old_xyz.end(), xyz.begin() + 3 * i, xyz.begin() + 3 * i + 3);
      }
      const al::KnnResult before = al::KnnAmongPoints(old_xyz, ko);
      const al::KnnResult after = al::KnnWithAddedPoints(xyz, before, new_of_old, added, ko);
      const al::KnnResult fresh = al::KnnAmongPoints(xyz, ko);
      EXPECT_EQ(after.k, fresh.k);
      EXPECT_EQ(after.neighbors, fresh.neighbors) << "k " << k << " mod " << mod;
      EXPECT_EQ(after.sq_dist, fresh.sq_dist);
    }
  }
  }
}

}  // namespace
