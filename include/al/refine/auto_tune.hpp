// `refine --auto` (issue #7 part 3): choose (k, δ, λ) on a small grid without ground truth.
// Every grid point is refined (graph once per (k, δ), λ by rescaling, as in sweeps) and scored by
// an unsupervised criterion:
//  - "eval" (cameras and the object given): the evaluator's acc_Δdepth (float mode: how much of the
//    object's pixels lose their depth) minus its collateral damage (fraction of non-object pixels
//    whose depth changed); acc over the views no candidate's trust flags mark (TrustedViewScores,
//    docs/metrics.md), collateral over all evaluated views; higher is better. Every view flagged:
//    "stability" decides instead.
//  - "stability" (otherwise): how little the decision moves when one parameter moves one grid
//    step: the mean Jaccard similarity between the point's changed set (added ∪ restored) and
//    those of its grid neighbours. A setting on a plateau is one where the cut follows a real
//    boundary of the graph energy rather than a parameter value.
// Ground truth, when given, is reported beside the choice (never used to choose), so the
// criterion's hit rate can be measured (docs/sweep.md).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/refine/stages.hpp"
#include "al/refine/sweep.hpp"

namespace al {

struct AutoTuneOptions {
  std::vector<int> k = {6, 10, 14};
  std::vector<double> delta = {0.8, 1.0, 1.2};
  std::vector<double> lambda = {0.5, 1.0, 2.0};
  std::optional<PointEvalSetup> eval;  // set: the "eval" criterion, else "stability"
  void Check() const;  // non-empty axes, k >= 1, delta finite, lambda >= 0
};

struct AutoTuneCandidate {
  int k = 0;
  double delta = 0, lambda = 0;
  double score = 0;                   // the criterion (higher is better)
  bool empty_graph = false;
  std::size_t added = 0, restored = 0;
  nlohmann::json eval;                // evaluator metrics ("eval" criterion)
  std::optional<double> gt_f1;        // F1 against ground truth, when known (reporting only)
  // "stability": the Jaccard similarity with each grid neighbour (candidate index, similarity);
  // the score is their mean. Kept so a report shows why a point won, and so other aggregations or
  // sub-grids can be studied from the records without solving again.
  std::vector<std::pair<std::size_t, double>> neighbour_jaccard;
};

struct AutoTuneResult {
  std::string criterion;              // "eval" or "stability"
  std::vector<AutoTuneCandidate> candidates;  // grid order: k, then δ, then λ
  std::size_t best = 0, runner_up = 0;        // indices into candidates (equal when only one)
  std::optional<std::size_t> best_by_gt;      // with ground truth: the highest F1 (first on ties)
  double seconds = 0;
  nlohmann::json ToJson() const;      // criterion, chosen, runner_up, best_by_gt, candidates
};

// Refines inputs at every grid point with `solver` and `decision` (other graph options from base)
// and picks the best point by the criterion; ties go to the earlier grid point. Throws al::Error
// for an empty grid.
AutoTuneResult AutoTune(const RefineInputs& inputs, const GraphOptions& base, Solver& solver,
                        const DecisionOptions& decision, const AutoTuneOptions& options);

// `refine --auto`: loads the inputs, runs AutoTune (the "eval" criterion when cameras are given:
// object from object_masks, else the labels' target), then RunRefine at the chosen (k, δ, λ); the
// report.json written by RunRefine is rewritten with an "auto" section (AutoTuneResult::ToJson).
// The inputs are loaded twice (once for the search, once by RunRefine).
struct AutoRefineOutcome {
  AutoTuneResult tune;
  RefineResult refine;
};
AutoRefineOutcome RunAutoRefine(RefineOptions options, AutoTuneOptions auto_options, const std::string& cameras,
                                const std::string& views, const std::string& object_masks);

// "6,10,14" -> {6, 10, 14}, for the --auto-k / --auto-delta / --auto-lambda flags (usage error
// on anything else).
std::vector<double> ParseAutoList(const std::string& flag, const std::string& text);

}  // namespace al
