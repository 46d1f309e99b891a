#include "al/eval/report_json.hpp"

#include <cstdio>
#include <sstream>
#include <vector>

#include "al/eval/view_metric.hpp"

namespace al::eval {

using json = nlohmann::json;

namespace {

json MeanStdJson(const metrics::MeanStd& m) { return {{"mean", m.mean}, {"std", m.std}, {"count", m.count}}; }

json DepthSummaryJson(const metrics::DepthSummary& s, const std::string& mode, const EvalOptions& o) {
  json j = s.ToJson("view");
  j["mode"] = mode;
  j["depth_holes"] = metrics::DepthHolesName(o.depth_holes);
  return j;
}

json SemanticSummaryJson(const metrics::SemanticSummary& s) {
  json seg = json::object(), table = json::object();
  auto key = [](double t) {
    std::ostringstream o;
    o << t;
    return o.str();
  };
  for (const auto& t : s.acc_seg) seg[key(t.threshold)] = t.value;
  for (const auto& t : s.acc_iou_post_above) table[key(t.threshold)] = t.value;
  return {{"n_images", s.images},          {"mean_iou_before", s.iou_before}, {"mean_iou_after", s.iou_after},
          {"mean_iou_drop", s.iou_drop},    {"mean_acc_before", s.acc_before}, {"mean_acc_after", s.acc_after},
          {"mean_acc_diff", s.acc_diff},    {"acc_seg", seg},                  {"acc_iou_post_above_percent", table},
          {"missing_before", s.missing_before}, {"missing_after", s.missing_after}};
}

// The feature metrics of a column: the GroundedSAM fields with the feature segmentation as the
// detector (suffix-free names inside the "feature" object), plus the residual.
json FeatureSummaryJson(const metrics::FeatureSummary& s) {
  json j = SemanticSummaryJson(s.semantic);
  j.erase("missing_before");
  j.erase("missing_after");
  j["mean_residual"] = s.residual.mean;
  j["std_residual"] = s.residual.std;
  j["n_residual_views"] = s.residual.count;
  j["views_without_target_before"] = s.views_without_target;
  return j;
}

}  // namespace

void AddEvalParams(json& report, const std::vector<EvalColumn>& columns, const ObjectSource& object,
                   const EvalOptions& o) {
  json& params = report["params"];
  if (!params.is_object()) params = json::object();
  params["row_name"] = o.row_name;
  params["columns"] = json::array();
  for (const auto& c : columns)
    params["columns"].push_back({{"name", c.name}, {"label", c.label}, {"seg_dir", c.seg_dir}, {"sam_dir", c.sam_dir}});
  params["seg_before"] = o.seg_before_dir;
  params["sam_before"] = o.sam_before_dir;
  params["seg_class"] = o.seg_class;
  params["object_masks"] = object.masks_dir.empty() ? json("rendered from labels (share >= 0.5)") : json(object.masks_dir);
  if (object.masks_dir.empty()) params["object_id"] = object.object_id;
  params["background"] = {o.render.background.x(), o.render.background.y(), o.render.background.z()};
  params["max_sh_degree"] = o.render.max_sh_degree;
  params["ght"] = {{"nu", o.ght.nu}, {"tau", o.ght.tau}, {"kappa", o.ght.kappa}, {"omega", o.ght.omega}};
  params["depth_norm"] = metrics::DepthNormName(o.float_depth.depth_norm);
  params["alpha_hit"] = o.float_depth.alpha_hit;
  params["depth_holes"] = metrics::DepthHolesName(o.depth_holes);
  params["depth_trust"] = o.trust.ToJson();
  params["sam_min_iou"] = o.sim_sam.min_object_iou;
  params["export_renders"] = o.export_renders;
  params["feature"] = o.feature.ToJson();
  params["residual"] = metrics::ResidualOptions::Table().ToJson(o.residual);
  params["write_images"] = o.write_images;
}

json ColumnSummaryJson(const EvalColumn& column, const ColumnSummary& s, const EvalOptions& o) {
  json j = {{"name", column.name},
            {"label", column.label},
            {"num_removed", s.num_removed},
            {"depth", DepthSummaryJson(s.depth8, "8bit", o)},
            {"depth_float", DepthSummaryJson(s.depth_float, "float", o)},
            {"collateral_psnr", {{"psnr", MeanStdJson(s.collateral_psnr)}, {"identical", s.identical}}}};
  j["depth_float"]["depth_norm"] = metrics::DepthNormName(o.float_depth.depth_norm);
  if (s.semantic) j["semantic"] = SemanticSummaryJson(*s.semantic);
  if (s.feature) j["feature"] = FeatureSummaryJson(*s.feature);
  if (!s.view_metrics.empty()) {  // the plug-in metrics (al/eval/view_metric.hpp)
    json& vm = j["view_metrics"];
    for (std::size_t k = 0; k < s.view_metrics.size(); ++k) vm[ViewMetrics()[k].name] = MeanStdJson(s.view_metrics[k]);
  }
  if (s.sim_sam)
    j["sim_sam"] = {{"n_scored", s.sim_sam->count},
                    {"mean_sim_sam", s.sim_sam->mean},
                    {"std_sim_sam", s.sim_sam->std},
                    {"dropped_empty_side", s.sim_sam_dropped},
                    {"missing_lists", s.sim_sam_missing},
                    {"direction", "SAM segments of the before render vs this column's render: lower = better "
                                  "removal (paper)"}};
  return j;
}

namespace {

// "0.123" for a residual's mean in a column summary, "-" when it was not computed or not scored.
std::string ResidualText(const json& column, const std::string& key) {
  if (!column.contains(key) || !column[key]["mean"].is_number()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", column[key]["mean"].get<double>());
  return buf;
}

}  // namespace

std::string EvalResult::BriefReport(const std::string& row, std::size_t num_views) const {
  std::string out;
  char line[640];
  std::snprintf(line, sizeof line, "eval %s: %zu of %zu views evaluated (%zu without the object)\n", row.c_str(),
                evaluated, num_views, skipped_empty_object + missing_object_masks);
  out += line;
  // The headline residual first (what is left of the object: 0 = gone), the paper's figures beside it.
  std::vector<std::string> residuals = {headline};
  for (const char* k : {"residual_gt", "residual_est", "residual_px"})
    if (k != headline) residuals.push_back(k);
  std::snprintf(line, sizeof line, "  %-16s %9s %12s %12s %12s %9s %10s %11s %9s %11s %10s\n", "removal", "removed",
                residuals[0].c_str(), residuals[1].c_str(), residuals[2].c_str(), "acc_dd", "acc_dd_f", "coll_depth",
                "IoU_drop", "IoU_drop_ft", "resid_ft");
  out += line;
  auto field = [](const json& c, const char* group, const char* key) {
    return c.contains(group) ? std::to_string(c[group][key].get<double>()).substr(0, 6) : std::string("-");
  };
  for (const auto& c : report["metrics"]["columns"]) {
    std::snprintf(line, sizeof line, "  %-16s %9zu %12s %12s %12s %9.3f %10.3f %11.4f %9s %11s %10s\n",
                  c["label"].get<std::string>().c_str(), c["num_removed"].get<std::size_t>(),
                  ResidualText(c, residuals[0]).c_str(), ResidualText(c, residuals[1]).c_str(),
                  ResidualText(c, residuals[2]).c_str(), c["depth"]["mean_acc_delta_depth"].get<double>(),
                  c["depth_float"]["mean_acc_delta_depth"].get<double>(),
                  c["depth"]["collateral_depth"]["mean"].get<double>(), field(c, "semantic", "mean_iou_drop").c_str(),
                  field(c, "feature", "mean_iou_drop").c_str(), field(c, "feature", "mean_residual").c_str());
    out += line;
  }
  for (const auto& s : skipped)
    if (s.column == "after") out += "  skipped " + s.metric + ": " + s.reason + "\n";
  return out;
}

}  // namespace al::eval
