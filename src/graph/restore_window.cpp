// InRestoreWindow (al/graph/restore_window.hpp).
#include "al/graph/restore_window.hpp"

#include <tuple>

#include "src/graph/robust_stats.hpp"

namespace al {

nlohmann::json RestoreWindowStats::ToJson() const {
  return {{"prototype_rows", prototype_rows}, {"median", median}, {"sigma", sigma}, {"floor", floor}, {"kept", kept}};
}

namespace {

// The removed rows' unit features and their mean direction (zero when none is usable).
Eigen::VectorXd Prototype(const SceneFeatureMap& map, const std::vector<bool>& removed,
                          const std::vector<std::uint8_t>& active, std::size_t& rows) {
  const Eigen::Index D = map.features.cols();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(D);
  Eigen::VectorXf f(D);
  rows = 0;
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (removed[i] && active[i] && map.Row(std::int64_t(i), f.data())) sum += f.cast<double>(), ++rows;
  const double norm = sum.norm();
  return norm > 0 && std::isfinite(norm) ? Eigen::VectorXd(sum / norm) : Eigen::VectorXd::Zero(D);
}

}  // namespace

std::vector<std::uint8_t> InRestoreWindow(const SceneFeatureMap& map, const std::vector<bool>& removed,
                                          const std::vector<std::uint8_t>& active,
                                          const std::vector<std::int64_t>& rows, double mads,
                                          RestoreWindowStats* stats) {
  std::vector<std::uint8_t> inside(rows.size(), 0);
  RestoreWindowStats st;
  const Eigen::VectorXf proto = Prototype(map, removed, active, st.prototype_rows).cast<float>();
  if (proto.isZero()) {
    if (stats) *stats = st;
    return inside;
  }
  Eigen::VectorXf f(map.features.cols());
  std::vector<double> cos;
  cos.reserve(st.prototype_rows);
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (removed[i] && active[i] && map.Row(std::int64_t(i), f.data())) cos.push_back(double(f.dot(proto)));
  std::tie(st.median, st.sigma) = MedianAndSpread(std::move(cos));
  st.floor = st.median - mads * st.sigma;
  for (std::size_t t = 0; t < rows.size(); ++t)
    if (map.Row(rows[t], f.data()) && double(f.dot(proto)) >= st.floor) inside[t] = 1, ++st.kept;
  if (stats) *stats = st;
  return inside;
}

}  // namespace al
