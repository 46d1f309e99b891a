// Median and robust spread of a sample, shared by the graph's σ_x (graph.cpp), the feature prior
// (prior.cpp) and the restore window (restore_window.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace al {

inline constexpr double kMadToSigma = 1.4826;  // a normal distribution's σ per median absolute deviation

// The median (the mean of the two middle values for an even count); 0 for an empty sample.
inline double MedianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(h), v.end());
  if (v.size() % 2) return v[h];
  return 0.5 * (v[h] + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(h)));
}

// (median, 1.4826 · MAD): the centre and a robust standard deviation of the sample.
inline std::pair<double, double> MedianAndSpread(std::vector<double> v) {
  const double median = MedianOf(v);
  for (double& x : v) x = std::abs(x - median);
  return {median, kMadToSigma * MedianOf(std::move(v))};
}

}  // namespace al
