// `al-refine metrics --dir SCENE_DIR [--out DIR]`: the evaluator's metrics (METRICS.md) on renders
// made by another pipeline, read from the released per-scene layout; writes semantic.json,
// depth.json, sam.json (and collateral.json), plus report.json with the summary.
#include <chrono>
#include <filesystem>
#include <iostream>

#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/metrics/directory.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class MetricsCommand : public Command {
 public:
  std::string Name() const override { return "metrics"; }
  std::string Description() const override {
    return "Metrics (IoU_drop, acc_seg, sim_SAM, acc_delta_depth, collateral) on renders in the published layout";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--dir", dir_, "Scene directory (masks/, gsam2/, depth/, sam/)")->required();
    app.add_option("--out", out_, "Output directory (default: DIR/al_metrics)");
    app.add_option("--object-masks", o_.object_masks, "Object masks, relative to DIR")->default_str("masks");
    seg_flags_[0] = app.add_option("--seg-before", o_.seg_before, "Detector masks before removal (named: must exist)")
                        ->default_str("gsam2/before/mask");
    seg_flags_[1] = app.add_option("--seg-after", o_.seg_after, "Detector masks after removal (named: must exist)")
                        ->default_str("gsam2/after/mask");
    app.add_option("--seg-class", o_.seg_class, "GroundedSAM JSON class to keep (default: all instances)");
    app.add_option("--depth-before", o_.depth_before, "8-bit depth before removal")->default_str("depth/before");
    app.add_option("--depth-after", o_.depth_after, "8-bit depth after removal")->default_str("depth/after");
    app.add_option("--sam-a", o_.sam_a, "SAM segment lists, side A (\"gt\")")->default_str("masks");
    app.add_option("--sam-b", o_.sam_b, "SAM segment lists, side B (\"sam\")")->default_str("sam/after");
    app.add_option("--rgb-before", o_.rgb_before, "RGB renders before removal (collateral PSNR)");
    app.add_option("--rgb-after", o_.rgb_after, "RGB renders after removal (collateral PSNR)");
    app.add_option("--sam-min-iou", o_.sim_sam.min_object_iou, "sim_SAM filter: min IoU with the object")
        ->default_val(0.10);
    app.add_option("--ght-nu", o_.ght.nu, "GHT nu")->default_val(1000.0);
    app.add_option("--ght-tau", o_.ght.tau, "GHT tau")->default_val(300.0);
    app.add_option("--depth-holes", holes_,
                   "Depth 0 = no depth. before: |delta| = 0 only where the depth before is missing, so a pixel "
                   "whose depth vanished counts as a change (released evaluator); both: also where the depth "
                   "after is missing (al-refine before issue 16)")
        ->check(CLI::IsMember({"before", "both"}))->capture_default_str();
    app.add_option("--trust-min-object-pixels", o_.trust.min_object_pixels,
                   "acc_delta_depth trust flag small_object below this many object pixels")->capture_default_str();
    app.add_option("--trust-max-outside-share", o_.trust.max_outside_share,
                   "Flag change_outside_object above this share of changed pixels outside the object")
        ->capture_default_str();
    app.add_option("--trust-min-object-peak", o_.trust.min_object_peak,
                   "Flag stretch_outside_object below this object peak / image peak change")->capture_default_str();
    app.add_option("--trust-min-object-median", o_.trust.min_object_median,
                   "Flag object_change_compressed below this object median / image peak change")->capture_default_str();
  }
  int Run() override {
    namespace fs = std::filesystem;
    const auto start = std::chrono::steady_clock::now();
    o_.dir = dir_;
    o_.seg_folders_named = seg_flags_[0]->count() + seg_flags_[1]->count() > 0;
    o_.depth_holes = *metrics::DepthHolesFromName(holes_);
    const fs::path out = out_.empty() ? fs::path(dir_) / "al_metrics" : fs::path(out_);
    OutputSet set(out, OutputSetOptions("metrics", {dir_}, {"semantic.json", "depth.json", "sam.json", "collateral.json", "report.json"}));
    const metrics::DirectoryMetricsResult r = metrics::EvaluateDirectory(o_);
    const auto files = metrics::WriteDirectoryMetrics(r, set.dir());

    nlohmann::json report = NewReport("metrics");
    report["params"] = o_.ToJson();
    report["params"]["out"] = out.string();
    report["inputs"]["dir"] = {{"path", dir_}};
    report["counts"] = r.counts;
    report["metrics"] = metrics::SummaryJson(r);
    report["outputs"] = nlohmann::json::array();
    for (const auto& f : files) report["outputs"].push_back((out / f.filename()).string());
    for (const auto& w : r.warnings) report["warnings"].push_back(w);
    report["timings_s"]["total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    set.Commit(report);

    const auto& m = report["metrics"];
    if (m.contains("semantic"))
      std::cout << "semantic: " << m["semantic"]["n_images"] << " images, IoU_drop " << m["semantic"]["mean_iou_drop"]
                << ", acc_seg@0.5 " << m["semantic"]["acc_seg"]["0.5"] << "\n";
    if (m.contains("depth"))
      std::cout << "depth:    " << m["depth"]["n_images"] << " images, acc_delta_depth "
                << m["depth"]["mean_acc_delta_depth"] << " (depth holes: " << holes_ << "; "
                << m["depth"]["trust"]["flagged_images"] << " flagged as untrustworthy)\n";
    if (m.contains("sim_sam"))
      std::cout << "sim_SAM:  " << m["sim_sam"]["n_scored"] << " scored (" << m["sim_sam"]["dropped_empty_side"]
                << " dropped), mean " << m["sim_sam"]["mean_sim_sam"] << "\n";
    for (const auto& s : r.skipped) std::cout << "skipped " << s.metric << ": " << s.reason << "\n";
    for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
    std::cout << "wrote " << (out / "report.json").string() << "\n";
    return 0;
  }

 private:
  std::string dir_, out_, holes_ = "before";
  CLI::Option* seg_flags_[2] = {nullptr, nullptr};
  metrics::DirectoryMetricsOptions o_;
};

AL_REGISTER_COMMAND(MetricsCommand);

}  // namespace al::cli
