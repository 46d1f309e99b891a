#include "al/metrics/stats.hpp"

#include <cmath>

namespace al::metrics {

MeanStd ComputeMeanStd(const std::vector<double>& values) {
  MeanStd m;
  m.count = values.size();
  if (values.empty()) return m;
  for (double v : values) m.mean += v;
  m.mean /= double(values.size());
  double ss = 0;
  for (double v : values) ss += (v - m.mean) * (v - m.mean);
  m.std = std::sqrt(ss / double(values.size()));
  return m;
}

}  // namespace al::metrics
