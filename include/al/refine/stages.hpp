// The refine pipeline as reusable stages: load once, build a graph per (k, δ, hops, ...), solve it
// with any number of solvers and decision rules, score against ground truth. RunRefine
// (al/refine/refine.hpp) is these stages in a row; `compare`, `sweep` and `refine --auto` reuse a
// loaded input and a built graph instead of repeating the work a parameter doesn't change.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/decision.hpp"
#include "al/graph/graph.hpp"
#include "al/io/masks.hpp"
#include "al/refine/preset.hpp"
#include "al/refine/refine.hpp"
#include "al/scene/scene.hpp"
#include "al/solver.hpp"

namespace al {

// Ground truth of a synthetic scene: the object id per Gaussian and the target object.
struct GroundTruth {
  std::vector<std::int32_t> labels;   // N
  int target = -1;
  std::vector<float> opacity_logits;  // N (empty: count-only scores)
};

// Everything the graph and the solvers need, loaded once.
struct RefineInputs {
  std::shared_ptr<const Scene> scene;  // shared, never copied (a Python Scene holds the same one)
  bool colour_fallback = false;       // features are RGB, compared by raw Euclidean distance
  std::string feature_spec;           // what was asked: "semantic_", "auto", FILE.npy, "colour", ...
  std::string feature_source;         // what was used, for the report
  RemovedIs removed_is = RemovedIs::kRemoved;
  RemovalSet removal;
  MethodPreset preset;                // the method's preset (report params.preset)
  nlohmann::json fgs_mask;            // null unless the FGS mask was derived from prompts
  std::optional<GroundTruth> ground_truth;

  // The N×D feature rows the graph compares (colour features when colour_fallback): held here
  // (read from a file, decoded, colour) or borrowed (the scene's own columns, or a caller's array
  // that must outlive the inputs), so features handed over from memory are never copied.
  Eigen::Map<const RowMatXf> features() const;
  void SetFeatures(RowMatXf rows);
  void BorrowFeatures(const float* rows, Eigen::Index count, Eigen::Index dim);

 private:
  RowMatXf owned_features_;
  const float* borrowed_ = nullptr;
  Eigen::Index borrowed_rows_ = 0, borrowed_dim_ = 0;
};

// Which scene columns LoadRefineInputs decodes: all (the evaluator renders the scene: sweeps and
// --auto with cameras), or what refinement reads (f_rest, and rotations unless a subset PLY is
// matched, only checked for finite values: PlyReadOptions::sh_rest, rotations).
enum class SceneColumns { kAll, kRefine };

// Validates the options and loads scene, features, removed set and labels. Records input files,
// warnings and per-stage seconds into report (a NewReport object). Throws al::Error before any
// output is written.
RefineInputs LoadRefineInputs(const RefineOptions& options, nlohmann::json& report,
                              SceneColumns columns = SceneColumns::kAll);

// The same from memory (RefineData, al/refine/refine.hpp): the scene is shared, the arrays are read
// in place (float32 feature rows are borrowed, not copied); options.scene/removed/features/labels
// are not read. Throws al::Error like LoadRefineInputs.
RefineInputs InputsFromData(const RefineData& data, const RefineOptions& options, nlohmann::json& report);

// The graph for these inputs under options (feature normalisation follows the feature kind).
GraphResult BuildGraphFor(const RefineInputs& inputs, const GraphOptions& options);

// "cp" when registered, else "bk", for an empty name; the name otherwise.
std::string ResolveSolverName(const std::string& name);

struct SolveOutcome {
  bool empty_graph = false;
  std::string message;                // one human-readable summary
  std::vector<bool> refined;          // N (the input mask for an empty graph)
  std::vector<double> p;              // per graph node (empty for an empty graph)
  std::vector<std::int32_t> partition;  // per graph node: cp's component (empty for other solvers)
  std::vector<std::uint8_t> saturated;  // per cp component: saturated at the end
  std::size_t added = 0, restored = 0;
  nlohmann::json solver = nlohmann::json::object();    // name, objective, iterations, seconds, ...
  nlohmann::json decision = nlohmann::json::object();  // rule, threshold, counts
  std::vector<std::string> warnings;
  double last_steps_seconds = 0.0;    // RunLastSteps (a part of the refine report's timings_s.decide)
};

// Solves the graph's problem and applies the decision rule. An edgeless graph is not an error: the
// outcome is empty_graph with an actionable message (naming the graph options that produced it)
// and refined = the input removed set.
// With warm (a previous round's solution mapped onto this graph's nodes) the solver starts from it
// (Solver::SolveFrom).
SolveOutcome SolveAndDecide(const RefineInputs& inputs, const GraphResult& graph,
                            const GraphOptions& graph_options, Solver& solver,
                            const DecisionOptions& decision, const SolverWarmStart* warm = nullptr);

// Builds the graph and solves it. With options.grow_rounds > 0 the candidate set then also grows
// one hop around every Gaussian the cut added, and the enlarged graph is built from the previous
// one (GrowRefineGraph) and solved again from the previous solution (Solver::SolveFrom), until a
// round adds fewer new Gaussians than 0.5 % of the removed count or the rounds run out (`capped`,
// a warning). The observations always come from the input mask. An unset (auto) λ takes the
// preset's value for this solver (MethodPreset::LambdaFor); graph.stats.lambda says which.
struct GrownSolve {
  GraphResult graph;                  // the last graph solved
  SolveOutcome outcome;
  int rounds = 1;                     // graphs built and solved
  bool capped = false;                // still adding when grow_rounds ran out
  // Why growth stopped: "fixed" (grow_rounds 0), "empty graph", "trickle" (the round added under
  // 0.5 % of the removed count), "few new candidates" (growing from what it added would bring
  // under 0.5 % of the removed count into the graph), "capped".
  std::string growth_stop = "fixed";
  double graph_seconds = 0.0;         // all builds
  double solve_seconds = 0.0;         // all solves
};

// The steps after the final round (src/refine/last_steps.cpp; docs/refine.md pipeline steps 9-11):
// the taken-whole guard, the opt-in restore window, the second-object trim and the feature-group
// bound, in that order, as `options` switch them. Updates out's refined mask, counts, decision,
// message and warnings.
void RunLastSteps(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& options,
                  SolveOutcome& out);
GrownSolve BuildAndSolve(const RefineInputs& inputs, const GraphOptions& options, Solver& solver,
                         const DecisionOptions& decision);
// The same from a first graph already built with these options (sweeps build it once for many
// points and rescale its λ): solves it, then grows as BuildAndSolve does, the grown graphs built at
// options' λ (auto resolved as there: it should be first's scale); graph_seconds counts the growth
// rounds' builds only.
GrownSolve SolveAndGrow(const RefineInputs& inputs, const GraphOptions& options, Solver& solver,
                        const DecisionOptions& decision, GraphResult first);

// {"object_id", "before": {...}, "after": {...}, "change": {...}} with precision/recall/F1/IoU by
// count and opacity-weighted (SPEC §1 keys gt.before.f1, gt.after.f1, ...); "change" says what the
// refinement did: added (of them the object: precision_added; misses_recovered = share of the
// method's misses added) and restored (of them background: precision_restored).
nlohmann::json ScoreAgainstGroundTruth(const GroundTruth& truth, const std::vector<bool>& before,
                                       const std::vector<bool>& after);

}  // namespace al
