#include "al/metrics/semantic.hpp"

#include <algorithm>
#include <cmath>

namespace al::metrics {

SemanticRecord ComputeSemantic(const Gray8& object, const Gray8* before, const Gray8* after,
                               const std::string& image_name) {
  int h = object.height, w = object.width;
  for (const Gray8* g : {before, after})
    if (g) h = std::max(h, g->height), w = std::max(w, g->width);
  auto binarised = [&](const Gray8* g) {
    return g ? Binarize(Resize(*g, w, h, ResizeRule::kFloor), 0) : EmptyMask(w, h);
  };
  const Mask o = binarised(&object), pre = binarised(before), post = binarised(after);
  SemanticRecord r;
  r.image_name = image_name;
  r.missing_before = before == nullptr;
  r.missing_after = after == nullptr;
  r.iou_before = IoU(o, pre);
  r.iou_after = IoU(o, post);
  r.iou_drop = r.iou_before - r.iou_after;
  r.acc_before = AccIn(o, pre);
  const Overlap op = CountOverlap(o, post);
  r.acc_after = op.a == 0 ? 0.0 : double(op.a - op.intersection) / double(op.a);
  r.acc_diff = r.acc_after - r.acc_before;
  return r;
}

SemanticSummary SummarizeSemantic(const std::vector<SemanticRecord>& records, const SemanticOptions& options) {
  SemanticSummary s;
  s.images = records.size();
  for (const auto& r : records) {
    s.missing_before += r.missing_before;
    s.missing_after += r.missing_after;
    s.iou_before += r.iou_before;
    s.iou_after += r.iou_after;
    s.acc_before += r.acc_before;
    s.acc_after += r.acc_after;
  }
  const double n = records.empty() ? 1.0 : double(records.size());
  s.iou_before /= n;
  s.iou_after /= n;
  s.acc_before /= n;
  s.acc_after /= n;
  // Differences of the means, so that mean IoU_drop = mean IoU_pre − mean IoU_post holds exactly.
  s.iou_drop = s.iou_before - s.iou_after;
  s.acc_diff = s.acc_after - s.acc_before;
  for (double xi : options.acc_seg_thresholds) {
    std::size_t below = 0;
    for (const auto& r : records) below += r.iou_after < xi;
    s.acc_seg.push_back({xi, records.empty() ? 0.0 : double(below) / double(records.size())});
  }
  for (double xi : options.table_thresholds) {
    std::size_t above = 0;
    for (const auto& r : records) above += r.iou_after > xi;
    s.acc_iou_post_above.push_back({xi, records.empty() ? 0.0 : 100.0 * double(above) / double(records.size())});
  }
  return s;
}

}  // namespace al::metrics
