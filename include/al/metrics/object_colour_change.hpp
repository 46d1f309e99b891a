// How much the object's pixels changed colour: mean over the object mask of the mean absolute
// RGB difference between the before and after renders (values clamped to [0, 1] as a PNG would
// hold them). 0 = the object region looks exactly as before (nothing was removed there); larger =
// more of what was seen there is gone. A plug-in of the evaluator (al/eval/view_metric.hpp).
#pragma once
#include <optional>
#include <span>

#include "al/metrics/mask.hpp"

namespace al::metrics {

// before / after: H*W*3 RGB of the object mask's size (read in place, no copy). nullopt when the
// mask is empty; throws al::Error when the sizes disagree.
std::optional<double> ObjectColourChange(std::span<const float> before, std::span<const float> after,
                                         const Mask& object);

}  // namespace al::metrics
