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

// One table line per removal; refinements also show what changed and how long they took.
std::string SummaryTable(const DemoResult& r) {
  std::string text = Format("%-10s %8s %7s %8s %8s %8s %7s %7s %10s %10s %11s %11s %9s %9s\n", "removal", "removed",
                            "added", "restored", "miss_rec", "prec_add", "F1(GT)", "IoU(GT)", "acc_ddepth",
                            "acc_dd_flt", "collat_dep", "IoU_drop_ft", "resid_ft", "refine_s");
  const json& cols = r.eval.report["metrics"]["columns"];
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const json& col = cols[c];
    const json change = c == 0 ? json() : r.runs[c - 1].result.report["gt"]["change"];
    auto cell = [&](const char* key, const char* fmt) {
      return c > 0 && change[key].is_number() ? Format(fmt, change[key].get<double>()) : std::string("-");
    };
    const std::string secs = c > 0 ? Format("%.2f", r.runs[c - 1].seconds) : "-";
    const bool feat = col.contains("feature");
    text += Format("%-10s %8zu %7s %8s %8s %8s %7.3f %7.3f %10.3f %10.3f %11.4f %11.3f %9.3f %9s\n",
                   col["label"].get<std::string>().c_str(), col["num_removed"].get<std::size_t>(),
                   cell("added", "%.0f").c_str(), cell("restored", "%.0f").c_str(),
                   cell("misses_recovered", "%.3f").c_str(), cell("precision_added", "%.3f").c_str(),
                   col["gt"]["f1"].get<double>(), col["gt"]["iou"].get<double>(),
                   col["depth"]["mean_acc_delta_depth"].get<double>(),
                   col["depth_float"]["mean_acc_delta_depth"].get<double>(),
                   col["depth"]["collateral_depth"]["mean"].get<double>(),
                   feat ? col["feature"]["mean_iou_drop"].get<double>() : NAN,
                   feat ? col["feature"]["mean_residual"].get<double>() : NAN, secs.c_str());
  }
  return text;
}

std::string WhereToLook(const DemoResult& r) {
  const std::filesystem::path shown(r.out_dir);
  std::string text = "features: IoU_drop_ft = drop of the target's IoU in the scene's own rendered feature field, "
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
  for (const DemoRefineRun& run : runs)
    if (run.result.exit_code != 0) text += "note: refine with " + run.solver + ": " + run.result.message + "\n";
  text += Format("timings: synth %.1f s, refine bk %.1f s, cp %.1f s, eval %.1f s (render %.1f, metrics %.1f, io %.1f)\n",
                 synth_seconds, runs[0].seconds, runs[1].seconds, eval_seconds, eval.seconds_render,
                 eval.seconds_metrics, eval.seconds_io);
  return text + WhereToLook(*this);
}

}  // namespace al
