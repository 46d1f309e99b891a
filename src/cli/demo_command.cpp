// `al-refine demo --out DIR`: the whole job on a generated scene (README "./al demo"): synth →
// refine the simulated GaussianCut removal with bk and cp → eval of the three removals → a short
// summary. GC's errors are residuals refinement can recover (its missed contact band; issue 13):
// the summary says how many of the method's misses came back and how precise the additions were.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>

#include "al/core/output_set.hpp"
#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/eval/eval.hpp"
#include "al/fixtures/synth.hpp"
#include "al/refine/refine.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

constexpr const char* kMethod = "gc";  // the simulator whose removal the demo refines

class DemoCommand : public Command {
 public:
  std::string Name() const override { return "demo"; }
  std::string Description() const override {
    return "Generate a synthetic room, refine its simulated GaussianCut removal with bk and cp, evaluate all "
           "three and print a summary (outputs under --out)";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--out", out_, "Output folder")->default_val("demo_out");
    app.add_option("--gaussians", synth_.num_gaussians, "Scene size")->check(CLI::Range(1000, 10000000))
        ->capture_default_str();
    app.add_option("--seed", synth_.seed, "Random seed")->capture_default_str();
    app.add_option("--views", synth_.num_views, "Camera views")->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--resolution", resolution_, "Image size WxH")->capture_default_str();
    app.add_flag("--quiet", quiet_, "No progress bars");
  }

  int Run() override {
    namespace fs = std::filesystem;
    std::smatch m;
    static const std::regex re("^([0-9]+)x([0-9]+)$");
    if (!std::regex_match(resolution_, m, re)) throw Error("demo: --resolution must look like 320x240", ExitCode::kUsage);
    synth_.width = std::stoi(m[1].str());
    synth_.height = std::stoi(m[2].str());
    OutputSetOptions so;
    so.command = "demo";
    so.planned = {"scene", "refine_bk", "refine_cp", "eval", "report.json"};
    OutputSet set(out_, so);
    // Written into the staging folder; the commit renames it to --out (and fixes nested reports' paths).
    const fs::path out = set.dir(), final_out = set.out(), scene_dir = out / "scene";
    Timer total, t;

    // The page to open first: everything below in one place (written by eval at the end).
    const std::string page = (final_out / "eval" / "report.html").string();
    std::printf("report: %s\n", page.c_str());
    // 1. The scene, its ground truth, object masks and the simulated removals.
    std::printf("demo: generating a %s scene with %zu Gaussians, %d views %dx%d ...\n", synth_.preset.c_str(),
                synth_.num_gaussians, synth_.num_views, synth_.width, synth_.height);
    std::fflush(stdout);
    const fixtures::SynthScene synth = fixtures::SynthesizeToFolder(synth_, scene_dir.string()).synth;
    const double synth_s = t.Seconds();

    // 2. Refine the GC removal with both solvers.
    struct Run {
      std::string solver;
      RefineResult result;
      double seconds = 0;
    };
    std::vector<Run> runs;
    for (const std::string solver : {"bk", "cp"}) {
      t.Reset();
      RefineOptions ro;
      ro.scene = (scene_dir / "scene.ply").string();
      ro.removed = (scene_dir / (std::string("removed_") + kMethod + ".npy")).string();
      ro.method = kMethod;
      ro.solver = solver;
      ro.labels = (scene_dir / "labels.npy").string();
      ro.out_dir = (out / ("refine_" + solver)).string();
      std::printf("demo: refine --method %s --solver %s ...\n", kMethod, solver.c_str());
      std::fflush(stdout);
      runs.push_back({solver, RunRefine(ro), 0});
      runs.back().seconds = t.Seconds();
    }

    // 3. Evaluate the GC removal and both refinements (object masks from synth, ground truth from labels).
    t.Reset();
    std::vector<eval::EvalColumn> columns = {{"after", kMethod, synth.removed.at(kMethod), "", ""}};
    for (const Run& r : runs) columns.push_back({r.solver, std::string(kMethod) + "+" + r.solver, r.result.refined, "", ""});
    eval::ObjectSource object;
    object.masks_dir = (scene_dir / "masks").string();
    object.labels = synth.labels;
    object.object_id = synth.target_id;
    eval::EvalOptions eo;
    eo.out_dir = (out / "eval").string();
    eo.row_name = synth.preset + "-" + synth.target_name;
    eo.progress = !quiet_;
    std::printf("demo: eval ...\n");
    std::fflush(stdout);
    const eval::EvalResult er = eval::RunEval(synth.scene, synth.cameras, columns, object, eo);
    const double eval_s = t.Seconds();

    // 4. Summary.
    const auto& cols = er.report["metrics"]["columns"];
    std::printf("\n%s: target '%s' (%zu Gaussians), %zu of %zu views show it\n", eo.row_name.c_str(),
                synth.target_name.c_str(), synth.objects[std::size_t(synth.target_id)].count, er.evaluated,
                synth.cameras.size());
    std::printf("%-10s %8s %7s %8s %8s %8s %7s %7s %10s %10s %11s %11s %9s %9s\n", "removal", "removed", "added",
                "restored", "miss_rec", "prec_add", "F1(GT)", "IoU(GT)", "acc_ddepth", "acc_dd_flt", "collat_dep",
                "IoU_drop_ft", "resid_ft", "refine_s");
    nlohmann::json summary = nlohmann::json::array();
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const auto& col = cols[c];
      const double refine_s = c == 0 ? 0.0 : runs[c - 1].seconds;
      const nlohmann::json change = c == 0 ? nlohmann::json() : runs[c - 1].result.report["gt"]["change"];
      auto cell = [&](const char* key, const char* fmt) {
        char b[32] = "-";
        if (c > 0 && change[key].is_number()) std::snprintf(b, sizeof b, fmt, change[key].get<double>());
        return std::string(b);
      };
      char secs[32] = "-";
      if (c > 0) std::snprintf(secs, sizeof secs, "%.2f", refine_s);
      // Feature metrics: segmentation of the scene's own rendered feature field (docs/eval.md).
      const bool feat = col.contains("feature");
      std::printf("%-10s %8zu %7s %8s %8s %8s %7.3f %7.3f %10.3f %10.3f %11.4f %11.3f %9.3f %9s\n",
                  col["label"].get<std::string>().c_str(), col["num_removed"].get<std::size_t>(),
                  cell("added", "%.0f").c_str(), cell("restored", "%.0f").c_str(), cell("misses_recovered", "%.3f").c_str(),
                  cell("precision_added", "%.3f").c_str(), col["gt"]["f1"].get<double>(),
                  col["gt"]["iou"].get<double>(), col["depth"]["mean_acc_delta_depth"].get<double>(),
                  col["depth_float"]["mean_acc_delta_depth"].get<double>(),
                  col["depth"]["collateral_depth"]["mean"].get<double>(),
                  feat ? col["feature"]["mean_iou_drop"].get<double>() : NAN,
                  feat ? col["feature"]["mean_residual"].get<double>() : NAN, secs);
      nlohmann::json s = {{"label", col["label"]},
                          {"num_removed", col["num_removed"]},
                          {"gt", col["gt"]},
                          {"acc_delta_depth", col["depth"]["mean_acc_delta_depth"]},
                          {"acc_delta_depth_float", col["depth_float"]["mean_acc_delta_depth"]},
                          {"collateral_depth", col["depth"]["collateral_depth"]["mean"]}};
      if (feat) {
        s["iou_drop_feat"] = col["feature"]["mean_iou_drop"];
        s["acc_seg_feat"] = col["feature"]["acc_seg"];
        s["residual_feat"] = col["feature"]["mean_residual"];
      }
      if (c > 0) {
        s["added"] = col["added"];
        s["change"] = change;
        s["refine_status"] = runs[c - 1].result.status;
        s["refine_seconds"] = refine_s;
      }
      summary.push_back(s);
    }
    for (const Run& r : runs)
      if (r.result.exit_code != 0) std::printf("note: refine with %s: %s\n", r.solver.c_str(), r.result.message.c_str());
    std::printf("timings: synth %.1f s, refine bk %.1f s, cp %.1f s, eval %.1f s (render %.1f, metrics %.1f, io %.1f)\n",
                synth_s, runs[0].seconds, runs[1].seconds, eval_s, er.seconds_render, er.seconds_metrics, er.seconds_io);
    std::printf("features: IoU_drop_ft = drop of the target's IoU in the scene's own rendered feature field, "
                "resid_ft = share of its before-pixels still segmented as it after (lower = less left)\n");
    std::printf("open first: %s (summary, every view side by side, residual and added overlays)\n", page.c_str());
    const fs::path shown(out_);
    std::printf("images: %s/  (VIEW_before/_after/_bk/_cp.png, _depthdiff.png, _bk_added.png = pink: added by bk, "
                "cyan: restored, _featseg.png = feature segmentation before | after, red = residual)\n",
                (shown / "eval" / "images").string().c_str());
    std::printf("tables: %s, %s; scene: %s; refinements: %s, %s\n", (shown / "eval" / "table.md").string().c_str(),
                (shown / "eval" / "table.tex").string().c_str(), (shown / "scene").string().c_str(),
                (shown / "refine_bk").string().c_str(), (shown / "refine_cp").string().c_str());

