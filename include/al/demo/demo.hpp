// The whole job on a generated scene (README "./al demo"): synth → refine the simulated
// GaussianCut removal with bk and cp → eval of the three removals → a summary. GC's errors are
// residuals refinement can recover (its missed contact band), so the summary says how many of the
// method's misses came back and how precise the additions were.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/eval/eval.hpp"
#include "al/fixtures/synth.hpp"
#include "al/refine/refine.hpp"

namespace al {

struct DemoOptions {
  std::string out_dir = "demo_out";
  fixtures::SynthOptions synth = [] {
    fixtures::SynthOptions o;
    o.preset = "room";
    o.num_gaussians = 200000;
    o.num_views = 12;
    o.width = 320;
    o.height = 240;
    return o;
  }();
  bool progress = true;                                // eval's progress bar
  std::function<void(const std::string& line)> on_step;  // one line per step (library code never prints)
  void Check() const;  // out_dir given, and the synth options
};

struct DemoRefineRun {
  std::string solver;
  RefineResult result;
  double seconds = 0;
};

struct DemoResult {
  std::string out_dir, page;          // the committed folder and its eval/report.html
  std::string row, target_name;
  std::size_t target_gaussians = 0, num_views = 0;
  std::vector<DemoRefineRun> runs;    // bk, cp
  eval::EvalResult eval;
  nlohmann::json summary;             // per removal: counts, ground truth, change, depth and feature metrics
  double synth_seconds = 0, eval_seconds = 0;
  nlohmann::json report;              // demo/report.json
  std::string BriefReport() const;    // the summary table, timings and where to look
};

// Runs the demo into one output set at options.out_dir. Throws al::Error on bad options.
DemoResult RunDemo(const DemoOptions& options);

}  // namespace al
