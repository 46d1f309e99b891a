// How much the object's pixels changed colour: mean over the object mask of the mean absolute
// RGB difference between the before and after renders (values clamped to [0, 1] as a PNG would
// hold them). 0 = the object region looks exactly as before (nothing was removed there); larger =
// more of what was seen there is gone. A plug-in of the evaluator (al/eval/view_metric.hpp).
#pragma once
#include <optional>

#include "al/metrics/collateral.hpp"
#include "al/metrics/mask.hpp"

namespace al::metrics {

// nullopt when the mask is empty; throws al::Error when the sizes disagree.
std::optional<double> ObjectColourChange(const RgbImage& before, const RgbImage& after, const Mask& object);

}  // namespace al::metrics
