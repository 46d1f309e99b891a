// `al-refine eval --scene S --removed R [--refined [NAME=]F]... --cameras C (--object-masks DIR |
// --labels GT.npy [--object-id I]) [segmentations] --out DIR` (SPEC §6): flags → al::eval::RunEval.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/eval/eval.hpp"
#include "al/eval/inputs.hpp"
#include "al/io/cameras.hpp"
#include "al/io/masks.hpp"
#include "al/io/ply.hpp"
#include "src/cli/background_flag.hpp"
#include "src/cli/command.hpp"
#include "src/cli/feature_flags.hpp"

namespace al::cli {

class EvalCommand : public Command {
 public:
  std::string Name() const override { return "eval"; }
  std::string Description() const override {
    return "Score a removal (and its refinements): renders before/after/refined, acc_delta_depth, collateral "
           "damage, feature-field IoU_drop/acc_seg/residual, IoU_drop and sim_SAM when segmentations are given; "
           "report.json, metrics.csv, table.md/.tex, images";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", scene_, "Full pre-removal scene (.ply or .splat)")->required();
    app.add_option("--removed", removed_, "The removal method's set (.npy mask/indices, .txt, subset .ply)")
        ->required();
    app.add_option("--removed-is", removed_is_, "Whether --removed lists removed or remaining Gaussians")
        ->check(CLI::IsMember({"removed", "remaining"}))
        ->default_val("removed");
    app.add_option("--label", label_, "Table name of the removal method (default: from the file, "
                                      "removed_fgs.npy -> fgs)");
    app.add_option("--refined", refined_, "Refined removed set (refine's refined.npy); NAME=FILE names it; "
                                          "repeat for several")
        ->take_all();
    app.add_option("--cameras", cameras_, "Cameras: INRIA cameras.json, COLMAP folder, or JSON list")->required();
    app.add_option("--views", views_, "Comma-separated view names, or all")->default_val("all");
    app.add_option("--object-masks", object_masks_, "Folder of object masks VIEW.png (> 0 = object)");
    app.add_option("--labels", labels_, "Ground-truth labels .npy: object masks are rendered (share >= 0.5) and "
                                        "the report scores each removal against them");
    app.add_option("--object-id", object_id_, "Target object id (else target.json beside --labels)");
    app.add_option("--seg-before", seg_before_, "Detector (GroundedSAM) masks of the before renders");
    app.add_option("--seg-after", seg_after_, "Detector masks of the after renders");
    app.add_option("--seg-refined", seg_refined_, "Detector masks of the refined renders (one per --refined)")
        ->take_all();
    app.add_option("--seg-class", seg_class_, "GroundedSAM JSON class to keep (default: all instances)");
    app.add_option("--sam-before", sam_before_, "SAM segment lists of the before renders");
    app.add_option("--sam-after", sam_after_, "SAM segment lists of the after renders");
    app.add_option("--sam-refined", sam_refined_, "SAM segment lists of the refined renders (one per --refined)")
        ->take_all();
    app.add_flag("--export-renders", o_.export_renders,
                 "Also write renders/{before,after,refined}/VIEW.png for external segmenters");
    app.add_flag("--no-images", no_images_, "Skip the per-view pictures (images/)");
    app.add_option("--row-name", row_name_, "Table row (default: PRESET-OBJECT from target.json, else the scene name)");
    app.add_option("--bg", bg_, "Background: 0 (black), 1 (white) or r,g,b")->default_val("0");
    app.add_option("--sh-degree", o_.render.max_sh_degree, "Maximum SH degree evaluated")
        ->check(CLI::Range(0, 3))
        ->default_val(3);
    app.add_option("--threads", o_.render.num_threads, "OpenMP threads (0 = default)")->check(CLI::NonNegativeNumber);
    app.add_option("--depth-norm", depth_norm_, "Float-mode depth normaliser: maxdiff | range")
        ->check(CLI::IsMember({"maxdiff", "range"}))
        ->default_val("maxdiff");
    app.add_option("--depth-holes", holes_, "before: a pixel with depth before and none after is a depth change "
                                            "(released evaluator); both: it is ignored")
        ->check(CLI::IsMember({"before", "both"}))->capture_default_str();
    app.add_option("--alpha-hit", o_.float_depth.alpha_hit, "A pixel has depth iff alpha > this")->default_val(0.0);
    app.add_option("--ght-nu", o_.ght.nu, "GHT nu")->default_val(1000.0);
    app.add_option("--ght-tau", o_.ght.tau, "GHT tau")->default_val(300.0);
    app.add_option("--out", o_.out_dir, "Output directory")->required();
    app.add_flag("--quiet", quiet_, "No progress bar");
    AddFeatureFlags(app, feature_);
  }

