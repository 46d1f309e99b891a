// Check() of the metrics' options structs: the ranges METRICS.md gives their parameters.
#include "al/core/option_table.hpp"
#include "al/metrics/depth.hpp"
#include "al/metrics/semantic.hpp"
#include "al/metrics/sim_sam.hpp"

namespace al::metrics {

void GhtOptions::Check() const {
  using R = NumericRange;
  CheckOptionRange("ght", "nu", nu, R::AtLeast(0), "GHT prior strength nu");
  CheckOptionRange("ght", "tau", tau, R::AtLeast(0), "GHT prior scale tau");
  CheckOptionRange("ght", "kappa", kappa, R::AtLeast(0), "GHT prior weight kappa");
  CheckOptionRange("ght", "omega", omega, R::Closed(0, 1), "GHT prior mode omega");
}

void FloatDepthOptions::Check() const {
  CheckOptionRange("depth", "alpha_hit", alpha_hit, NumericRange{0, 1, false, true}, "a pixel has depth iff alpha > this");
  ght.Check();
}

void SemanticOptions::Check() const {
  for (double t : acc_seg_thresholds)
    CheckOptionRange("semantic", "acc_seg_thresholds", t, NumericRange::Closed(0, 1), "IoU_post thresholds xi");
  for (double t : table_thresholds)
    CheckOptionRange("semantic", "table_thresholds", t, NumericRange::Closed(0, 1), "IoU_post thresholds of the table");
}

void SimSamOptions::Check() const {
  CheckOptionRange("sim_sam", "min_object_iou", min_object_iou, NumericRange::Closed(0, 1),
                   "keep a SAM segment iff its IoU with the object is at least this");
}

}  // namespace al::metrics
