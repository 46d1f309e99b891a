// FindSecondObject (al/graph/removed_parts.hpp). Sequential sums in node order: the result does
// not depend on the thread count.
#include "al/graph/removed_parts.hpp"

#include <algorithm>
#include <cmath>

#include "al/graph/disjoint_sets.hpp"

namespace al {
namespace {

// Part root of every removed node (−1 for kept ones), over short kNN edges between removed nodes.
std::vector<std::int32_t> RemovedParts(const KnnResult& knn, double median_edge, const std::vector<double>& removed) {
  const std::size_t V = removed.size();
  const double link = kPartLinkScale * median_edge, link_sq = link * link;
  ConcurrentDisjointSets sets(V);
  const auto vv = static_cast<std::int64_t>(V);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t u = 0; u < vv; ++u) {
    if (removed[std::size_t(u)] < 0.5) continue;
    for (int c = 0; c < knn.k; ++c) {
      const std::size_t at = std::size_t(u) * std::size_t(knn.k) + std::size_t(c);
      const std::int32_t v = knn.neighbors[at];
      if (v < 0 || removed[std::size_t(v)] < 0.5 || knn.sq_dist[at] > link_sq)
        continue;
      sets.Unite(std::int32_t(u), v);
    }
  }
  std::vector<std::int32_t> part(V, -1);
#pragma omp parallel for schedule(static)
  for (std::int64_t u = 0; u < vv; ++u)
    if (removed[std::size_t(u)] >= 0.5) part[std::size_t(u)] = sets.Find(std::int32_t(u));
  return part;
}

// Mean unit feature of the nodes of one part (zero rows carry no direction).
Eigen::VectorXd PartMean(const std::vector<std::int32_t>& part, std::int32_t root,
                         Eigen::Ref<const RowMatXf> features, const std::vector<std::int64_t>& node_ids) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(features.cols());
  for (std::size_t u = 0; u < part.size(); ++u) {
    if (part[u] != root) continue;
    const Eigen::VectorXd f = features.row(Eigen::Index(node_ids[u])).transpose().cast<double>();
    const double norm = f.norm();
    if (norm > 0 && std::isfinite(norm)) sum += f / norm;
  }
  return sum;
}

std::vector<std::int64_t> SceneRowsOf(const std::vector<std::int32_t>& part, std::int32_t root,
                                      const std::vector<std::int64_t>& node_ids) {
  std::vector<std::int64_t> rows;
  for (std::size_t u = 0; u < part.size(); ++u)
    if (part[u] == root) rows.push_back(node_ids[u]);
  // Graph nodes are numbered in ascending scene row, so the rows usually arrive sorted.
  if (!std::is_sorted(rows.begin(), rows.end())) std::sort(rows.begin(), rows.end());
  return rows;
}

double Cosine(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double n = a.norm() * b.norm();
  return n > 0 ? a.dot(b) / n : 1.0;  // no direction: no evidence of a second object
}

}  // namespace

SecondObject FindSecondObject(const KnnResult& knn, double median_edge, const std::vector<double>& removed,
                              Eigen::Ref<const RowMatXf> features, const std::vector<std::int64_t>& node_ids) {
  SecondObject out;
  const std::vector<std::int32_t> part = RemovedParts(knn, median_edge, removed);
  std::vector<std::size_t> size(part.size(), 0);
  std::size_t n_removed = 0;
  for (std::int32_t p : part)
    if (p >= 0) ++size[std::size_t(p)], ++n_removed;
  if (n_removed == 0) return out;
  const auto largest = std::int32_t(std::max_element(size.begin(), size.end()) - size.begin());
  std::vector<std::int32_t> big{largest};  // the largest part, then the others large enough to be an object
  for (std::size_t r = 0; r < size.size(); ++r)
    if (std::int32_t(r) != largest && double(size[r]) >= kSecondShare * double(n_removed)) big.push_back(std::int32_t(r));
  // One part per thread, each summed in node order: the same doubles as one after the other.
  std::vector<Eigen::VectorXd> mean(big.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t b = 0; b < big.size(); ++b) mean[b] = PartMean(part, big[b], features, node_ids);
  std::int32_t second = -1;
  for (std::size_t b = 1; b < big.size(); ++b) {
    const auto r = std::size_t(big[b]);
    const double cosine = Cosine(mean[b], mean[0]);
    if (cosine >= kSameObjectCosine || (out.Found() && cosine >= out.cosine)) continue;
    out = {size[r], size[std::size_t(largest)], double(size[r]) / double(n_removed), cosine, {}, {}};
    second = std::int32_t(r);
  }
  if (out.Found()) {
    out.largest_scene_rows = SceneRowsOf(part, largest, node_ids);
    out.second_scene_rows = SceneRowsOf(part, second, node_ids);
  }
  return out;
}

FeatureGroupParts FindWholeObjectGroup(const PriorStats& prior, const std::vector<double>& upper,
                                       const std::vector<double>& removed, const std::vector<std::int64_t>& node_ids) {
  FeatureGroupParts out;
  if (!prior.kept_credit || prior.prototype_rows == 0 || upper.size() != removed.size() ||
      prior.removal_rate_upper < kWholeGroupRate || prior.separation < kApartSeparation)
    return out;
  for (std::size_t u = 0; u < removed.size(); ++u)  // node order = ascending scene rows
    if (removed[u] >= 0.5) (upper[u] >= 0.5 ? out.object_rows : out.other_rows).push_back(node_ids[u]);
  return out;
}

nlohmann::json FeatureGroupParts::ToJson() const {
  if (!Found()) return nullptr;
  return {{"object_rows", object_rows.size()}, {"other_rows", other_rows.size()}};
}

nlohmann::json SecondObject::ToJson() const {
  if (!Found()) return nullptr;
  return {{"rows", rows}, {"largest_rows", largest_rows}, {"share", share}, {"cosine", cosine}};
}

}  // namespace al
