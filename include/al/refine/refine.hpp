// The refine pipeline (SPEC §1, §3-5): load scene, features and removed set per the method
// preset, build the graph, solve, decide, score against ground truth, write the outputs
// (refined.npy, refined.txt, added.txt, remaining.ply, report.json) into out_dir.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/output_set.hpp"
#include "al/decision.hpp"
#include "al/graph/graph.hpp"
#include "al/io/masks.hpp"

namespace al {

struct RefineOptions {
  std::string scene;                  // --scene (.ply or .splat), the index space
  std::string removed;                // --removed (mask/indices .npy, .txt, subset .ply); may be
                                      // empty for fgs with prompt_embeddings
  std::optional<RemovedIs> removed_is;  // unset: the preset's (gg: remaining, else removed)
  std::string method = "generic";     // fgs | gg | sags | gc | generic
  std::string features;               // empty: the preset's; "auto", PREFIX, FILE.npy or FILE.ply
  std::string decoder;                // "W.npy,b.npy" (fgs speed-up models)
  GraphOptions graph;                 // k, delta, lambda, spatial, hops, radius_scale, ...
  std::string solver;                 // empty: "cp" when registered, else "bk"
  nlohmann::json solver_options = nlohmann::json::object();
  DecisionOptions decision;           // threshold rule, restore
  std::string labels;                 // ground truth (int32 object id per Gaussian)
  std::optional<int> object_id;       // else target.json beside labels
  std::size_t max_unmatched = 0;
  double match_tol = 0.0;
  // FGS derived mask (method fgs without --removed).
  std::string prompt_embeddings;
  std::vector<int> positives;
  double fgs_threshold = 0.4;
  std::string out_dir;                // required
  std::string export_problem_dir;     // non-empty: write the solvers' problem + p as .npy (problem_io.hpp)
  // Called after each stage with its name and duration (the CLI prints the slow ones).
  std::function<void(const std::string& stage, double seconds)> on_stage;
};

struct RefineResult {
  std::string status = "ok";          // "ok" or "empty_graph"
  int exit_code = 0;                  // 0, or 3 for an empty graph
  std::string message;                // one human-readable summary (empty graph: what to try)
  std::vector<bool> removed, refined; // N
  nlohmann::json report;              // exactly what was written to report.json
};

// Throws al::Error (bad input / usage) before writing anything. The outputs form one output set
// (al/core/output_set.hpp): inputs inside out_dir that the run would replace are refused up front.
RefineResult RunRefine(const RefineOptions& options);

// The pieces of RunRefine for callers that add to the set (refine --auto): the OutputSet options
// of out_dir (inputs, planned names), and the run writing into set.dir() without committing.
OutputSetOptions RefineOutputSetOptions(const RefineOptions& options);
RefineResult RefineIntoSet(const RefineOptions& options, OutputSet& set);
// Writes the solvers' problem (and p) into its own output set (--export-problem).
void ExportProblemSet(const RefineOptions& options, const RefineProblem& problem, const std::vector<double>* p);

}  // namespace al
