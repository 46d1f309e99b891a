// RunDemo (al/demo/demo.hpp): synth → refine (bk, cp) → eval → summary, as one output set.
#include "al/demo/demo.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr const char* kMethod = "gc";  // the simulator whose removal the demo refines

void Step(const DemoOptions& o, const std::string& line) {
  if (o.on_step) o.on_step(line);
}

std::vector<DemoRefineRun> RefineWithBothSolvers(const DemoOptions& o, const fs::path& out, const fs::path& scene_dir) {
  std::vector<DemoRefineRun> runs;
  for (const std::string solver : {"bk", "cp"}) {
    Timer t;
    RefineOptions ro;
    ro.scene = (scene_dir / "scene.ply").string();
    ro.removed = (scene_dir / (std::string("removed_") + kMethod + ".npy")).string();
    ro.method = kMethod;
    ro.solver = solver;
    ro.labels = (scene_dir / "labels.npy").string();
    ro.out_dir = (out / ("refine_" + solver)).string();
    Step(o, "demo: refine --method " + std::string(kMethod) + " --solver " + solver + " ...");
    runs.push_back({solver, RunRefine(ro), 0});
    runs.back().seconds = t.Seconds();
  }
  return runs;
}

// The GC removal and both refinements (object masks from synth, ground truth from labels).
eval::EvalResult EvaluateAll(const DemoOptions& o, const fixtures::SynthScene& synth, const fs::path& out,
                             const fs::path& scene_dir, const std::vector<DemoRefineRun>& runs) {
  std::vector<eval::EvalColumn> columns = {{"after", kMethod, synth.removed.at(kMethod), "", ""}};
  for (const DemoRefineRun& r : runs)
    columns.push_back({r.solver, std::string(kMethod) + "+" + r.solver, r.result.refined, "", ""});
  eval::ObjectSource object;
  object.masks_dir = (scene_dir / "masks").string();
  object.labels = synth.labels;
  object.object_id = synth.target_id;
  eval::EvalOptions eo;
  eo.out_dir = (out / "eval").string();
  eo.row_name = synth.preset + "-" + synth.target_name;
  eo.progress = o.progress;
  Step(o, "demo: eval ...");
  return eval::RunEval(synth.scene, synth.cameras, columns, object, eo);
}

// One summary row per removal: what the evaluator measured and, for a refinement, what changed.
json SummaryRows(const eval::EvalResult& er, const std::vector<DemoRefineRun>& runs) {
  json summary = json::array();
  const json& cols = er.report["metrics"]["columns"];
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const json& col = cols[c];
    json s = {{"label", col["label"]},
              {"residual_gt", col["residual_gt"]["mean"]},  // the headline: what is left of the object
              {"residual_px", col["residual_px"]["mean"]},
              {"num_removed", col["num_removed"]},
              {"gt", col["gt"]},
              {"acc_delta_depth", col["depth"]["mean_acc_delta_depth"]},
              {"acc_delta_depth_float", col["depth_float"]["mean_acc_delta_depth"]},
              {"collateral_depth", col["depth"]["collateral_depth"]["mean"]}};
    if (col.contains("feature")) {  // segmentation of the scene's own rendered feature field (docs/eval.md)
      s["iou_drop_feat"] = col["feature"]["mean_iou_drop"];
      s["acc_seg_feat"] = col["feature"]["acc_seg"];
      s["residual_feat"] = col["feature"]["mean_residual"];
    }
    if (col.contains("residual_est")) s["residual_est"] = col["residual_est"]["mean"];
    if (c > 0) {
      s["added"] = col["added"];
      s["change"] = runs[c - 1].result.report["gt"]["change"];
      s["refine_status"] = runs[c - 1].result.status;
      s["refine_seconds"] = runs[c - 1].seconds;
    }
    summary.push_back(s);
  }
  return summary;
}

json DemoReport(const DemoOptions& o, const DemoResult& r, const fs::path& final_out, double total_s) {
  json report = NewReport("demo");
  report["params"] = {{"out", o.out_dir},
                      {"preset", o.synth.preset},
                      {"gaussians", o.synth.num_gaussians},
                      {"seed", o.synth.seed},
                      {"views", o.synth.num_views},
                      {"resolution", std::to_string(o.synth.width) + "x" + std::to_string(o.synth.height)},
                      {"method", kMethod},
                      {"solvers", {"bk", "cp"}}};
  report["counts"] = {{"num_gaussians", o.synth.num_gaussians},
                      {"target_gaussians", r.target_gaussians},
                      {"views", r.num_views},
                      {"evaluated_views", r.eval.evaluated}};
  report["summary"] = r.summary;
  report["timings_s"] = {{"synth", r.synth_seconds}, {"refine_bk", r.runs[0].seconds},
                         {"refine_cp", r.runs[1].seconds}, {"eval", r.eval_seconds}, {"total", total_s}};
  report["outputs"] = {{"scene", (final_out / "scene").string()},
                       {"refine_bk", (final_out / "refine_bk").string()},
                       {"refine_cp", (final_out / "refine_cp").string()},
                       {"eval", (final_out / "eval").string()}, {"report_html", r.page}};
  return report;
}

}  // namespace

void DemoOptions::Check() const {
  if (out_dir.empty()) throw Error("demo: --out is required", ExitCode::kUsage);
  synth.Check();
}

DemoResult RunDemo(const DemoOptions& o) {
  o.Check();
  OutputSetOptions so;
  so.command = "demo";
  so.planned = {"scene", "refine_bk", "refine_cp", "eval", "report.json"};
  OutputSet set(o.out_dir, so);
  // Written into the staging folder; the commit renames it to --out (and fixes nested reports' paths).
  const fs::path out = set.dir(), final_out = set.out(), scene_dir = out / "scene";
  Timer total, t;
  DemoResult r;
  r.out_dir = o.out_dir;
  r.page = (final_out / "eval" / "report.html").string();  // the page to open first
  Step(o, "report: " + r.page);
  Step(o, "demo: generating a " + o.synth.preset + " scene with " + std::to_string(o.synth.num_gaussians) +
              " Gaussians, " + std::to_string(o.synth.num_views) + " views " + std::to_string(o.synth.width) + "x" +
              std::to_string(o.synth.height) + " ...");
  const fixtures::SynthScene synth = fixtures::SynthesizeToFolder(o.synth, scene_dir.string()).synth;
  r.synth_seconds = t.Seconds();
  r.row = synth.preset + "-" + synth.target_name;
  r.target_name = synth.target_name;
  r.target_gaussians = synth.objects[std::size_t(synth.target_id)].count;
  r.num_views = synth.cameras.size();
  r.runs = RefineWithBothSolvers(o, out, scene_dir);
  t.Reset();
  r.eval = EvaluateAll(o, synth, out, scene_dir, r.runs);
  r.eval_seconds = t.Seconds();
  r.summary = SummaryRows(r.eval, r.runs);
  r.report = DemoReport(o, r, final_out, total.Seconds());
  set.Commit(r.report);
  return r;
}

}  // namespace al
