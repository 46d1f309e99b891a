// Small random scenes for the graph tests: clusters, a few huge Gaussians, exact duplicates.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "al/scene/scene.hpp"

namespace al::test {

struct GraphScene {
  Scene scene;
  RowMatXf features;
  std::vector<bool> removed;
};

inline GraphScene MakeGraphScene(int n, unsigned seed, int dim = 8, int huge = 3, int dups = 10) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.f, 1.f);
  std::normal_distribution<float> gauss(0.f, 1.f);
  GraphScene g;
  Scene& s = g.scene;
  s.means.resize(n, 3);
  s.log_scales.resize(n, 3);
  s.rotations.resize(n, 4);
  s.opacity_logits.resize(n);
  s.sh.resize(n, 3);
  g.features.resize(n, dim);
  std::vector<Eigen::Vector3f> centres;
  std::vector<std::vector<float>> classes;
  for (int c = 0; c < 6; ++c) {
    centres.emplace_back(10 * uni(rng), 10 * uni(rng), 10 * uni(rng));
    std::vector<float> e(dim);
    for (auto& x : e) x = gauss(rng);
    classes.push_back(e);
  }
  for (int i = 0; i < n; ++i) {
    const int c = static_cast<int>(uni(rng) * 6) % 6;
    for (int a = 0; a < 3; ++a) s.means(i, a) = centres[c][a] + 1.5f * gauss(rng);
    for (int a = 0; a < 3; ++a) s.log_scales(i, a) = std::log(0.02f + 0.1f * uni(rng));
    s.rotations.row(i) << 1, 0, 0, 0;
    s.opacity_logits[i] = gauss(rng);
    for (int a = 0; a < 3; ++a) s.sh(i, a) = gauss(rng);
    for (int d = 0; d < dim; ++d) g.features(i, d) = classes[c][d] + 0.3f * gauss(rng);
    g.removed.push_back(c == 0 && uni(rng) < 0.7f);
  }
  for (int h = 0; h < huge && h < n; ++h) {  // huge spheres, one of them removed
    const int i = static_cast<int>(uni(rng) * n) % n;
    for (int a = 0; a < 3; ++a) s.log_scales(i, a) = std::log(3.0f + uni(rng));
    if (h == 0) g.removed[i] = true;
  }
  for (int d = 0; d < dups && n > 1; ++d) {  // exact duplicates of other Gaussians
    const int i = static_cast<int>(uni(rng) * n) % n, j = static_cast<int>(uni(rng) * n) % n;
    if (i == j) continue;
    s.means.row(j) = s.means.row(i);
    s.log_scales.row(j) = s.log_scales.row(i);
    g.features.row(j) = g.features.row(i);
  }
  s.sh_degree = 0;
  s.has_opacity = s.has_scales = s.has_rotations = s.has_f_dc = true;
  s.source_path = "generated";
  return g;
}

}  // namespace al::test
