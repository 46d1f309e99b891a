// The kNN's exact kd-tree (src/graph/point_tree.hpp) against two independent answers: brute force
// over (float squared distance, index) and FLANN's exact KDTreeSingleIndex, which it replaced.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <flann/flann.hpp>
#include <gtest/gtest.h>

#include "src/graph/point_tree.hpp"
#include "tests/graph/clustered_points.hpp"

namespace al {
namespace {

float SqDist(const float* a, const float* b) {  // FLANN L2_3D's order
  float s = 0;
  for (int c = 0; c < 3; ++c) s += (a[c] - b[c]) * (a[c] - b[c]);
  return s;
}

std::vector<TreeNeighbor> BruteForce(const std::vector<float>& xyz, const float* q, std::size_t m, std::int32_t skip) {
  std::vector<TreeNeighbor> all;
  for (std::size_t j = 0; j < xyz.size() / 3; ++j)
    if (std::int32_t(j) != skip) all.push_back({SqDist(q, &xyz[3 * j]), std::int32_t(j)});
  std::sort(all.begin(), all.end(),
            [](const TreeNeighbor& a, const TreeNeighbor& b) { return a.d < b.d || (a.d == b.d && a.i < b.i); });
  if (all.size() > m) all.resize(m);
  return all;
}

void ExpectSameLists(const std::vector<TreeNeighbor>& got, const std::vector<TreeNeighbor>& want, const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t c = 0; c < got.size(); ++c) {
    ASSERT_EQ(got[c].i, want[c].i) << what << ", entry " << c;
    ASSERT_EQ(got[c].d, want[c].d) << what << ", entry " << c;  // the same float sums, bit for bit
  }
}

// Point sets the tree must get right: a lattice (ties everywhere, points on every split plane),
// clusters whose scales differ by many octaves at 1e-6 and 1e6 units, coincident piles, a line.
std::vector<std::vector<float>> HardSets() {
  std::vector<std::vector<float>> sets;
  std::mt19937 rng(5);
  std::vector<float> lattice;
  for (int i = 0; i < 3000; ++i) lattice.insert(lattice.end(), {float(i % 15), float((i / 15) % 20), float(i / 300)});
  sets.push_back(lattice);
  for (const double unit : {1e-6, 1e6}) sets.push_back(test_points::ClusteredPoints(5, 30, 80, 3.0, 30.0, unit));
  std::vector<float> piles;
  for (int i = 0; i < 1500; ++i) piles.insert(piles.end(), {float(rng() % 6), float(rng() % 6), 0.5f});
  sets.push_back(piles);
  std::vector<float> line;
  for (int i = 0; i < 1000; ++i) line.insert(line.end(), {float(i % 97) * 1e-3f, 2.0f, -1.0f});
  sets.push_back(line);
  return sets;
}

TEST(PointTree, ListsEqualBruteForceForAnyListLengthAndSkip) {
  for (const std::vector<float>& xyz : HardSets()) {
    const PointTree tree(xyz);
    const std::size_t n = xyz.size() / 3;
    ASSERT_EQ(tree.size(), n);
    std::vector<TreeNeighbor> got;
    for (std::size_t i = 0; i < n; i += 13)
      for (const std::size_t m : {std::size_t(1), std::size_t(10), std::size_t(40)}) {
        tree.Nearest(&xyz[3 * i], m, std::int32_t(i), got);
        ExpectSameLists(got, BruteForce(xyz, &xyz[3 * i], m, std::int32_t(i)), "self skipped");
        const float off[3] = {xyz[3 * i] + 0.37f, xyz[3 * i + 1] - 1.1f, xyz[3 * i + 2] * 2.0f};
        tree.Nearest(off, m, -1, got);  // a query that is not a point of the set
        ExpectSameLists(got, BruteForce(xyz, off, m, -1), "outside query");
      }
  }
}

// The order is a permutation, and the lists equal FLANN's exact tree's up to its tie order.
TEST(PointTree, AgreesWithFlannsExactTree) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  std::vector<float> xyz(3 * 20000);
  for (float& v : xyz) v = u(rng);
  const PointTree tree(xyz);
  std::vector<std::int32_t> order = tree.order();
  std::sort(order.begin(), order.end());
  for (std::size_t t = 0; t < order.size(); ++t) ASSERT_EQ(order[t], std::int32_t(t));
  flann::KDTreeSingleIndex<flann::L2_3D<float>> flann_tree(flann::Matrix<float>(xyz.data(), 20000, 3),
                                                           flann::KDTreeSingleIndexParams(10));
  flann_tree.buildIndex();
  std::vector<TreeNeighbor> got;
  for (std::size_t i = 0; i < 20000; i += 7) {
    tree.Nearest(&xyz[3 * i], 12, -1, got);
    flann::KNNSimpleResultSet<float> rs(12);
    flann_tree.findNeighbors(rs, &xyz[3 * i], flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED, 0, false));
    std::vector<std::size_t> idx(12);
    std::vector<float> dist(12);
    rs.copy(idx.data(), dist.data(), 12);
    for (int c = 0; c < 12; ++c) {  // random floats: no ties
      ASSERT_EQ(got[std::size_t(c)].i, std::int32_t(idx[std::size_t(c)])) << "point " << i;
      ASSERT_EQ(got[std::size_t(c)].d, dist[std::size_t(c)]) << "point " << i;
    }
  }
}

// Piles of three among distinct points: no leaf holds more than three at one position.
TEST(PointTree, SmallPilesStaySmallInLeaves) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> xyz;
  for (int i = 0; i < 3000; ++i) {
    const float p[3] = {u(rng), u(rng), u(rng)};
    for (int c = 0; c < (i % 10 == 0 ? 3 : 1); ++c) xyz.insert(xyz.end(), p, p + 3);
  }
  const PointTree tree(xyz);
  EXPECT_GE(tree.LargestPileInALeaf(), 1u);
  EXPECT_LE(tree.LargestPileInALeaf(), 3u);
}

TEST(PointTree, DegenerateSets) {
  std::vector<TreeNeighbor> got;
  const PointTree empty(std::vector<float>{});
  const float q[3] = {0, 0, 0};
  empty.Nearest(q, 5, -1, got);
  EXPECT_TRUE(got.empty());
  const std::vector<float> one = {1, 2, 3};
  const PointTree single(one);
  single.Nearest(q, 5, -1, got);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].i, 0);
  EXPECT_EQ(got[0].d, 14.0f);
  single.Nearest(one.data(), 5, 0, got);  // the only point skipped
  EXPECT_TRUE(got.empty());
  // 5000 copies of one point: every list is the smallest other indices at distance 0.
  const std::vector<float> pile(3 * 5000, 0.25f);
  const PointTree piled(pile);
  piled.Nearest(pile.data(), 4, 2, got);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ((std::vector<std::int32_t>{got[0].i, got[1].i, got[2].i, got[3].i}), (std::vector<std::int32_t>{0, 1, 3, 4}));
  EXPECT_GE(piled.LargestPileInALeaf(), 16u);  // a pile that fills leaves is seen
  EXPECT_EQ(single.LargestPileInALeaf(), 1u);
  // Coordinates whose squares overflow float: distances are inf, the order falls back to the index.
  const std::vector<float> far = {3e19f, 0, 0, -3e19f, 0, 0, 0, 3e19f, 0};
  const PointTree huge(far);
  huge.Nearest(q, 3, -1, got);
  ASSERT_EQ(got.size(), 3u);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(got[std::size_t(c)].i, c);
}

}  // namespace
}  // namespace al