  int Run() override {
    if (object_masks_.empty() && labels_.empty())
      throw Error("eval: give --object-masks DIR or --labels GT.npy (which pixels are the object)", ExitCode::kUsage);
    if (seg_refined_.size() > refined_.size() || sam_refined_.size() > refined_.size())
      throw Error("eval: more --seg-refined/--sam-refined folders than --refined sets", ExitCode::kUsage);
    o_.render.background = ParseBackground(bg_);
    o_.float_depth.depth_norm = depth_norm_ == "range" ? metrics::DepthNorm::kRange : metrics::DepthNorm::kMaxDiff;
    o_.depth_holes = *metrics::DepthHolesFromName(holes_);
    o_.write_images = !no_images_;
    o_.progress = !quiet_;
    o_.seg_before_dir = seg_before_;
    o_.sam_before_dir = sam_before_;
    o_.seg_class = seg_class_;
    o_.input_paths = {scene_, removed_, cameras_, object_masks_, labels_, seg_after_, sam_after_};
    for (const auto* list : {&refined_, &seg_refined_, &sam_refined_})
      for (const auto& p : *list) o_.input_paths.push_back(eval::SplitNamedPath(p).second);
    { OutputSet preflight(o_.out_dir, eval::EvalOutputSetOptions(o_)); }  // --out checked before loading

    nlohmann::json report = NewReport("eval");
    Timer t;
    Scene scene = ReadScene(scene_);
    AddInputFile(report, "scene", scene_);
    const double load_scene_s = t.Seconds();
    t.Reset();
    CameraLoadResult loaded = ReadCameras(cameras_);
    for (const auto& w : loaded.warnings) report["warnings"].push_back(w);
    const std::vector<Camera> views = SelectViews(loaded.cameras, views_);
    if (std::filesystem::is_regular_file(cameras_)) AddInputFile(report, "cameras", cameras_);

    std::vector<eval::EvalColumn> columns;
    RemovalLoadOptions ro;
    ro.removed_is = removed_is_ == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
    RemovalSet removal = LoadRemovalSet(removed_, scene, ro);
    for (const auto& w : removal.warnings) report["warnings"].push_back(w);
    if (std::filesystem::is_regular_file(removed_)) AddInputFile(report, "removed", removed_);
    const std::string method = label_.empty() ? eval::ColumnLabelFromPath(removed_) : label_;
    columns.push_back({"after", method, std::move(removal.removed), seg_after_, sam_after_});
    for (std::size_t i = 0; i < refined_.size(); ++i) {
      auto [name, path] = eval::SplitNamedPath(refined_[i]);
      if (name.empty()) name = refined_.size() == 1 ? "refined" : "refined" + std::to_string(i + 1);
      RemovalSet set = LoadRemovalSet(path, scene, {});
      for (const auto& w : set.warnings) report["warnings"].push_back(w);
      if (std::filesystem::is_regular_file(path)) AddInputFile(report, "refined_" + name, path);
      columns.push_back({name, method + "+" + name, std::move(set.removed),
                         i < seg_refined_.size() ? seg_refined_[i] : "", i < sam_refined_.size() ? sam_refined_[i] : ""});
    }

    eval::ObjectSource object;
    object.masks_dir = object_masks_;
    if (!object_masks_.empty()) report["inputs"]["object_masks"] = {{"path", object_masks_}};
    std::string row = row_name_;
    if (!labels_.empty()) {
      object.labels = eval::LoadLabels(labels_, scene.size());
      AddInputFile(report, "labels", labels_);
      const eval::TargetInfo target = eval::ResolveTarget(
          labels_, object_id_ == kUnset ? std::nullopt : std::optional<int>(object_id_));
      object.object_id = target.object_id;
      if (row.empty() && !target.name.empty())
        row = (target.preset.empty() ? std::filesystem::path(scene_).parent_path().filename().string() : target.preset) +
              "-" + target.name;
    }
    if (row.empty() && labels_.empty()) {
      // A synth scene names its target in target.json beside scene.ply.
      const std::filesystem::path target = std::filesystem::path(scene_).parent_path() / "target.json";
      if (std::filesystem::is_regular_file(target)) {
        try {
          const eval::TargetInfo t = eval::ResolveTarget(target.string(), std::nullopt);
          if (!t.name.empty() && !t.preset.empty()) row = t.preset + "-" + t.name;
        } catch (const Error&) {  // not a synth target file: fall back to the folder name
        }
      }
    }
    if (row.empty()) row = std::filesystem::path(scene_).parent_path().filename().string();
    if (row.empty()) row = std::filesystem::path(scene_).stem().string();
    o_.row_name = row;
    o_.feature = ToFeatureOptions(feature_, scene);
    const double load_inputs_s = t.Seconds();

    report["params"] = {{"scene", scene_},          {"removed", removed_},   {"removed_is", removed_is_},
                        {"label", method},          {"refined", refined_},   {"cameras", cameras_},
                        {"views", views_},          {"labels", labels_},     {"bg", bg_},
                        {"threads", o_.render.num_threads}, {"no_images", no_images_}};
    report["timings_s"] = {{"load_scene", load_scene_s}, {"load_inputs", load_inputs_s}};
    const eval::EvalResult r = eval::RunEval(scene, views, columns, object, o_, &report);

    for (const auto& w : r.report["warnings"]) std::fprintf(stderr, "warning: %s\n", w.get<std::string>().c_str());
    const auto& cols = r.report["metrics"]["columns"];
    std::printf("eval %s: %zu of %zu views evaluated (%zu without the object)\n", row.c_str(), r.evaluated,
                views.size(), r.skipped_empty_object + r.missing_object_masks);
    std::printf("  %-16s %9s %9s %10s %11s %9s %11s %10s\n", "removal", "removed", "acc_dd", "acc_dd_f",
                "coll_depth", "IoU_drop", "IoU_drop_ft", "resid_ft");
    auto field = [](const nlohmann::json& c, const char* group, const char* key) {
      return c.contains(group) ? std::to_string(c[group][key].get<double>()).substr(0, 6) : std::string("-");
    };
    for (const auto& c : cols)
      std::printf("  %-16s %9zu %9.3f %10.3f %11.4f %9s %11s %10s\n", c["label"].get<std::string>().c_str(),
                  c["num_removed"].get<std::size_t>(), c["depth"]["mean_acc_delta_depth"].get<double>(),
                  c["depth_float"]["mean_acc_delta_depth"].get<double>(),
                  c["depth"]["collateral_depth"]["mean"].get<double>(), field(c, "semantic", "mean_iou_drop").c_str(),
                  field(c, "feature", "mean_iou_drop").c_str(), field(c, "feature", "mean_residual").c_str());
    for (const auto& s : r.skipped)
      if (s.column == "after") std::printf("  skipped %s: %s\n", s.metric.c_str(), s.reason.c_str());
    std::printf("wrote %s/{report.json, metrics.csv, table.md, table.tex, images/}\n", o_.out_dir.c_str());
    return 0;
  }

 private:
  static constexpr int kUnset = -2147483647;
  std::string scene_, removed_, removed_is_ = "removed", label_, cameras_, views_ = "all";
  std::vector<std::string> refined_, seg_refined_, sam_refined_;
  std::string object_masks_, labels_, seg_before_, seg_after_, seg_class_, sam_before_, sam_after_;
  std::string row_name_, bg_ = "0", depth_norm_ = "maxdiff", holes_ = "before";
  int object_id_ = kUnset;
  bool no_images_ = false, quiet_ = false;
  eval::EvalOptions o_;
  FeatureFlags feature_;
};

AL_REGISTER_COMMAND(EvalCommand);

}  // namespace al::cli
