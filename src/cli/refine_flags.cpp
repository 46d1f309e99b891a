#include "src/cli/refine_flags.hpp"

#include "al/core/error.hpp"
#include "al/solver.hpp"

namespace al::cli {

void AddInputFlags(CLI::App& app, RefineFlags& f) {
  RefineOptions& o = f.options;
  app.add_option("--scene", o.scene, "Full pre-removal scene (.ply or .splat): the index space")->required();
  app.add_option("--removed", o.removed, "Removed set: mask/indices .npy, indices .txt or subset .ply");
  app.add_option("--removed-is", f.removed_is, "A subset PLY holds the removed or the remaining Gaussians "
                 "(default: the preset's; gg: remaining)")->check(CLI::IsMember({"removed", "remaining"}));
  app.add_option("--method", o.method, "Removal method preset: fgs|gg|sags|gc|generic")
      ->check(CLI::IsMember({"fgs", "gg", "sags", "gc", "generic"}))->default_val("generic");
  app.add_option("--features", o.features, "auto | PREFIX | FILE.npy | FILE.ply (default: the preset's)");
  app.add_option("--decoder", o.decoder, "W.npy,b.npy: per-Gaussian f' = W f + b (FGS speed-up models)");
  app.add_option("--labels", o.labels, "Ground-truth labels .npy (int32 object id per Gaussian)");
  app.add_option("--object-id", f.object_id, "Target object id (else target.json beside --labels)");
  app.add_option("--max-unmatched", o.max_unmatched, "Subset-PLY rows allowed to stay unmatched")->default_val(0);
  app.add_option("--match-tol", o.match_tol, "Tolerance pass for subset matching (0 = off)")->default_val(0.0);
  app.add_option("--prompt-embeddings", o.prompt_embeddings, "FGS: text embeddings T.npy (rows = prompts)");
  app.add_option("--positive", o.positives, "FGS: positive prompt rows")->delimiter(',');
  app.add_option("--fgs-threshold", o.fgs_threshold, "FGS deletion threshold")->default_val(0.4);
}

void AddGraphFlags(CLI::App& app, RefineFlags& f) {
  GraphOptions& g = f.options.graph;
  app.add_option("--k", g.k, "Neighbours per node")->default_val(10);
  app.add_option("--delta", g.delta, "Semantic gate (distance of unit features)")->default_val(0.8);
  app.add_option("--delta-mode", f.delta_mode, "distance | cosine")
      ->check(CLI::IsMember({"distance", "cosine"}))->default_val("distance");
  app.add_option("--lambda", g.lambda, "Edge weight scale")->default_val(1.0);
  app.add_option("--spatial", f.spatial, "Spatial weight factor on|off")
      ->check(CLI::IsMember({"on", "off"}))->default_val("on");
  app.add_option("--hops", g.hops, "Candidate growth repetitions")->default_val(1);
  app.add_option("--grow-rounds", g.grow_rounds, "Grow the candidate set around what the cut added and "
                 "solve again, at most this many times (0 = fixed candidate set)")
      ->check(CLI::Range(0, 1000))->capture_default_str();
  app.add_option("--radius-scale", g.radius_scale, "Multiplier of r_i = max exp(scale)")->default_val(1.0);
  app.add_option("--knn-checks", g.knn_checks, "0 = exact kNN; > 0 approximate (FLANN checks)")->default_val(0);
  app.add_option("--kl-smoothing", g.kl_smoothing, "s of the smoothed KL")->default_val(0.1);
  app.add_option("--centre", f.centre, "Centre semantic features on the scene mean (on|off)")
      ->check(CLI::IsMember({"on", "off"}))->default_val("on");
  app.add_option("--prior-weight", g.prior.weight, "Feature prior in the unary: y = (1-w) mask + w q "
                 "(0 = the mask alone)")->check(CLI::Range(0.0, 1.0))->capture_default_str();
}

void AddDecisionFlags(CLI::App& app, RefineFlags& f) {
  app.add_option("--threshold", f.threshold, "Decision: a number tau or percentile:P")->default_val("0.5");
  app.add_flag("--restore,!--no-restore", f.options.decision.restore,
               "Let removed Gaussians with p < tau return (default on; --no-restore: add only)");
  app.add_option("--min-segment-share", f.options.decision.min_segment_share,
                 "Segment rule: add only to graph components the method removed at least this share "
                 "of (0 = SPEC 5's plain rule)")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
}

void AddSolverFlags(CLI::App& app, RefineFlags& f) {
  std::string solvers;
  for (const auto& n : SolverNames()) solvers += (solvers.empty() ? "" : "|") + n;
  app.add_option("--solver", f.options.solver, "Solver: " + solvers + " (default cp if available, else bk)");
  app.add_option("--solver-options", f.solver_options, "Solver options as a JSON object");
}

RefineOptions ToRefineOptions(const RefineFlags& f) {
  RefineOptions o = f.options;
  if (!f.removed_is.empty())
    o.removed_is = f.removed_is == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
  o.graph.delta_mode = f.delta_mode == "cosine" ? DeltaMode::kCosine : DeltaMode::kDistance;
  o.graph.spatial = f.spatial == "on";
  o.graph.centre_features = f.centre == "on";
  o.decision.rule = ParseDecisionRule(f.threshold);
  if (f.object_id != RefineFlags::kUnset) o.object_id = f.object_id;
  if (!f.solver_options.empty()) {
    try {
      o.solver_options = nlohmann::json::parse(f.solver_options);
    } catch (const std::exception&) {
      throw Error("--solver-options: not valid JSON", ExitCode::kUsage);
    }
  }
  return o;
}

}  // namespace al::cli
