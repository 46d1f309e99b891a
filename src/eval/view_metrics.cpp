// The evaluator's plug-in metrics (al/eval/view_metric.hpp): one row per metric.
#include "al/eval/view_metric.hpp"
#include "al/metrics/object_colour_change.hpp"

namespace al::eval {

const std::vector<ViewMetric>& ViewMetrics() {
  static const std::vector<ViewMetric> metrics = {
      {"object_colour_change", "object colour change ↑ (mean |ΔRGB| over the object's pixels)",
       "$|\\Delta\\text{RGB}|_{\\text{obj}}\\uparrow$", +1, 3, false,
       [](const ViewMetricInput& in) { return metrics::ObjectColourChange(in.before.rgb, in.after.rgb, in.object); }},
  };
  return metrics;
}

}  // namespace al::eval
