// Evaluator metrics of one refined set (al/refine/sweep.hpp): a thin use of eval::RunEval with
// every file output turned off, for sweep points and `refine --auto`.
#include <filesystem>

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
  return {{"acc_delta_depth", s.depth8.acc_delta_depth.mean},
          {"acc_delta_depth_float", s.depth_float.acc_delta_depth.mean},
          {"collateral_depth", s.depth8.collateral_depth.mean},
          {"collateral_psnr", s.collateral_psnr.count ? nlohmann::json(s.collateral_psnr.mean) : nlohmann::json()},
          {"views_evaluated", r.evaluated},
          {"views_skipped", r.skipped_empty_object + r.missing_object_masks}};
}

}  // namespace al
