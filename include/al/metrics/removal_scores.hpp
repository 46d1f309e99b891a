// Ground-truth scores of a removed set against one labelled object (SPEC §1 gt.before / gt.after):
// precision / recall / F1 / IoU by count and weighted by activated opacity. Used by refine (gt
// scores), eval (per-column gt), auto-tune and the synthetic-scene statistics.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace al {

struct RemovalScores {
  std::size_t removed = 0, target = 0, true_positive = 0, false_positive = 0, false_negative = 0;
  double precision = 0, recall = 0, f1 = 0, iou = 0;
  double precision_w = 0, recall_w = 0, f1_w = 0, iou_w = 0;  // weighted by sigmoid(opacity)
  nlohmann::json ToJson() const;  // {precision, recall, f1, iou, precision_w, ..., counts}
};
// removed: N bools; labels: N ids; target_id: the object; opacity_logits: N raw opacities (may be
// empty: weights 1). Empty sets give 0 precision/recall (and 1 for both when both sets are empty).
RemovalScores ScoreRemoval(const std::vector<bool>& removed, const std::vector<std::int32_t>& labels,
                           int target_id, const std::vector<float>& opacity_logits = {});

}  // namespace al
