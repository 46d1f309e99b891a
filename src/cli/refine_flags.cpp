#include "src/cli/refine_flags.hpp"

#include "al/core/error.hpp"
#include "al/core/text.hpp"
#include "al/refine/stages.hpp"
#include "al/solver.hpp"
#include "src/cli/option_flags.hpp"

namespace al::cli {

void AddInputFlags(CLI::App& app, RefineFlags& f) {
  RefineOptions& o = f.options;
  app.add_option("--scene", o.scene, "Full pre-removal scene (.ply or .splat): the index space")->required();
  app.add_option("--removed", o.removed, "Removed set: mask/indices .npy, indices .txt or subset .ply");
  app.add_option("--removed-is", f.removed_is, "A subset PLY holds the removed or the remaining Gaussians "
                 "(default: the preset's; gg: remaining)")->check(CLI::IsMember({"removed", "remaining"}));
  const auto& method = RefineOptions::Table().Find("method");  // Python's refine() shares it
  app.add_option("--method", o.method, "Removal method preset: " + method.range)
      ->check(CLI::IsMember(SplitTrimmed(method.range, '|')))
      ->default_val(SpellOptionValue(method.get(RefineOptions{})));
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

// Flags, their help and their parsing come from the options tables: the library's Check() reports
// ranges in the same words for the CLI, sweep grids, Python keywords and solver-options JSON.
void AddGraphFlags(CLI::App& app, RefineFlags& f) {
  AddOptionFlags(app, GraphOptions::Table(), f.options.graph, "Graph");
}

void AddDecisionFlags(CLI::App& app, RefineFlags& f) {
  AddOptionFlags(app, DecisionOptions::Table(), f.options.decision, "Decision");
}

void AddSolverFlags(CLI::App& app, RefineFlags& f) {
  std::string solvers;
  for (const auto& n : SolverNames()) solvers += (solvers.empty() ? "" : "|") + n;
  app.add_option("--solver", f.options.solver, "Solver: " + solvers + " (default " + ResolveSolverName("") + ")");
  app.add_option("--solver-options", f.solver_options, "Solver options as a JSON object");
}

RefineOptions ToRefineOptions(const RefineFlags& f) {
  RefineOptions o = f.options;
  if (!f.removed_is.empty())
    o.removed_is = f.removed_is == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
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
