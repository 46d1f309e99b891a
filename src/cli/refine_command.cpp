// `al-refine refine` (also the default subcommand): flags -> RefineOptions -> RunRefine.
#include <iostream>

#include "al/core/error.hpp"
#include "al/refine/auto_tune.hpp"
#include "al/refine/refine.hpp"
#include "src/cli/command.hpp"
#include "src/cli/warnings.hpp"
#include "src/cli/refine_flags.hpp"

namespace al::cli {

class RefineCommand : public Command {
 public:
  std::string Name() const override { return "refine"; }
  std::string Description() const override {
    return "Refine a removal: candidates around the removed set, kNN + semantic graph, solver, "
           "threshold; writes refined.npy/.txt, added.txt, remaining.ply, report.json";
  }
  void Setup(CLI::App& app) override {
    AddInputFlags(app, flags_);
    AddGraphFlags(app, flags_);
    AddSolverFlags(app, flags_);
    AddDecisionFlags(app, flags_);
    app.add_option("--out", flags_.options.out_dir, "Output directory")->required();
    app.add_option("--export-problem", flags_.options.export_problem_dir,
                   "Also write the solvers' exact problem and p as .npy files into this directory "
                   "(first_edge, adj_vertices, edge_weights, y, node_weights, node_ids, params.json, p)");
    app.add_flag("--quiet", quiet_, "No progress lines");
    // --auto (al/refine/auto_tune.hpp): choose k, delta, lambda on a small grid without ground truth.
    app.add_flag("--auto", auto_, "Choose k, delta, lambda by an unsupervised criterion (evaluator with "
                 "--cameras, decision stability otherwise); report.json gets the chosen point and the runner-up");
    app.add_option("--auto-k", auto_k_, "--auto grid of k")->default_val("6,10,14");
    app.add_option("--auto-delta", auto_delta_, "--auto grid of delta")->default_val("0.8,1.0,1.2");
    app.add_option("--auto-lambda", auto_lambda_, "--auto grid of lambda")->default_val("0.5,1,2");
    app.add_option("--cameras", cameras_, "--auto: cameras for the evaluator criterion (object from "
                   "--object-masks, else --labels)");
    app.add_option("--object-masks", object_masks_, "--auto: folder of object mask PNGs");
    app.add_option("--views", views_, "--auto: views evaluated (all or comma-separated names)")->default_val("all");
  }

  int Run() override {
    RefineOptions o = ToRefineOptions(flags_);
    if (!quiet_)
      o.on_stage = [](const std::string& stage, double s) {
        if (s > 1.0) std::cerr << "refine  " << stage << "  " << s << " s\n";
      };
    if (!auto_ && (!cameras_.empty() || !object_masks_.empty()))
      throw Error("--cameras / --object-masks are for --auto (use `al-refine eval` to score a refinement)",
                  ExitCode::kUsage);
    const RefineResult r = auto_ ? RunAuto(o) : RunRefine(o);
    PrintReportWarnings(r.report, r.message);
    std::cout << r.BriefReport();
    (r.exit_code == 0 ? std::cout : std::cerr) << r.message << "\n";
    std::cout << "wrote " << o.out_dir << "/report.json\n";
    return r.exit_code;
  }

 private:
  RefineResult RunAuto(const RefineOptions& o) {
    AutoTuneOptions ao;
    ao.k.clear();
    for (double k : ParseAutoList("--auto-k", auto_k_)) {
      if (k != static_cast<int>(k)) throw Error("--auto-k: k must be integers", ExitCode::kUsage);
      ao.k.push_back(static_cast<int>(k));
    }
    ao.delta = ParseAutoList("--auto-delta", auto_delta_);
    ao.lambda = ParseAutoList("--auto-lambda", auto_lambda_);
    const AutoRefineOutcome a = RunAutoRefine(o, ao, cameras_, views_, object_masks_);
    const nlohmann::json j = a.tune.ToJson();
    auto show = [](const char* what, const nlohmann::json& c) {
      std::cout << what << " k " << c["k"] << ", delta " << c["delta"] << ", lambda " << c["lambda"] << "  score "
                << c["score"] << (c.contains("gt_f1") ? "  (ground-truth F1 " + c["gt_f1"].dump() + ")" : "") << "\n";
    };
    std::cout << "auto (" << a.tune.criterion << ", " << a.tune.candidates.size() << " points):\n";
    show("  chosen    ", j["chosen"]);
    show("  runner-up ", j["runner_up"]);
    if (j.contains("best_by_gt")) show("  best by ground truth (not used to choose)", j["best_by_gt"]);
    return a.refine;
  }

  RefineFlags flags_;
  bool quiet_ = false, auto_ = false;
  std::string auto_k_ = "6,10,14", auto_delta_ = "0.8,1.0,1.2", auto_lambda_ = "0.5,1,2";
  std::string cameras_, object_masks_, views_ = "all";
};

AL_REGISTER_COMMAND(RefineCommand);

}  // namespace al::cli
