#include "al/metrics/feature_segmentation.hpp"

#include <cmath>

#include "al/core/error.hpp"

namespace al::metrics {

const OptionTable<FeatureSegOptions>& FeatureSegOptions::Table() {
  using O = FeatureSegOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("feature segmentation")
          .Real("feature_min_sim", &O::min_similarity, R::Closed(-1, 1),
                "a pixel is the target only at cosine >= this to its prototype (centred features)")
          .Real("feature_min_alpha", &O::min_alpha, R::Closed(0, 1), "... and only where the render's alpha >= this");
  return table;
}

void FeatureSegOptions::Check() const { Table().Check(*this); }

Mask SegmentTarget(const FeatureImage& image, const Prototypes& prototypes, const FeatureSegOptions& options) {
  options.Check();
  const int dim = image.dim, k = static_cast<int>(prototypes.rows.rows());
  if (k < 1 || prototypes.rows.cols() != dim || prototypes.target < 0 || prototypes.target >= k)
    throw Error("feature segmentation: prototypes do not match the rendered channels");
  Mask mask = EmptyMask(image.width, image.height);
  const std::ptrdiff_t pixels = std::ptrdiff_t(image.width) * image.height;
  using ConstVec = Eigen::Map<const Eigen::VectorXf>;
  // Each pixel is decided alone, so any thread count gives the same mask.
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t p = 0; p < pixels; ++p) {
    if (!(image.alpha[p] >= options.min_alpha)) continue;
    const ConstVec f(image.feature + p * dim, dim);
    const float norm = f.norm();
    if (!(norm > 0) || !std::isfinite(norm)) continue;
    const float to_target = prototypes.rows.row(prototypes.target).dot(f);
    if (!(to_target >= static_cast<float>(options.min_similarity) * norm)) continue;
    bool nearest = true;
    for (int j = 0; j < k && nearest; ++j)
      if (j != prototypes.target && !(to_target > prototypes.rows.row(j).dot(f))) nearest = false;
    mask.bits[std::size_t(p)] = nearest ? 1 : 0;
  }
  return mask;
}

FeatureRecord ScoreFeatureSegmentation(const Mask& object, const Mask& before, const Mask& after,
                                       const std::string& image_name) {
  if (object.width != before.width || object.height != before.height || object.width != after.width ||
      object.height != after.height)
    throw Error("feature metrics: object mask and segmentations differ in size");
  FeatureRecord r;
  SemanticRecord& s = r.semantic;
  s.image_name = image_name;
  s.iou_before = IoU(object, before);
  s.iou_after = IoU(object, after);
  s.iou_drop = s.iou_before - s.iou_after;
  s.acc_before = AccIn(object, before);
  const Overlap post = CountOverlap(object, after);
  s.acc_after = post.a == 0 ? 0.0 : double(post.a - post.intersection) / double(post.a);
  s.acc_diff = s.acc_after - s.acc_before;
  for (std::size_t p = 0; p < object.bits.size(); ++p) {
    if (!object.bits[p] || !before.bits[p]) continue;
    ++r.before_pixels;
    r.residual_pixels += after.bits[p] != 0;
  }
  r.residual = r.before_pixels == 0 ? 0.0 : double(r.residual_pixels) / double(r.before_pixels);
  return r;
}

FeatureSummary SummarizeFeature(const std::vector<FeatureRecord>& records, const SemanticOptions& options) {
  FeatureSummary s;
  std::vector<SemanticRecord> semantic;
  std::vector<double> residual;
  for (const FeatureRecord& r : records) {
    semantic.push_back(r.semantic);
    if (r.before_pixels > 0) residual.push_back(r.residual);
    else ++s.views_without_target;
  }
  s.semantic = SummarizeSemantic(semantic, options);
  s.residual = ComputeMeanStd(residual);
  return s;
}

}  // namespace al::metrics
