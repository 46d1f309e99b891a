// Spherical k-means: finds well-separated directions, is deterministic, ignores zero rows.
#include <random>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/eval/kmeans.hpp"

namespace al::eval {
namespace {

RowMatXf ThreeDirections(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> N(0, 0.05f);
  RowMatXf rows(301, 3);
  for (Eigen::Index i = 0; i < 300; ++i) {
    const float length = 1.0f + 3.0f * float(i % 7);  // any length: clustering is by direction
    rows.row(i) << N(rng) * length, N(rng) * length, N(rng) * length;
    rows(i, i % 3) += length;
  }
  rows.row(300).setZero();
  return rows;
}

TEST(SphericalKMeans, FindsTheDirections) {
  const KMeansResult r = SphericalKMeans(ThreeDirections(1), 3);
  ASSERT_EQ(r.centroids.rows(), 3);
  std::size_t total = 0;
  for (Eigen::Index c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.centroids.row(c).norm(), 1.0f, 1e-5f);
    EXPECT_GT(r.centroids.row(c).cwiseAbs().maxCoeff(), 0.99f);  // one of the axes
    EXPECT_EQ(r.sizes[std::size_t(c)], 100u);
    total += r.sizes[std::size_t(c)];
  }
  EXPECT_EQ(total, 300u);  // the zero row is ignored
}

TEST(SphericalKMeans, DeterministicAndBounded) {
  const RowMatXf rows = ThreeDirections(2);
  const KMeansResult a = SphericalKMeans(rows, 5, 7), b = SphericalKMeans(rows, 5, 7);
  EXPECT_TRUE(a.centroids == b.centroids);
  EXPECT_EQ(a.sizes, b.sizes);
  EXPECT_LE(a.centroids.rows(), 5);
  EXPECT_EQ(SphericalKMeans(rows.topRows(2), 8).centroids.rows(), 2);  // k > points
  EXPECT_EQ(SphericalKMeans(RowMatXf::Zero(4, 3), 2).centroids.rows(), 0);
  EXPECT_THROW(SphericalKMeans(rows, 0), Error);
}

}  // namespace
}  // namespace al::eval
