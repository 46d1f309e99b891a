// Aggregation of per-image acc_Δdepth records (METRICS.md §4 step 6) with the trust flags.
#include <map>

#include "al/metrics/depth.hpp"

namespace al::metrics {

namespace {
nlohmann::json MeanStdJson(const MeanStd& m) { return {{"mean", m.mean}, {"std", m.std}, {"count", m.count}}; }
}  // namespace

DepthSummary SummarizeDepth(const std::vector<DepthRecord>& records) {
  DepthSummary s;
  s.images = records.size();
  std::vector<double> acc, iou, col, trusted;
  for (const auto& r : records) {
    acc.push_back(r.score.acc_delta_depth);
    iou.push_back(r.score.iou);
    col.push_back(r.score.collateral_depth);
    s.constant_masks += r.constant;
    s.missing_object += r.score.missing_object;
    s.holes_before += r.holes_before;
    s.holes_after += r.holes_after;
    if (r.trust.Trusted()) trusted.push_back(r.score.acc_delta_depth);
    else s.flagged.emplace_back(r.image, r.trust.Flags());
  }
  s.acc_delta_depth = ComputeMeanStd(acc);
  s.iou = ComputeMeanStd(iou);
  s.collateral_depth = ComputeMeanStd(col);
  s.acc_delta_depth_trusted = ComputeMeanStd(trusted);
  return s;
}

nlohmann::json DepthSummary::ToJson(const std::string& unit) const {
  std::map<std::string, std::size_t> counts;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [name, flags] : flagged) {
    for (const auto& f : flags) ++counts[f];
    list.push_back({{unit, name}, {"flags", flags}});
  }
  const nlohmann::json trusted_mean =
      acc_delta_depth_trusted.count ? nlohmann::json(acc_delta_depth_trusted.mean) : nlohmann::json(nullptr);
  return {{"n_images", images},
          {"mean_acc_delta_depth", acc_delta_depth.mean},
          {"std_acc_delta_depth", acc_delta_depth.std},
          {"mean_iou", iou.mean},
          {"std_iou", iou.std},
          {"collateral_depth", MeanStdJson(collateral_depth)},
          {"constant_masks", constant_masks},
          {"missing_object_masks", missing_object},
          {"hole_pixels", {{"before", holes_before}, {"after_only", holes_after}}},
          {"trust",
           {{"flagged_" + unit + "s", flagged.size()},
            {"trusted_" + unit + "s", acc_delta_depth_trusted.count},
            {"mean_acc_delta_depth_trusted", trusted_mean},
            {"flag_counts", counts},
            {"flagged", list}}}};
}

}  // namespace al::metrics
