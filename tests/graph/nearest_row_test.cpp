// NearestRowTree (src/graph/nearest_row.hpp) against a brute-force scan that uses the same float
// distance and the same tie rule: random clouds with near and far queries, coincident rows
// (ties decided by the smaller row), degenerate layouts (every row on one point, a plane, a line),
// coordinate scales from 1e-6 to 1e6, rows with non-finite positions and an empty row set.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "src/graph/nearest_row.hpp"

namespace {

struct Brute {
  std::int64_t row = -1;
  float sq_dist = std::numeric_limits<float>::infinity();
};

Brute BruteNearest(const std::vector<float>& xyz, const std::vector<std::int64_t>& rows, const float* p) {
  Brute best;
  for (std::int64_t r : rows) {
    const float* q = &xyz[3 * std::size_t(r)];
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2])) continue;
    float d = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float diff = q[a] - p[a];
      d += diff * diff;
    }
    if (d < best.sq_dist || (d == best.sq_dist && r < best.row)) best = {r, d};
  }
  return best;
}

// Every query's answer equals the scan's, and index points back at the row in `rows`.
void ExpectSameAsBrute(const std::vector<float>& xyz, const std::vector<std::int64_t>& rows,
                       const std::vector<float>& queries) {
  const al::NearestRowTree tree(xyz, rows);
  for (std::size_t q = 0; q < queries.size() / 3; ++q) {
    const float* p = &queries[3 * q];
    const Brute want = BruteNearest(xyz, rows, p);
    const al::NearestRowTree::Hit got = tree.Nearest(p);
    ASSERT_EQ(got.row, want.row) << "query " << q;
    ASSERT_EQ(got.sq_dist, want.sq_dist) << "query " << q;
    if (got.row >= 0) {
      ASSERT_EQ(rows[got.index], got.row);
    }
  }
}

std::vector<float> Uniform(std::mt19937& rng, std::size_t n, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(3 * n);
  for (float& x : v) x = u(rng);
  return v;
}

TEST(NearestRowTree, MatchesBruteForceNearAndFar) {
  std::mt19937 rng(3);
  const std::vector<float> xyz = Uniform(rng, 5000, 0.0f, 1.0f);
  std::vector<std::int64_t> rows;  // every third row, unsorted
  for (std::int64_t r = 4999; r >= 0; r -= 3) rows.push_back(r);
  std::vector<float> queries = Uniform(rng, 300, -0.2f, 1.2f);
  const std::vector<float> far = Uniform(rng, 300, -50.0f, 50.0f);  // mostly far outside the cloud
  queries.insert(queries.end(), far.begin(), far.end());
  ExpectSameAsBrute(xyz, rows, queries);
}

TEST(NearestRowTree, CoincidentRowsTieToTheSmallestRow) {
  std::mt19937 rng(5);
  std::vector<float> xyz = Uniform(rng, 2000, 0.0f, 1.0f);
  // 200 rows on one point and 100 on another, more than a leaf holds.
  for (std::size_t r = 100; r < 300; ++r) xyz[3 * r] = xyz[3 * r + 1] = xyz[3 * r + 2] = 0.5f;
  for (std::size_t r = 1000; r < 1100; ++r) xyz[3 * r] = 0.25f, xyz[3 * r + 1] = 0.75f, xyz[3 * r + 2] = 0.1f;
  std::vector<std::int64_t> rows(2000);
  for (std::size_t r = 0; r < rows.size(); ++r) rows[r] = std::int64_t(rows.size() - 1 - r);
  std::vector<float> queries = {0.5f, 0.5f, 0.5f, 0.25f, 0.75f, 0.1f, 0.5f, 0.5f, 0.6f, 9.0f, 9.0f, 9.0f};
  ExpectSameAsBrute(xyz, rows, queries);
  const al::NearestRowTree tree(xyz, rows);
  EXPECT_EQ(tree.Nearest(&queries[0]).row, 100);
  EXPECT_EQ(tree.Nearest(&queries[3]).row, 1000);
}

TEST(NearestRowTree, DegenerateLayouts) {
  std::mt19937 rng(11);
  std::vector<std::int64_t> rows(1500);
  for (std::size_t r = 0; r < rows.size(); ++r) rows[r] = std::int64_t(r);
  const std::vector<float> queries = Uniform(rng, 100, -2.0f, 2.0f);
  std::vector<float> point(3 * rows.size(), 0.3f);  // every row on one point
  ExpectSameAsBrute(point, rows, queries);
  std::vector<float> plane = Uniform(rng, rows.size(), -1.0f, 1.0f), line = plane;
  for (std::size_t r = 0; r < rows.size(); ++r) plane[3 * r + 2] = 0.0f, line[3 * r + 1] = line[3 * r + 2] = 0.0f;
  ExpectSameAsBrute(plane, rows, queries);
  ExpectSameAsBrute(line, rows, queries);
}

TEST(NearestRowTree, CoordinateScales) {
  for (float scale : {1e-6f, 1e6f}) {
    std::mt19937 rng(17);
    std::vector<float> xyz = Uniform(rng, 3000, -scale, scale);
    std::vector<std::int64_t> rows;
    for (std::int64_t r = 0; r < 3000; r += 2) rows.push_back(r);
    ExpectSameAsBrute(xyz, rows, Uniform(rng, 200, -3 * scale, 3 * scale));
  }
}

TEST(NearestRowTree, NonFiniteRowsAreLeftOutAndEmptyFindsNothing) {
  std::mt19937 rng(23);
  std::vector<float> xyz = Uniform(rng, 500, 0.0f, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (std::size_t r = 0; r < 500; r += 7) xyz[3 * r + (r % 3)] = (r % 2) ? nan : inf;
  std::vector<std::int64_t> rows(500);
  for (std::size_t r = 0; r < rows.size(); ++r) rows[r] = std::int64_t(r);
  ExpectSameAsBrute(xyz, rows, Uniform(rng, 200, -0.5f, 1.5f));
  const al::NearestRowTree empty(xyz, {});
  const float p[3] = {0.5f, 0.5f, 0.5f};
  EXPECT_EQ(empty.Nearest(p).row, -1);
  EXPECT_EQ(empty.size(), 0u);
  const std::vector<std::int64_t> only_nonfinite = {0, 7, 14};
  EXPECT_EQ(al::NearestRowTree(xyz, only_nonfinite).Nearest(p).row, -1);
}

}  // namespace
