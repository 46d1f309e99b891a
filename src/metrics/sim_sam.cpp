#include "al/metrics/sim_sam.hpp"

#include <algorithm>

#include "al/metrics/hungarian.hpp"

namespace al::metrics {

std::vector<int> FilterSegments(const Mask& object, const std::vector<Mask>& segments, const SimSamOptions& options,
                                std::vector<Mask>* kept) {
  std::vector<int> indices;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    Mask s = Resize(segments[i], object.width, object.height, ResizeRule::kFloor);
    for (auto& b : s.bits) b = b != 0;
    if (IoU(s, object) >= options.min_object_iou) {
      indices.push_back(int(i));
      if (kept) kept->push_back(std::move(s));
    }
  }
  return indices;
}

SimSamResult ComputeSimSam(const Gray8& object_image, const std::vector<Mask>& side_a,
                           const std::vector<Mask>& side_b, const SimSamOptions& options) {
  const Mask object = Binarize(object_image, options.object_threshold);
  std::vector<Mask> a, b;
  FilterSegments(object, side_a, options, &a);
  FilterSegments(object, side_b, options, &b);
  SimSamResult r;
  r.n_gt = int(a.size());
  r.n_sam = int(b.size());
  if (a.empty() || b.empty()) return r;  // drop rule: not scored
  const int n = r.n_gt, m = r.n_sam;
  std::vector<double> iou(std::size_t(n) * m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) iou[std::size_t(i) * m + j] = IoU(a[i], b[j]);
  const Assignment assignment = MaxWeightAssignment(iou, n, m);
  double total = 0;
  for (int i = 0; i < n; ++i) {
    const int j = assignment.row_to_col[i];
    if (j < 0) continue;
    const double v = iou[std::size_t(i) * m + j];
    if (v > 0) r.matches.push_back({i, j, v}), total += v;
  }
  r.scored = true;
  r.sim_sam = total / double(std::max(n, m));
  return r;
}

}  // namespace al::metrics
