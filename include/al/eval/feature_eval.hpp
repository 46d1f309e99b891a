// The evaluator's feature metrics (docs/eval.md, "Feature metrics"): the scene's semantic features
// are rendered with the RGB pass (al/render/feature_field.hpp), every render is segmented for the
// target by nearest prototype (al/metrics/feature_segmentation.hpp), and IoU_drop / acc_seg /
// residual are computed on those segmentations -- with no external segmenter.
//
// Prototypes, in the rendered (unit, centred, maybe projected) channel space, each the normalised
// mean of its Gaussians' channel rows (= the mean unit feature, centred and projected). The
// "neighbourhood" of a set = refine's candidates of it (al/graph/candidates.hpp: spheres of radius
// max σ that intersect, `candidate_hops` growth steps) minus the set: what touches the object.
//  * with ground-truth labels: the target = the labels' target object; the competitors = every
//    other label id present (0 = background included), each twice: its mean over all its Gaussians
//    and its mean over those in the target's neighbourhood (features blur across contacts: the
//    table just under the object looks more like the object than the table's global mean does);
//  * without labels: the target = the Gaussians of FeatureEvalOptions::target_set when given (FGS's
//    prompt rule), else the removal method's set (the first column); the competitors = spherical
//    k-means (k each) of the kept candidates -- the set's neighbourhood -- and of the kept Gaussians
//    in the evaluated views (the other objects, look-alikes included). A cluster at cosine >=
//    merge_similarity to the target prototype is taken for the target's own kept part (a
//    residual), not a competitor, and dropped: it would otherwise take the residual pixels it is
//    meant to reveal. Without labels a neighbour whose features blurred towards the target cannot
//    be told from a residual: it is reported as one (it is what a feature segmenter would show).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/io/camera.hpp"
#include "al/metrics/feature_segmentation.hpp"
#include "al/render/feature_field.hpp"
#include "al/render/render.hpp"
#include "al/scene/scene.hpp"

namespace al::eval {

struct FeatureEvalOptions {
  enum class Mode { kAuto, kOn, kOff };
  Mode mode = Mode::kAuto;               // auto: when the scene has features; on: fail without them
  FeatureFieldOptions field;             // centring, channel limit / projection
  metrics::FeatureSegOptions segmentation;
  int kmeans_k = 8;                      // competitor clusters without labels
  int candidate_hops = 1;                // growth steps from the target set (refine's candidates)
  double merge_similarity = 0.8;         // clusters this close to the target prototype are dropped
  bool use_labels = true;                // false: prototypes as without labels even when labels are given
  std::vector<bool> target_set;          // optional prototype source (N) when no labels are given
  std::string target_set_source;         // its name in the report, e.g. "prompts 0,2"
  // feature_metrics, feature_k, feature_hops, feature_merge_sim, feature_prototype (not the nested
  // field / segmentation options, which have their own tables).
  static const OptionTable<FeatureEvalOptions>& Table();
  void Check() const;                    // al::Error (usage), nested options included
  nlohmann::json ToJson() const;         // every table field, the nested ones included
};

// Where the target prototype comes from (labels win, then target_set, then the removal).
struct FeaturePrototypeInput {
  const std::vector<std::int32_t>* labels = nullptr;  // N ids, may be null / empty
  int object_id = 0;
  const std::vector<bool>* removed = nullptr;         // the removal method's set (N)
  const std::vector<Camera>* cameras = nullptr;       // the evaluated views (competitors without labels)
};

// Per view and column, next to ColumnViewMetrics' other metrics.
struct FeatureViewMetrics {
  metrics::FeatureRecord record;
  std::size_t target_pixels_after = 0;  // |S_post|
};

// Prepares the channels and prototypes once per scene and segments each render.
class FeatureScorer {
 public:
  FeatureScorer(const Scene& scene, const FeaturePrototypeInput& input, const FeatureEvalOptions& options);
  bool enabled() const { return enabled_; }
  const std::string& skip_reason() const { return skip_reason_; }
  // The matrix to put in RenderOptions::features (null when disabled).
  const RowMatXf* channels() const { return enabled_ ? &field_.channels : nullptr; }
  metrics::Mask Segment(const RenderOutput& render) const;
  FeatureViewMetrics Score(const metrics::Mask& object, const metrics::Mask& before, const metrics::Mask& after,
                           const std::string& view) const;
  // {field, prototypes: {source, names, count, ...}, options, seconds}; {"skipped": reason} if disabled.
  nlohmann::json ToJson() const;

 private:
  FeatureEvalOptions options_;
  bool enabled_ = false;
  std::string skip_reason_;
  FeatureField field_;
  metrics::Prototypes prototypes_;
  nlohmann::json prototype_info_;
  double seconds_ = 0;
};

}  // namespace al::eval
