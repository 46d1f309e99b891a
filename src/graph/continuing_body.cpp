// MeasureContinuingBody (al/graph/continuing_body.hpp).
#include "al/graph/continuing_body.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "src/graph/row_tree.hpp"

namespace al {

nlohmann::json ContinuingBody::ToJson() const {
  return {{"added", added}, {"body", body}, {"ratio", Ratio()}, {"continues", Continues()}};
}

namespace {

// The additions' unit features (rows of a D-column matrix; zero rows dropped) and their mean direction.
struct AdditionFeatures {
  RowMatXf rows;
  Eigen::VectorXf mean;  // unit; zero when no usable row
};

AdditionFeatures FeaturesOf(const SceneFeatureMap& map, const std::vector<std::int64_t>& added) {
  const Eigen::Index D = map.features.cols();
  AdditionFeatures out{RowMatXf(Eigen::Index(added.size()), D), Eigen::VectorXf::Zero(D)};
  Eigen::Index used = 0;
  for (std::int64_t row : added)
    if (map.Row(row, out.rows.row(used).data())) ++used;
  out.rows.conservativeResize(used, D);
  if (used == 0) return out;
  out.mean = out.rows.colwise().sum().transpose();
  const float norm = out.mean.norm();
  if (norm > 0 && std::isfinite(norm)) out.mean /= norm; else out.mean.setZero();
  return out;
}

// The kContinuingPercentile-th percentile of the additions' cosines to their mean (nearest rank).
float CosineFloor(const AdditionFeatures& f) {
  Eigen::VectorXf cos = f.rows * f.mean;
  std::vector<float> v(cos.data(), cos.data() + cos.size());
  const auto rank = static_cast<std::size_t>(std::floor(kContinuingPercentile / 100.0 * double(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(rank), v.end());
  return v[rank];
}

}  // namespace

ContinuingBody MeasureContinuingBody(const ContinuingBodyInputs& in) {
  ContinuingBody out;
  std::vector<std::int64_t> added;
  for (std::size_t i = 0; i < in.refined.size(); ++i)
    if (in.refined[i] && !in.removed[i] && in.active[i]) added.push_back(std::int64_t(i));
  out.added = added.size();
  const AdditionFeatures f = FeaturesOf(in.features, added);
  if (f.rows.rows() == 0 || f.mean.isZero()) return out;
  const float floor = CosineFloor(f);
  const auto cap = static_cast<std::size_t>(std::ceil(kContinuingRatio * double(added.size())));
  SceneKnn knn(in.xyz, in.active);
  std::vector<std::uint8_t> seen(in.refined.begin(), in.refined.end());  // the refined set is no body
  std::vector<float> feature(std::size_t(in.features.features.cols()));
  const auto similar = [&](std::int64_t row) {
    return in.features.Row(row, feature.data()) &&
           Eigen::Map<const Eigen::VectorXf>(feature.data(), f.mean.size()).dot(f.mean) >= floor;
  };
  // Breadth-first from the additions (their kept neighbours first), through similar kept rows.
  std::deque<std::int64_t> queue(added.begin(), added.end());
  std::vector<std::int64_t> nb;
  while (!queue.empty() && out.body < cap) {
    const std::int64_t u = queue.front();
    queue.pop_front();
    knn.Neighbours(u, in.k, nb);
    for (std::int64_t v : nb) {
      if (seen[std::size_t(v)]) continue;
      seen[std::size_t(v)] = 1;
      if (!similar(v)) continue;
      queue.push_back(v);
      if (++out.body >= cap) break;
    }
  }
  return out;
}

}  // namespace al
