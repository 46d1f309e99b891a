// FeatureScorer (al/eval/feature_eval.hpp): channels, prototypes, segmentation and scores.
#include "al/eval/feature_eval.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"
#include "al/eval/kmeans.hpp"
#include "al/graph/candidates.hpp"

namespace al::eval {
namespace {

using json = nlohmann::json;
constexpr std::size_t kMaxClusterRows = 50000;  // k-means sample (evenly spaced over the candidates)
// Fewer Gaussians than this make no prototype: their mean is mostly feature noise, and a noisy
// competitor near the target would take target pixels at random.
constexpr std::size_t kMinPrototypeGaussians = 20;

// Normalised sum of the channel rows where take(i); empty when nothing (or only zero rows) summed.
template <class Take>
Eigen::VectorXf UnitMean(const RowMatXf& channels, Take take, std::size_t& count) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(channels.cols());
  count = 0;
  for (Eigen::Index i = 0; i < channels.rows(); ++i)
    if (take(std::size_t(i))) {
      sum += channels.row(i).transpose().cast<double>();
      ++count;
    }
  const double norm = sum.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return {};
  return (sum / norm).cast<float>();
}

void AddPrototype(metrics::Prototypes& p, const Eigen::VectorXf& row, const std::string& name) {
  p.rows.conservativeResize(p.rows.rows() + 1, row.size());
  p.rows.row(p.rows.rows() - 1) = row.transpose();
  p.names.push_back(name);
}

// One prototype per label (the normalised mean of its Gaussians' channels) and, for every other
// label, a second one from its Gaussians in the target's neighbourhood (`near`): features blur
// across contacts, so the table right under an object looks more like the object than the table's
// global mean does -- without the local prototype, the table revealed by a perfect removal would be
// segmented as the object.
metrics::Prototypes FromLabels(const RowMatXf& channels, const std::vector<std::int32_t>& labels, int target,
                               const std::vector<std::uint8_t>& near, json& info) {
  metrics::Prototypes p;
  std::map<std::int32_t, std::size_t> ids;
  for (std::int32_t l : labels) ++ids[l];
  if (!ids.count(target)) throw Error("feature metrics: no Gaussian has object id " + std::to_string(target));
  json sizes = json::object(), local = json::object();
  for (const auto& [id, n] : ids) {
    std::size_t count = 0;
    const Eigen::VectorXf row = UnitMean(channels, [&](std::size_t i) { return labels[i] == id; }, count);
    if (row.size() == 0) {
      if (id == target) throw Error("feature metrics: the target object's features average to zero");
      continue;  // an object whose features are all zero cannot be told apart: no competitor
    }
    if (id == target) p.target = static_cast<int>(p.rows.rows());
    std::string name = id == target ? "target: label " : "label ";
    name += std::to_string(id);
    AddPrototype(p, row, name);
    sizes[std::to_string(id)] = n;
    if (id == target) continue;
    std::size_t near_count = 0;
    const Eigen::VectorXf near_row =
        UnitMean(channels, [&](std::size_t i) { return labels[i] == id && near[i]; }, near_count);
    if (near_count < kMinPrototypeGaussians || near_row.size() == 0) continue;
    AddPrototype(p, near_row, name + " near the target");
    local[std::to_string(id)] = near_count;
  }
  info = {{"source", "labels"}, {"object_id", target}, {"gaussians_per_label", sizes},
          {"near_target_per_label", local}};
  return p;
}

// Gaussians outside the set whose 1σ spheres reach it within `hops` growth steps: refine's
// candidates (al/graph/candidates.hpp, radius = largest σ) minus the set.
std::vector<std::uint8_t> NearSet(const Scene& scene, const std::vector<bool>& set, int hops) {
  const std::size_t n = scene.size();
  std::vector<float> xyz(3 * n);
  std::vector<double> radii(n);
  std::vector<std::uint8_t> active(n), seeds(n);
  for (std::size_t i = 0; i < n; ++i) {
    double r = 0;
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      xyz[3 * i + a] = scene.means(Eigen::Index(i), a);
      ok = ok && std::isfinite(xyz[3 * i + a]);
      r = std::max(r, std::exp(double(scene.log_scales(Eigen::Index(i), a))));
    }
    active[i] = ok && std::isfinite(r);
    radii[i] = active[i] ? r : 0.0;
    seeds[i] = set[i] ? 1 : 0;
  }
  std::vector<std::uint8_t> in = GrowCandidates(xyz, radii, active, seeds, hops);
  for (std::size_t i = 0; i < n; ++i) in[i] = in[i] && !set[i];
  return in;
}

