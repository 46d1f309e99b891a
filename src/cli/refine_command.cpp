// `al-refine refine` (also the default subcommand): flags -> RefineOptions -> RunRefine.
#include <iostream>
#include <sstream>

#include "al/core/error.hpp"
#include "al/refine/refine.hpp"
#include "al/solver.hpp"
#include "src/cli/command.hpp"

namespace al::cli {

class RefineCommand : public Command {
 public:
  std::string Name() const override { return "refine"; }
  std::string Description() const override {
    return "Refine a removal: candidates around the removed set, kNN + semantic graph, solver, "
           "threshold; writes refined.npy/.txt, added.txt, remaining.ply, report.json";
  }
  void Setup(CLI::App& app) override {
    std::string solvers;
    for (const auto& n : SolverNames()) solvers += (solvers.empty() ? "" : "|") + n;
    app.add_option("--scene", o_.scene, "Full pre-removal scene (.ply or .splat): the index space")->required();
    app.add_option("--removed", o_.removed, "Removed set: mask/indices .npy, indices .txt or subset .ply");
    app.add_option("--removed-is", removed_is_, "A subset PLY holds the removed or the remaining Gaussians "
                   "(default: the preset's; gg: remaining)")->check(CLI::IsMember({"removed", "remaining"}));
    app.add_option("--method", o_.method, "Removal method preset: fgs|gg|sags|gc|generic")
        ->check(CLI::IsMember({"fgs", "gg", "sags", "gc", "generic"}))->default_val("generic");
    app.add_option("--features", o_.features, "auto | PREFIX | FILE.npy | FILE.ply (default: the preset's)");
    app.add_option("--decoder", o_.decoder, "W.npy,b.npy: per-Gaussian f' = W f + b (FGS speed-up models)");
    app.add_option("--k", o_.graph.k, "Neighbours per node")->default_val(10);
    app.add_option("--delta", o_.graph.delta, "Semantic gate (distance of unit features)")->default_val(0.8);
    app.add_option("--delta-mode", delta_mode_, "distance | cosine")
        ->check(CLI::IsMember({"distance", "cosine"}))->default_val("distance");
    app.add_option("--lambda", o_.graph.lambda, "Edge weight scale")->default_val(1.0);
    app.add_option("--spatial", spatial_, "Spatial weight factor on|off")
        ->check(CLI::IsMember({"on", "off"}))->default_val("on");
    app.add_option("--hops", o_.graph.hops, "Candidate growth repetitions")->default_val(1);
    app.add_option("--radius-scale", o_.graph.radius_scale, "Multiplier of r_i = max exp(scale)")->default_val(1.0);
    app.add_option("--knn-checks", o_.graph.knn_checks, "0 = exact kNN; > 0 approximate (FLANN checks)")->default_val(0);
    app.add_option("--kl-smoothing", o_.graph.kl_smoothing, "s of the smoothed KL")->default_val(0.1);
    app.add_option("--solver", o_.solver, "Solver: " + solvers + " (default cp if available, else bk)");
    app.add_option("--solver-options", solver_options_, "Solver options as a JSON object");
    app.add_option("--threshold", threshold_, "Decision: a number tau or percentile:P")->default_val("0.5");
    app.add_flag("--restore", o_.decision.restore, "Also let removed Gaussians with p < tau return");
    app.add_option("--labels", o_.labels, "Ground-truth labels .npy (int32 object id per Gaussian)");
    app.add_option("--object-id", object_id_, "Target object id (else target.json beside --labels)");
    app.add_option("--max-unmatched", o_.max_unmatched, "Subset-PLY rows allowed to stay unmatched")->default_val(0);
    app.add_option("--match-tol", o_.match_tol, "Tolerance pass for subset matching (0 = off)")->default_val(0.0);
    app.add_option("--prompt-embeddings", o_.prompt_embeddings, "FGS: text embeddings T.npy (rows = prompts)");
    app.add_option("--positive", o_.positives, "FGS: positive prompt rows")->delimiter(',');
    app.add_option("--fgs-threshold", o_.fgs_threshold, "FGS deletion threshold")->default_val(0.4);
    app.add_option("--out", o_.out_dir, "Output directory")->required();
    app.add_option("--export-problem", o_.export_problem_dir,
                   "Also write the solvers' exact problem and p as .npy files into this directory "
                   "(first_edge, adj_vertices, edge_weights, y, node_weights, node_ids, params.json, p)");
    app.add_flag("--quiet", quiet_, "No progress lines");
  }

  int Run() override {
    if (!removed_is_.empty())
      o_.removed_is = removed_is_ == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
    o_.graph.delta_mode = delta_mode_ == "cosine" ? DeltaMode::kCosine : DeltaMode::kDistance;
    o_.graph.spatial = spatial_ == "on";
    o_.decision.rule = ParseDecisionRule(threshold_);
    if (object_id_ != kUnset) o_.object_id = object_id_;
    if (!solver_options_.empty()) {
      try {
        o_.solver_options = nlohmann::json::parse(solver_options_);
      } catch (const std::exception&) {
        throw Error("--solver-options: not valid JSON", ExitCode::kUsage);
      }
    }
    if (!quiet_)
      o_.on_stage = [](const std::string& stage, double s) {
        if (s > 1.0) std::cerr << "refine  " << stage << "  " << s << " s\n";
      };
    const RefineResult r = RunRefine(o_);
    const auto& c = r.report["counts"];
    std::cout << "nodes " << c["candidates"] << ", edges " << c["edges"] << ", removed "
              << c["removed_input"] << " -> " << c["refined"] << "\n";
    if (r.report.contains("gt"))
      std::cout << "ground truth F1 " << r.report["gt"]["before"]["f1"] << " -> "
                << r.report["gt"]["after"]["f1"] << "\n";
    (r.exit_code == 0 ? std::cout : std::cerr) << r.message << "\n";
    std::cout << "wrote " << o_.out_dir << "/report.json\n";
    return r.exit_code;
  }

 private:
  static constexpr int kUnset = -2147483647;
  RefineOptions o_;
  std::string removed_is_, delta_mode_ = "distance", spatial_ = "on", threshold_ = "0.5", solver_options_;
  int object_id_ = kUnset;
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(RefineCommand);

}  // namespace al::cli
