// DemoResult::BriefReport (al/demo/demo.hpp): the summary table the demo prints, and where to look.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "al/demo/demo.hpp"

namespace al {
namespace {

using json = nlohmann::json;

std::string Format(const char* fmt, auto... args) {
  char line[512];
  std::snprintf(line, sizeof line, fmt, args...);
  return line;
}

double MeanOf(const json& col, const char* key) {
  return col.contains(key) && col[key]["mean"].is_number() ? col[key]["mean"].get<double>() : NAN;
}

// One table line per removal, led by residual_gt (what is left of the object, from the ground
// truth); refinements also show what changed and how long they took.
std::string SummaryTable(const DemoResult& r) {
  std::string text = Format("%-10s %11s %11s %7s %7s %8s %7s %8s %8s %8s %10s %10s %11s %11s %9s %9s\n", "removal",
                            "residual_gt", "residual_px", "F1(GT)", "IoU(GT)", "removed", "added", "restored",
                            "miss_rec", "prec_add", "acc_ddepth", "acc_dd_flt", "collat_dep", "IoU_drop_ft",
                            "resid_ft", "refine_s");
  const json& cols = r.eval.report["metrics"]["columns"];
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const json& col = cols[c];
    const json change = c == 0 ? json() : r.runs[c - 1].result.report["gt"]["change"];
    auto cell = [&](const char* key, const char* fmt) {
      return c > 0 && change[key].is_number() ? Format(fmt, change[key].get<double>()) : std::string("-");
    };
    const std::string secs = c > 0 ? Format("%.2f", r.runs[c - 1].seconds) : "-";
    const bool feat = col.contains("feature");
    text += Format("%-10s %11.4f %11.4f %7.3f %7.3f %8zu %7s %8s %8s %8s %10.3f %10.3f %11.4f %11.3f %9.3f %9s\n",
                   col["label"].get<std::string>().c_str(), MeanOf(col, "residual_gt"), MeanOf(col, "residual_px"),
                   col["gt"]["f1"].get<double>(), col["gt"]["iou"].get<double>(), col["num_removed"].get<std::size_t>(),
                   cell("added", "%.0f").c_str(), cell("restored", "%.0f").c_str(),
                   cell("misses_recovered", "%.3f").c_str(), cell("precision_added", "%.3f").c_str(),
                   col["depth"]["mean_acc_delta_depth"].get<double>(),
                   col["depth_float"]["mean_acc_delta_depth"].get<double>(),
                   col["depth"]["collateral_depth"]["mean"].get<double>(),
                   feat ? col["feature"]["mean_iou_drop"].get<double>() : NAN,
                   feat ? col["feature"]["mean_residual"].get<double>() : NAN, secs.c_str());
  }
  return text;
}

// One line per refinement: does it leave less of the object than the method's removal, by
// residual_gt, and does that agree with F1?
std::string Verdicts(const DemoResult& r) {
  std::string text;
  const json& cols = r.eval.report["metrics"]["columns"];
  const double res0 = MeanOf(cols[0], "residual_gt"), f10 = cols[0]["gt"]["f1"].get<double>();
  for (std::size_t c = 1; c < cols.size(); ++c) {
    const double res = MeanOf(cols[c], "residual_gt"), f1 = cols[c]["gt"]["f1"].get<double>();
    const char* verdict = res < res0 ? "leaves less of the object" : res > res0 ? "leaves MORE of the object"
                                                                                : "leaves as much of the object";
    text += Format("%s: %s than %s (residual_gt %.4f -> %.4f; F1 %.3f -> %.3f)\n",
                   cols[c]["label"].get<std::string>().c_str(), verdict, cols[0]["label"].get<std::string>().c_str(),
                   res0, res, f10, f1);
  }
  return text;
}

std::string WhereToLook(const DemoResult& r) {
  const std::filesystem::path shown(r.out_dir);
  std::string text = "residual_gt = share of the object's visible signal still there (0 = gone, 1 = untouched; "
                     "against the render without it), residual_px = share of its mask whose colour and depth did not "
                     "change; the paper's acc_ddepth (8-bit) and acc_dd_flt (float) beside them (docs/eval.md)\n";
  text += "features: IoU_drop_ft = drop of the target's IoU in the scene's own rendered feature field, "
                     "resid_ft = share of its before-pixels still segmented as it after (lower = less left)\n";
  text += "open first: " + r.page + " (summary, every view side by side, residual and added overlays)\n";
  text += "images: " + (shown / "eval" / "images").string() +
          "/  (VIEW_before/_after/_bk/_cp.png, _depthdiff.png, _bk_added.png = pink: added by bk, "
          "cyan: restored, _featseg.png = feature segmentation before | after, red = residual)\n";
  text += "tables: " + (shown / "eval" / "table.md").string() + ", " + (shown / "eval" / "table.tex").string() +
          "; scene: " + (shown / "scene").string() + "; refinements: " + (shown / "refine_bk").string() + ", " +
          (shown / "refine_cp").string() + "\n";
  return text;
}

}  // namespace

std::string DemoResult::BriefReport() const {
  std::string text = Format("\n%s: target '%s' (%zu Gaussians), %zu of %zu views show it\n", row.c_str(),
                            target_name.c_str(), target_gaussians, eval.evaluated, num_views);
  text += SummaryTable(*this);
  text += Verdicts(*this);
  for (const DemoRefineRun& run : runs)
    if (run.result.exit_code != 0) text += "note: refine with " + run.solver + ": " + run.result.message + "\n";
  text += Format("timings: synth %.1f s, refine bk %.1f s, cp %.1f s, eval %.1f s (render %.1f, metrics %.1f, io %.1f)\n",
                 synth_seconds, runs[0].seconds, runs[1].seconds, eval_seconds, eval.seconds_render,
                 eval.seconds_metrics, eval.seconds_io);
  return text + WhereToLook(*this);
}

}  // namespace al