// Gaussians outside the set whose centre projects into at least one view (in front of the camera).
std::vector<std::uint8_t> InViews(const Scene& scene, const std::vector<bool>& set, const std::vector<Camera>& cams) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(scene.size());
  std::vector<std::uint8_t> in(static_cast<std::size_t>(n), 0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (set[std::size_t(i)]) continue;
    const Eigen::Vector3d x = scene.means.row(i).transpose().cast<double>();
    for (const Camera& c : cams) {
      const Eigen::Vector3d q = c.R * x + c.t;
      if (!(q.z() > 0.2)) continue;
      const double u = c.fx * q.x() / q.z() + c.cx, v = c.fy * q.y() / q.z() + c.cy;
      if (u >= 0 && v >= 0 && u < c.width && v < c.height) {
        in[std::size_t(i)] = 1;
        break;
      }
    }
  }
  return in;
}

// Spherical k-means of the channels of the rows where take[i] (an evenly spaced sample); the
// clusters not merged into the target become prototypes named `what` j.
json AddClusters(const RowMatXf& channels, const std::vector<std::uint8_t>& take, const Eigen::VectorXf& target,
                 const FeatureEvalOptions& o, const std::string& what, metrics::Prototypes& p) {
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < take.size(); ++i)
    if (take[i]) rows.push_back(Eigen::Index(i));
  const std::size_t m = std::min(rows.size(), kMaxClusterRows);
  RowMatXf sample(static_cast<Eigen::Index>(m), channels.cols());
  for (std::size_t k = 0; k < m; ++k) sample.row(Eigen::Index(k)) = channels.row(rows[k * rows.size() / m]);
  // At most one cluster per kMinPrototypeGaussians rows; smaller clusters are dropped too.
  const int k = static_cast<int>(std::min<std::size_t>(std::size_t(o.kmeans_k), m / kMinPrototypeGaussians));
  const KMeansResult km = k > 0 ? SphericalKMeans(sample, k) : KMeansResult{};
  json clusters = json::array();
  for (Eigen::Index c = 0; c < km.centroids.rows(); ++c) {
    const double cos = km.centroids.row(c).dot(target);
    const bool merged = cos >= o.merge_similarity, small = km.sizes[std::size_t(c)] < kMinPrototypeGaussians;
    clusters.push_back({{"size", km.sizes[std::size_t(c)]}, {"cosine_to_target", cos},
                        {"dropped", merged ? "target-like" : small ? "small" : ""}});
    if (!merged && !small) AddPrototype(p, km.centroids.row(c).transpose(), what + " " + std::to_string(c));
  }
  return {{"gaussians", rows.size()}, {"clustered_rows", m}, {"k", k}, {"iterations", km.iterations},
          {"clusters", clusters}};
}

// Without labels: the competitors are clusters of what surrounds the set (its neighbourhood: the
// blurred contacts) and of what the views show (the other objects, look-alikes included).
metrics::Prototypes FromSet(const Scene& scene, const RowMatXf& channels, const std::vector<bool>& set,
                            const std::vector<Camera>& cameras, const std::string& source,
                            const FeatureEvalOptions& o, json& info) {
  metrics::Prototypes p;
  std::size_t count = 0;
  const Eigen::VectorXf target = UnitMean(channels, [&](std::size_t i) { return bool(set[i]); }, count);
  if (target.size() == 0) throw Error("feature metrics: the " + source + " set's features average to zero");
  AddPrototype(p, target, "target: " + source);
  const json near = AddClusters(channels, NearSet(scene, set, o.candidate_hops), target, o, "near cluster", p);
  const json views = AddClusters(channels, InViews(scene, set, cameras), target, o, "view cluster", p);
  info = {{"source", source}, {"target_gaussians", count}, {"k", o.kmeans_k}, {"near_target", near},
          {"in_views", views}};
  return p;
}

}  // namespace

const OptionTable<FeatureEvalOptions>& FeatureEvalOptions::Table() {
  using O = FeatureEvalOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("feature metrics")
          .Choice("feature_metrics", &O::mode, {{"auto", Mode::kAuto}, {"on", Mode::kOn}, {"off", Mode::kOff}},
                  "IoU_drop_feat, acc_seg_feat, residual_feat: auto = when the scene has semantic features, on = "
                  "fail without them")
          .Choice("feature_prototype", &O::use_labels, {{"auto", true}, {"removal", false}},
                  "target prototype: auto = the --labels object, else the --positive prompts' Gaussians, else the "
                  "removed set; removal = as without labels")
          .Int("feature_k", &O::kmeans_k, R::Closed(1, 256),
               "without labels: k-means clusters (of the set's neighbourhood, and of the views) that compete with "
               "the target")
          .Int("feature_hops", &O::candidate_hops, R::Closed(1, 16), "growth steps of the target's neighbourhood")
          .Real("feature_merge_sim", &O::merge_similarity, R::Closed(-1, 1),
                "without labels: clusters at least this close to the target prototype count as its kept part");
  return table;
}

