// ObjectColourChange (al/metrics/object_colour_change.hpp).
#include "al/metrics/object_colour_change.hpp"

#include <algorithm>
#include <cmath>

#include "al/core/error.hpp"

namespace al::metrics {

std::optional<double> ObjectColourChange(std::span<const float> before, std::span<const float> after,
                                         const Mask& object) {
  const std::size_t pixels = std::size_t(object.width) * std::size_t(object.height);
  if (before.size() != 3 * pixels || after.size() != 3 * pixels || object.bits.size() != pixels)
    throw Error("object colour change: renders and object mask differ in size", ExitCode::kInternal);
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (!object.bits[p]) continue;
    double d = 0;
    for (int c = 0; c < 3; ++c)
      d += std::fabs(std::clamp(double(before[3 * p + c]), 0.0, 1.0) - std::clamp(double(after[3 * p + c]), 0.0, 1.0));
    sum += d / 3.0;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return sum / double(count);
}

}  // namespace al::metrics
