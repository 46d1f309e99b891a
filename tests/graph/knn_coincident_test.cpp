// kNN with exactly coincident points (issue #14): grouped queries give the brute-force answer
// (ascending squared distance, ties by index, the query excluded by index) and stay fast.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "al/graph/knn.hpp"
#include "tests/graph/clustered_points.hpp"

namespace al {
namespace {

// The definition: every other point sorted by (float squared distance, index), first k.
std::vector<std::int32_t> BruteForce(const std::vector<float>& xyz, std::size_t i, int k) {
  const std::size_t n = xyz.size() / 3;
  std::vector<std::pair<float, std::int32_t>> all;
  for (std::size_t j = 0; j < n; ++j) {
    if (j == i) continue;
    float d = 0;
    for (int a = 0; a < 3; ++a) d += (xyz[3 * i + a] - xyz[3 * j + a]) * (xyz[3 * i + a] - xyz[3 * j + a]);
    all.push_back({d, static_cast<std::int32_t>(j)});
  }
  std::sort(all.begin(), all.end());
  std::vector<std::int32_t> out;
  for (int c = 0; c < k && c < int(all.size()); ++c) out.push_back(all[c].second);
  return out;
}

TEST(Knn, CoincidentGroupsGiveTheBruteForceAnswer) {
  // Piles of 1, 3 and 40 points at a few positions, on a coarse grid (many equal distances).
  std::mt19937 rng(3);
  std::vector<float> xyz;
  for (int g = 0; g < 60; ++g) {
    const float p[3] = {float(rng() % 5), float(rng() % 5), float(rng() % 3)};
    const int copies = g % 7 == 0 ? 40 : g % 3 == 0 ? 3 : 1;
    for (int c = 0; c < copies; ++c) xyz.insert(xyz.end(), p, p + 3);
  }
  std::shuffle(xyz.begin(), xyz.end(), rng);  // scramble coordinates: other piles, same multiset
  for (int k : {1, 5, 12}) {
    const KnnResult r = KnnAmongPoints(xyz, {k, 0});
    EXPECT_GT(r.coincident, 0u);
    for (std::size_t i = 0; i < xyz.size() / 3; ++i) {
      const auto expect = BruteForce(xyz, i, k);
      const std::vector<std::int32_t> got(r.neighbors.begin() + i * k, r.neighbors.begin() + i * k + expect.size());
      ASSERT_EQ(got, expect) << "point " << i << ", k = " << k;
    }
  }
}

// Above 65,536 points the exact search runs on two trees (the halves at the median of the longest
// axis, built in parallel): points on a grid, many on the splitting plane and at equal distances,
// with and without coincident piles, give the brute-force answer.
TEST(Knn, TwoHalfTreesGiveTheBruteForceAnswer) {
  for (const bool piles : {false, true}) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> cell(0, 60);
    std::vector<float> xyz;
    for (int i = 0; i < 90000; ++i) {  // piles: random cells (some shared); else a lattice (all distinct)
      const int lattice[3] = {i % 45, (i / 45) % 45, i / 2025};
      for (int a = 0; a < 3; ++a) xyz.push_back(piles ? float(cell(rng)) : float(lattice[a]));
    }
    const KnnResult r = KnnAmongPoints(xyz, {6, 0});
    EXPECT_EQ(r.coincident > 0, piles);
    for (std::size_t i = 0; i < 90000; i += 997) {
      const auto expect = BruteForce(xyz, i, 6);
      ASSERT_EQ(std::vector<std::int32_t>(r.neighbors.begin() + i * 6, r.neighbors.begin() + i * 6 + 6), expect)
          << "point " << i << (piles ? " (piles)" : "");
    }
  }
}

// Scales spread over many octaves (dense clumps beside sparse points), coordinates from 1e-6 to
// 1e6, and fewer points than k: lists and float distances equal brute force's.
TEST(Knn, ClusteredScalesAndTinySetsGiveTheBruteForceAnswer) {
  for (const double unit : {1e-6, 1.0, 1e6}) {
    const std::vector<float> xyz = test_points::ClusteredPoints(17, 40, 100, 2.5, 20.0, unit);
    for (int k : {1, 12}) {
      const KnnResult r = KnnAmongPoints(xyz, {k, 0});
      for (std::size_t i = 0; i < xyz.size() / 3; i += 7) {
        const auto expect = BruteForce(xyz, i, k);
        ASSERT_EQ(std::vector<std::int32_t>(r.neighbors.begin() + i * k, r.neighbors.begin() + (i + 1) * k), expect)
            << "point " << i << ", unit " << unit;
        for (int c = 0; c < k; ++c) {
          float d = 0;
          for (int a = 0; a < 3; ++a) {
            const float x = xyz[3 * i + a] - xyz[3 * std::size_t(expect[c]) + a];
            d += x * x;
          }
          ASSERT_EQ(r.sq_dist[i * k + c], d);
        }
      }
    }
  }
  for (std::size_t n : {1u, 2u, 3u}) {  // k is cut to n - 1
    std::vector<float> xyz;
    for (std::size_t i = 0; i < n; ++i) xyz.insert(xyz.end(), {float(i), 0.f, float(n - i)});
    const KnnResult r = KnnAmongPoints(xyz, {10, 0});
    EXPECT_EQ(r.k, int(n) - 1);
    for (std::size_t i = 0; i < n; ++i)
      EXPECT_EQ(std::vector<std::int32_t>(r.neighbors.begin() + i * r.k, r.neighbors.begin() + (i + 1) * r.k),
                BruteForce(xyz, i, r.k));
  }
}

TEST(Knn, OneHundredThousandCoincidentPoints) {
  // Time is checked by cli.reliability_degenerate (100k coincident Gaussians refined in < 5 s).
  std::vector<float> xyz(3 * 100000, 0.5f);
  const KnnResult r = KnnAmongPoints(xyz, {10, 0});
  EXPECT_EQ(r.coincident, 99999u);
  // Ties go to the smaller index: point i's neighbours are 0..10 without i.
  for (std::size_t i : {0u, 5u, 99999u}) {
    std::vector<std::int32_t> expect;
    for (std::int32_t j = 0; int(expect.size()) < 10; ++j)
      if (std::size_t(j) != i) expect.push_back(j);
    EXPECT_EQ(std::vector<std::int32_t>(r.neighbors.begin() + i * 10, r.neighbors.begin() + i * 10 + 10), expect);
  }
}

}  // namespace
}  // namespace al
