// Spherical k-means (cosine similarity) for the feature prototypes of objects that have no labels
// (docs/eval.md, "Feature metrics"). Deterministic in the seed and independent of the thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "al/scene/scene.hpp"

namespace al::eval {

struct KMeansResult {
  RowMatXf centroids;                 // k' x dim, unit rows (k' <= k: empty clusters are dropped)
  std::vector<std::size_t> sizes;     // members per centroid
  int iterations = 0;
};

// rows: points (any norm; zero rows are ignored), clustered by cosine: k-means++ seeding on
// 1 - cos, then Lloyd steps (assign to the largest cosine, centroid = normalised mean) until no
// assignment changes or max_iterations.
KMeansResult SphericalKMeans(const RowMatXf& rows, int k, std::uint64_t seed = 1, int max_iterations = 50);

}  // namespace al::eval
