// `al-refine eval --scene S --removed R [--refined [NAME=]F]... --cameras C (--object-masks DIR |
// --labels GT.npy [--object-id I]) [segmentations] --out DIR` (SPEC §6): flags → al::eval::RunEval.
#include <iostream>

#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/eval/eval.hpp"
#include "al/eval/inputs.hpp"
#include "src/cli/background_flag.hpp"
#include "src/cli/command.hpp"
#include "src/cli/warnings.hpp"
#include "src/cli/feature_flags.hpp"
#include "src/cli/option_flags.hpp"

namespace al::cli {

class EvalCommand : public Command {
 public:
  std::string Name() const override { return "eval"; }
  std::string Description() const override {
    return "Score a removal (and its refinements): what is left of the object -- residual_gt (with --labels: "
           "share of the object's visible signal still there, against the render without it), residual_est (the "
           "same against the first --refined render), residual_px (object-mask pixels whose colour and depth did "
           "not change) --, beside the paper's acc_delta_depth, IoU_drop and sim_SAM (given segmentations), "
           "collateral damage and the feature-field metrics; report.json, metrics.csv, table.md/.tex, report.html";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", files_.scene, "Full pre-removal scene (.ply or .splat)")->required();
    app.add_option("--removed", files_.removed, "The removal method's set (.npy mask/indices, .txt, subset .ply)")
        ->required();
    app.add_option("--removed-is", files_.removed_is, "Whether --removed lists removed or remaining Gaussians")
        ->check(CLI::IsMember({"removed", "remaining"}))
        ->default_val("removed");
    app.add_option("--label", files_.label, "Table name of the removal method (default: from the file, "
                                      "removed_fgs.npy -> fgs)");
    app.add_option("--refined", files_.refined, "Refined removed set (refine's refined.npy); NAME=FILE names it; "
                                          "repeat for several. The first is residual_est's ideal (the "
                                          "object as the refinement sees it)")
        ->take_all();
    app.add_option("--cameras", files_.cameras, "Cameras: INRIA cameras.json, COLMAP folder, or JSON list")->required();
    app.add_option("--views", files_.views, "Comma-separated view names, or all")->default_val("all");
    app.add_option("--object-masks", files_.object_masks, "Folder of object masks VIEW.png (> 0 = object)");
    app.add_option("--labels", files_.labels, "Ground-truth labels .npy: object masks are rendered (share >= 0.5), "
                                        "residual_gt is measured against the render without the object, and the "
                                        "report scores each removal against them");
    app.add_option("--object-id", files_.object_id, "Target object id (else target.json beside --labels)");
    app.add_option("--seg-before", o_.seg_before_dir, "Detector (GroundedSAM) masks of the before renders");
    app.add_option("--seg-after", files_.seg_after, "Detector masks of the after renders");
    app.add_option("--seg-refined", files_.seg_refined, "Detector masks of the refined renders (one per --refined)")
        ->take_all();
    app.add_option("--seg-class", o_.seg_class, "GroundedSAM JSON class to keep (default: all instances)");
    app.add_option("--sam-before", o_.sam_before_dir, "SAM segment lists of the before renders");
    app.add_option("--sam-after", files_.sam_after, "SAM segment lists of the after renders");
    app.add_option("--sam-refined", files_.sam_refined, "SAM segment lists of the refined renders (one per --refined)")
        ->take_all();
    app.add_flag("--export-renders", o_.export_renders,
                 "Also write renders/{before,after,refined}/VIEW.png for external segmenters");
    app.add_flag("--no-images", no_images_, "Skip the per-view pictures (images/)");
    app.add_option("--row-name", files_.row_name, "Table row (default: PRESET-OBJECT from target.json, else the scene name)");
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
    AddOptionFlags(app, metrics::ResidualOptions::Table(), o_.residual, "Residuals");
  }

  int Run() override {
    o_.render.background = ParseBackground(bg_);
    o_.float_depth.depth_norm = depth_norm_ == "range" ? metrics::DepthNorm::kRange : metrics::DepthNorm::kMaxDiff;
    o_.depth_holes = *metrics::DepthHolesFromName(holes_);
    o_.write_images = !no_images_;
    o_.progress = !quiet_;
    files_.Check();
    o_.input_paths = files_.Paths();
    { OutputSet preflight(o_.out_dir, eval::EvalOutputSetOptions(o_)); }  // --out checked before loading
    eval::EvalInputs in = eval::LoadEvalInputs(files_);
    o_.row_name = in.row;
    o_.feature = ToFeatureOptions(feature_, in.scene);
    in.report["params"].update({{"bg", bg_}, {"threads", o_.render.num_threads}, {"no_images", no_images_}});
    const eval::EvalResult r = eval::RunEval(in.scene, in.views, in.columns, in.object, o_, &in.report);
    PrintReportWarnings(r.report);
    std::cout << r.BriefReport(in.row, in.views.size());
    std::printf("wrote %s/{report.json, report.html, metrics.csv, table.md, table.tex, images/}\n", o_.out_dir.c_str());
    return 0;
  }

 private:
  eval::EvalFiles files_;
  std::string bg_ = "0", depth_norm_ = "maxdiff", holes_ = "before";
  bool no_images_ = false, quiet_ = false;
  eval::EvalOptions o_;
  FeatureFlags feature_;
};

AL_REGISTER_COMMAND(EvalCommand);

}  // namespace al::cli
