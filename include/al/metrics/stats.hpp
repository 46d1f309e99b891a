// Aggregation helpers shared by the metrics (per-scene mean/std and pooled means).
#pragma once
#include <cstddef>
#include <vector>

namespace al::metrics {

// Mean and population standard deviation (ddof 0, as the released evaluator); zeros for no values.
struct MeanStd {
  double mean = 0, std = 0;
  std::size_t count = 0;
};
MeanStd ComputeMeanStd(const std::vector<double>& values);

}  // namespace al::metrics
