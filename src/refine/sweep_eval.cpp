// Evaluator metrics of one refined set (al/refine/sweep.hpp): a thin use of eval::RunEval with
// every file output turned off, for sweep points and `refine --auto`.
#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "al/core/error.hpp"
#include "al/io/cameras.hpp"
#include "al/refine/sweep.hpp"

namespace al {

namespace fs = std::filesystem;

PointEvalSetup MakePointEvalSetup(const std::string& cameras, const std::string& views,
                                  const std::string& object_masks, const RefineInputs& inputs,
                                  const std::string& work_dir) {
  PointEvalSetup setup;
  CameraLoadResult loaded = ReadCameras(cameras);
  setup.cameras = SelectViews(loaded.cameras, views.empty() ? "all" : views);
  if (!object_masks.empty()) {
    setup.object.masks_dir = object_masks;
  } else if (inputs.ground_truth) {
    setup.object.labels = inputs.ground_truth->labels;
    setup.object.object_id = inputs.ground_truth->target;
  } else {
    throw Error(cameras + ": evaluating with cameras needs the object: give object masks or labels", ExitCode::kUsage);
  }
  setup.work_dir = work_dir;
  return setup;
}

nlohmann::json EvaluatePoint(const Scene& scene, const PointEvalSetup& setup, const std::vector<bool>& removed) {
  eval::EvalOptions o;
  o.out_dir = setup.work_dir;
  o.write_images = false;
  o.write_depth_pngs = false;
  o.progress = false;
  const std::vector<eval::EvalColumn> columns = {{"refined", "refined", removed, "", ""}};
  const eval::EvalResult r = eval::RunEval(scene, setup.cameras, columns, setup.object, o);
  std::error_code ec;
  fs::remove_all(setup.work_dir, ec);  // only the numbers are kept
  const eval::ColumnSummary& s = r.summaries.at(0);
  nlohmann::json views = nlohmann::json::array();
  for (const eval::ViewRecord& v : r.views) {
    if (!v.evaluated) continue;
    const eval::ColumnViewMetrics& m = v.columns.at(0);
    views.push_back({{"view", v.name},
                     {"acc_delta_depth_float", m.depth_float.acc_delta_depth},
                     {"collateral_depth", m.depth8.collateral_depth},
                     {"flags_float", m.trust_float.Flags()}});
  }
  return {{"acc_delta_depth", s.depth8.acc_delta_depth.mean},
          {"acc_delta_depth_float", s.depth_float.acc_delta_depth.mean},
          {"collateral_depth", s.depth8.collateral_depth.mean},
          {"collateral_psnr", s.collateral_psnr.count ? nlohmann::json(s.collateral_psnr.mean) : nlohmann::json()},
          {"views_evaluated", r.evaluated},
          {"views_skipped", r.skipped_empty_object + r.missing_object_masks},
          {"views_flagged_float", s.depth_float.flagged.size()},
          {"views", std::move(views)}};
}

std::optional<std::vector<double>> TrustedViewScores(const std::vector<nlohmann::json*>& evals) {
  // Views are matched by name; the evaluated set is the same for every candidate (same cameras and
  // object), so a view missing from one evaluation is treated as flagged.
  std::map<std::string, std::size_t> seen;
  std::set<std::string> flagged;
  for (const nlohmann::json* e : evals)
    for (const auto& v : e->at("views")) {
      const std::string name = v.at("view").get<std::string>();
      ++seen[name];
      if (!v.at("flags_float").empty()) flagged.insert(name);
    }
  std::vector<std::string> trusted;
  for (const auto& [name, count] : seen)
    if (count == evals.size() && !flagged.count(name)) trusted.push_back(name);
  if (trusted.empty()) return std::nullopt;
  std::vector<double> scores;
  for (nlohmann::json* e : evals) {
    double acc = 0, collateral = 0;
    for (const auto& v : e->at("views")) {
      collateral += v.at("collateral_depth").get<double>();
      if (std::binary_search(trusted.begin(), trusted.end(), v.at("view").get<std::string>()))
        acc += v.at("acc_delta_depth_float").get<double>();
    }
    const double n = double(std::max<std::size_t>(e->at("views").size(), 1));
    (*e)["score_views"] = trusted;
    (*e)["acc_delta_depth_float_trusted"] = acc / double(trusted.size());
    scores.push_back(acc / double(trusted.size()) - collateral / n);
  }
  return scores;
}

}  // namespace al
