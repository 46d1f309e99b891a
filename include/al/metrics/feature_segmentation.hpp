// Segmentation of the target in a rendered feature field, and the metrics on it (docs/eval.md,
// "Feature metrics"): the scene's own semantic features stand in for GroundedSAM, so IoU_drop,
// acc_seg and the residual need no external segmenter. Named apart from the GroundedSAM metrics
// (suffix _feat) because they answer a different question: "does the scene's feature field still
// show the object?" rather than "does an open-vocabulary detector still find it in the RGB image?".
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "al/core/option_table.hpp"
#include "al/metrics/mask.hpp"
#include "al/metrics/semantic.hpp"
#include "al/metrics/stats.hpp"

namespace al::metrics {

// A rendered feature image (not owned): feature = H*W*dim pixel-major, alpha = H*W.
struct FeatureImage {
  int width = 0, height = 0, dim = 0;
  const float* feature = nullptr;
  const float* alpha = nullptr;
};

// Unit-length prototypes in the rendered channel space; row `target` is the target's, the others
// compete with it (other objects).
struct Prototypes {
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows;  // K x dim
  int target = 0;
  std::vector<std::string> names;  // K, for the report
};

struct FeatureSegOptions {
  // A pixel is the target only if the cosine of its feature to the target prototype reaches this.
  // 0.5 (60°) is a scale-free reading of "mostly the target's direction", chosen before looking
  // at any scene and kept for all (docs/eval.md gives the measured IoU against ground-truth masks on
  // both generators). Cosines are taken in the centred space (al/render/feature_field.hpp), where
  // unrelated classes sit near 0 even for CLIP-like features.
  double min_similarity = 0.5;
  // ... and only where the render is mostly opaque: below this alpha the pixel shows mostly the
  // background colour, whatever its (normalised) feature says. Same 0.5 as the object-mask rule.
  double min_alpha = 0.5;
  static const OptionTable<FeatureSegOptions>& Table();  // feature_min_sim, feature_min_alpha
  void Check() const;  // al::Error (usage) when a value is outside [-1, 1] / [0, 1]
};

// Target mask of one rendered view: alpha >= min_alpha, cos(f, target) >= min_similarity and
// cos(f, target) > cos(f, p) for every other prototype p (strict: a tie is not the target).
// Pixels with a zero feature are never the target. Thread-count independent.
Mask SegmentTarget(const FeatureImage& image, const Prototypes& prototypes, const FeatureSegOptions& options);

// Per view and removal. With O = object mask, S_pre / S_post = target masks of the before / after
// renders: iou_before = IoU(O, S_pre), iou_after = IoU(O, S_post), iou_drop, acc_before/after as in
// METRICS.md §2 (the feature masks take the detector's place), and
// residual = |O ∩ S_pre ∩ S_post| / |O ∩ S_pre| (0 when O ∩ S_pre is empty): the share of the
// object's before-pixels still segmented as the target after the removal.
struct FeatureRecord {
  SemanticRecord semantic;
  double residual = 0;
  std::size_t before_pixels = 0;    // |O ∩ S_pre|
  std::size_t residual_pixels = 0;  // |O ∩ S_pre ∩ S_post|
};
FeatureRecord ScoreFeatureSegmentation(const Mask& object, const Mask& before, const Mask& after,
                                       const std::string& image_name = "");

struct FeatureSummary {
  SemanticSummary semantic;       // means, acc_seg (fractions, strict <), acc_{IoU-post > ξ} (percent)
  MeanStd residual;               // over the views with before pixels
  std::size_t views_without_target = 0;  // views whose O ∩ S_pre is empty (residual undefined)
};
FeatureSummary SummarizeFeature(const std::vector<FeatureRecord>& records, const SemanticOptions& options = {});

}  // namespace al::metrics
