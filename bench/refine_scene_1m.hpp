// The deterministic 1M-Gaussian refinement scene shared by the graph and bk benchmarks.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "al/scene/scene.hpp"

namespace al::bench {

struct BenchScene {
  al::Scene scene;
  std::vector<bool> removed;
};

// 1M Gaussians uniform in a 100³ box (density 1), radii 0.05..0.3; the removed set is a ball of
// radius 28 (~92k Gaussians); 16-D features: one class inside the ball, one outside, plus noise.
inline const BenchScene& Scene1M() {
  static const BenchScene s = [] {
    BenchScene b;
    const int n = 1000000;
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::normal_distribution<float> g(0.f, 1.f);
    b.scene.means.resize(n, 3);
    b.scene.log_scales.resize(n, 3);
    b.scene.features.resize(n, 16);
    b.removed.resize(n);
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) b.scene.means(i, a) = 100.f * uni(rng);
      for (int a = 0; a < 3; ++a) b.scene.log_scales(i, a) = std::log(0.05f + 0.25f * uni(rng));
      const float dx = b.scene.means(i, 0) - 50, dy = b.scene.means(i, 1) - 50, dz = b.scene.means(i, 2) - 50;
      const bool in = dx * dx + dy * dy + dz * dz < 28.f * 28.f;
      b.removed[i] = in && uni(rng) < 0.97f;  // some misses inside: work for the solver
      for (int d = 0; d < 16; ++d) b.scene.features(i, d) = (d == (in ? 0 : 1) ? 3.f : 0.f) + 0.4f * g(rng);
    }
    return b;
  }();
  return s;
}

}  // namespace al::bench
