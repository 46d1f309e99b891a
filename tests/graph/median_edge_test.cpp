// MedianKnnEdgeLength (a radix select over the lengths' bit patterns) against the plain median of
// every non-zero kNN edge length, with coincident points (zero lengths), missing neighbours,
// lengths spread over many octaves, odd and even counts, and 1 or 2 threads.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "al/graph/graph.hpp"
#include "al/graph/knn.hpp"

namespace {

double PlainMedian(const al::KnnResult& knn, const std::vector<float>& xyz) {
  std::vector<double> len;
  const std::size_t k = std::size_t(knn.k);
  for (std::size_t u = 0; k > 0 && u < knn.neighbors.size() / k; ++u)
    for (std::size_t c = 0; c < k; ++c) {
      const std::int32_t v = knn.neighbors[u * k + c];
      if (v < 0) continue;
      double s = 0;
      for (int a = 0; a < 3; ++a) {
        const double d = double(xyz[3 * u + a]) - double(xyz[3 * std::size_t(v) + a]);
        s += d * d;
      }
      if (s > 0) len.push_back(std::sqrt(s));
    }
  if (len.empty()) return 0.0;
  std::sort(len.begin(), len.end());
  const std::size_t h = len.size() / 2;
  return len.size() % 2 ? len[h] : 0.5 * (len[h - 1] + len[h]);
}

std::vector<float> Points(std::size_t n, unsigned seed, double spread) {
  std::mt19937 rng(seed);
  std::lognormal_distribution<double> scale(0.0, spread);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<float> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double s = scale(rng);
    for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(g(rng) * s);
  }
  for (std::size_t i = 0; i + 1 < n; i += 17)  // coincident pairs: zero lengths, left out
    for (int a = 0; a < 3; ++a) xyz[3 * (i + 1) + a] = xyz[3 * i + a];
  return xyz;
}

TEST(MedianKnnEdgeLength, EqualsThePlainMedian) {
  for (const auto& [n, seed, spread] : {std::tuple{2000u, 1u, 0.3}, {3001u, 2u, 3.0}, {501u, 3u, 8.0}}) {
    const std::vector<float> xyz = Points(n, seed, spread);
    al::KnnOptions o;
    o.k = 7;
    al::KnnResult knn = al::KnnAmongPoints(xyz, o);
    for (std::size_t e = 5; e < knn.neighbors.size(); e += 23) knn.neighbors[e] = -1;  // missing neighbours
    const double want = PlainMedian(knn, xyz);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), want) << n << " " << threads;
    }
  }
  omp_set_num_threads(2);
}

TEST(MedianKnnEdgeLength, OddCountsAllZeroAndEmpty) {
  std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 3, 0, 0, 3, 0, 0};
  al::KnnResult knn;
  knn.k = 1;
  knn.neighbors = {1, 0, 3, 2};  // lengths 1, 1, 0, 0: median of {1, 1}
  EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), 1.0);
  knn.neighbors = {1, 2, 3, 2};  // 1, 2, 0, 0: median of {1, 2}
  EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), 1.5);
  knn.neighbors = {1, 2, 0, 2};  // 1, 2, 3, 0: median of three
  EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), 2.0);
  knn.neighbors = {-1, -1, 3, 2};  // only zero lengths
  EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), 0.0);
  knn.k = 0;
  knn.neighbors.clear();
  EXPECT_EQ(al::MedianKnnEdgeLength(knn, xyz), 0.0);
}

}  // namespace
