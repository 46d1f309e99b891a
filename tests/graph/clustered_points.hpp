// Test point sets: clusters whose spreads differ by many octaves (dense clumps beside sparse
// points), for the kNN and kd-tree tests.
#pragma once
#include <random>
#include <vector>

namespace al::test_points {

// `clusters` Gaussian clusters of `per_cluster` points, centres ~ N(0, centre_sd²) per axis,
// spreads lognormal(0, spread_sigma), every coordinate times `unit`; xyz row-major.
inline std::vector<float> ClusteredPoints(unsigned seed, int clusters, int per_cluster, double spread_sigma,
                                          double centre_sd, double unit) {
  std::mt19937 rng(seed);
  std::lognormal_distribution<double> scale(0.0, spread_sigma);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<float> xyz;
  for (int c = 0; c < clusters; ++c) {
    const double s = scale(rng), cx = g(rng) * centre_sd, cy = g(rng) * centre_sd, cz = g(rng) * centre_sd;
    for (int i = 0; i < per_cluster; ++i)
      for (const double v : {cx + g(rng) * s, cy + g(rng) * s, cz + g(rng) * s}) xyz.push_back(float(v * unit));
  }
  return xyz;
}

}  // namespace al::test_points