void FeatureEvalOptions::Check() const {
  Table().Check(*this);
  field.Check();
  segmentation.Check();
}

FeatureScorer::FeatureScorer(const Scene& scene, const FeaturePrototypeInput& in, const FeatureEvalOptions& o)
    : options_(o) {
  o.Check();
  Timer timer;
  const bool has_labels = o.use_labels && in.labels != nullptr && !in.labels->empty();
  const bool has_set = !o.target_set.empty();
  if (o.mode == FeatureEvalOptions::Mode::kOff) {
    skip_reason_ = "turned off (--feature-metrics off)";
  } else if (scene.features.cols() == 0) {
    skip_reason_ = "the scene has no semantic features (semantic_*, obj_dc_*, ...)";
  } else if (scene.features.rows() != static_cast<Eigen::Index>(scene.size())) {
    throw Error("feature metrics: the scene's features have " + std::to_string(scene.features.rows()) +
                " rows for " + std::to_string(scene.size()) + " Gaussians");
  } else if (!has_labels && !has_set && (in.removed == nullptr || std::none_of(in.removed->begin(), in.removed->end(),
                                                                                [](bool b) { return b; }))) {
    skip_reason_ = "no target prototype: the removal is empty and neither --labels nor prompts were given";
  }
  if (!skip_reason_.empty()) {
    if (o.mode == FeatureEvalOptions::Mode::kOn)
      throw Error("feature metrics requested but impossible: " + skip_reason_, ExitCode::kUsage);
    return;
  }
  const std::size_t n = scene.size();
  if ((has_labels && in.labels->size() != n) || (has_set && o.target_set.size() != n) ||
      (in.removed != nullptr && in.removed->size() != n))
    throw Error("feature metrics: labels / sets do not match the scene's " + std::to_string(n) + " Gaussians");
  field_ = PrepareFeatureField(scene.features, o.field);
  static const std::vector<Camera> kNoCameras;
  const std::vector<Camera>& cams = in.cameras ? *in.cameras : kNoCameras;
  if (has_labels) {
    std::vector<bool> target(n);
    for (std::size_t i = 0; i < n; ++i) target[i] = (*in.labels)[i] == in.object_id;
    prototypes_ = FromLabels(field_.channels, *in.labels, in.object_id, NearSet(scene, target, o.candidate_hops),
                             prototype_info_);
  } else {
    const std::vector<bool>& set = has_set ? o.target_set : *in.removed;
    prototypes_ = FromSet(scene, field_.channels, set, cams, has_set ? o.target_set_source : "removed set", o,
                          prototype_info_);
  }
  prototype_info_["count"] = prototypes_.rows.rows();
  prototype_info_["names"] = prototypes_.names;
  enabled_ = true;
  seconds_ = timer.Seconds();
}

metrics::Mask FeatureScorer::Segment(const RenderOutput& r) const {
  if (!enabled_ || r.feature_dim != field_.dim()) throw Error("feature metrics: the render has no feature image");
  const metrics::FeatureImage image{r.width, r.height, r.feature_dim, r.feature.data(), r.alpha.data()};
  return metrics::SegmentTarget(image, prototypes_, options_.segmentation);
}

FeatureViewMetrics FeatureScorer::Score(const metrics::Mask& object, const metrics::Mask& before,
                                        const metrics::Mask& after, const std::string& view) const {
  FeatureViewMetrics m;
  m.record = metrics::ScoreFeatureSegmentation(object, before, after, view);
  m.target_pixels_after = after.Count();
  return m;
}

json FeatureEvalOptions::ToJson() const {
  json j = Table().ToJson(*this);
  j.update(FeatureFieldOptions::Table().ToJson(field));
  j.update(metrics::FeatureSegOptions::Table().ToJson(segmentation));
  if (!target_set_source.empty()) j["feature_target_set"] = target_set_source;
  return j;
}

json FeatureScorer::ToJson() const {
  const json options = options_.ToJson();
  if (!enabled_) return {{"skipped", skip_reason_}, {"options", options}};
  return {{"field", field_.ToJson()}, {"prototypes", prototype_info_}, {"options", options}, {"seconds", seconds_}};
}

}  // namespace al::eval