    nlohmann::json report = NewReport("demo");
    report["params"] = {{"out", out_},
                        {"preset", synth_.preset},
                        {"gaussians", synth_.num_gaussians},
                        {"seed", synth_.seed},
                        {"views", synth_.num_views},
                        {"resolution", resolution_},
                        {"method", kMethod},
                        {"solvers", {"bk", "cp"}}};
    report["counts"] = {{"num_gaussians", synth.labels.size()},
                        {"target_gaussians", synth.objects[std::size_t(synth.target_id)].count},
                        {"views", synth.cameras.size()},
                        {"evaluated_views", er.evaluated}};
    report["summary"] = summary;
    report["timings_s"] = {{"synth", synth_s}, {"refine_bk", runs[0].seconds}, {"refine_cp", runs[1].seconds},
                           {"eval", eval_s}, {"total", total.Seconds()}};
    report["outputs"] = {{"scene", (final_out / "scene").string()},
                         {"refine_bk", (final_out / "refine_bk").string()},
                         {"refine_cp", (final_out / "refine_cp").string()},
                         {"eval", (final_out / "eval").string()}, {"report_html", page}};
    set.Commit(report);
    return 0;
  }

 private:
  std::string out_ = "demo_out", resolution_ = "320x240";
  fixtures::SynthOptions synth_ = [] {
    fixtures::SynthOptions o;
    o.preset = "room";
    o.num_gaussians = 200000;
    o.num_views = 12;
    return o;
  }();
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(DemoCommand);

}  // namespace al::cli
