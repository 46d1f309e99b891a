// Semantic recognition metrics (METRICS.md §2): IoU_pre, IoU_post, IoU_drop, acc_before/after,
// acc_seg at strict thresholds and the paper's acc_{IoU-post > ξ} in percent.
#pragma once
#include <string>
#include <vector>

#include "al/metrics/mask.hpp"
#include "al/metrics/stats.hpp"

namespace al::metrics {

// Field names follow the released JSON (image_name, iou_before, ...).
struct SemanticRecord {
  std::string image_name;
  double iou_before = 0, iou_after = 0, iou_drop = 0;
  double acc_before = 0, acc_after = 0, acc_diff = 0;
  bool missing_before = false, missing_after = false;  // detector mask absent → empty mask
};

// Object mask and detector masks as 8-bit grey; nullptr = missing detection (an empty mask).
// All three are resized to (max H, max W) with the floor rule, then binarised > 0.
SemanticRecord ComputeSemantic(const Gray8& object, const Gray8* before, const Gray8* after,
                               const std::string& image_name = "");

struct SemanticOptions {
  std::vector<double> acc_seg_thresholds = {0.3, 0.5, 0.7, 0.9};  // fraction with IoU_post < ξ
  std::vector<double> table_thresholds = {0.5, 0.7, 0.9};         // percent with IoU_post > ξ
  void Check() const;  // every threshold in [0, 1]
};

struct ThresholdValue {
  double threshold = 0, value = 0;
};

struct SemanticSummary {
  std::size_t images = 0, missing_before = 0, missing_after = 0;
  double iou_before = 0, iou_after = 0, iou_drop = 0;  // means; iou_drop = iou_before − iou_after exactly
  double acc_before = 0, acc_after = 0, acc_diff = 0;
  std::vector<ThresholdValue> acc_seg;              // fractions, strict <
  std::vector<ThresholdValue> acc_iou_post_above;   // percent, strict >
};

// Mean over the given images (pass all images of all scenes for the pooled value).
SemanticSummary SummarizeSemantic(const std::vector<SemanticRecord>& records, const SemanticOptions& options = {});

}  // namespace al::metrics
