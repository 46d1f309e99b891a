// The refine pipeline (SPEC §1, §3-5): load scene, features and removed set per the method
// preset, build the graph, solve, decide, score against ground truth, write the outputs
// (refined.npy, refined.txt, added.txt, remaining.ply, report.json) into out_dir.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/option_table.hpp"
#include "al/core/output_set.hpp"
#include "al/decision.hpp"
#include "al/graph/graph.hpp"
#include "al/io/masks.hpp"
#include "al/io/npy.hpp"
#include "al/scene/scene.hpp"

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
  std::string solver;                 // empty: the default solver ("cp" when registered, else "bk")
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
  std::string out_dir;                // required for RunRefine(options); optional with RefineData
  std::string export_problem_dir;     // non-empty: write the solvers' problem + p as .npy (problem_io.hpp)
  // Called after each stage with its name and duration (the CLI prints the slow ones).
  std::function<void(const std::string& stage, double seconds)> on_stage;

  // The ranges of the graph and decision tables and of this struct's own table; throws al::Error
  // (usage) naming the option. RunRefine calls it before reading any file.
  void Check() const;
  // The options that are not paths: method, solver, max_unmatched, match_tol, fgs_threshold. The
  // CLI's flags and Python's keywords (and their defaults) come from it.
  static const OptionTable<RefineOptions>& Table();
};

struct RefineResult {
  std::string status = "ok";          // "ok" or "empty_graph"
  int exit_code = 0;                  // 0, or 3 for an empty graph
  std::string message;                // one human-readable summary (empty graph: what to try)
  std::vector<bool> removed, refined; // N
  std::vector<std::int64_t> added;    // indices refinement added to the removed set (ascending)
  std::vector<std::int64_t> restored; // indices it returned to the scene (ascending)
  nlohmann::json report;              // exactly what was written to report.json (or would be,
                                      // for RefineData without out_dir)

  // The gist: status, message, counts, ground-truth scores before/after (when labels were
  // given), total seconds.
  nlohmann::json Summary() const;
  // "nodes N, edges E, removed a -> b" and, with ground truth, "ground truth F1 x -> y; misses
  // recovered ..., precision of the added ..., of the restored ..." (one line each).
  std::string BriefReport() const;
};

// What to refine when it is already in memory (the Python module), in place of the files that
// options.scene / removed / features / labels name. The arrays are read where they are (no copy)
// and must outlive the call.
struct RefineData {
  std::shared_ptr<const Scene> scene;   // required
  NpyArray removed;                     // as a --removed .npy: bool/uint8 mask (N,), indices, gc floats
  NpyArray features;                    // optional (N, D) float rows (float32: used in place); none
                                        // (data == nullptr): the preset's, i.e. the scene's features
                                        // or the colour fallback
  std::vector<std::int32_t> labels;     // optional ground truth (object id per Gaussian)
  std::optional<int> object_id;         // the target; required with labels
  std::string name = "(memory)";        // stands for the file names in report.params and errors
};

// Throws al::Error (bad input / usage) before writing anything. The outputs form one output set
// (al/core/output_set.hpp): inputs inside out_dir that the run would replace are refused up front.
RefineResult RunRefine(const RefineOptions& options);

// The pieces of RunRefine for callers that add to the set (refine --auto): the OutputSet options
// of out_dir (inputs, planned names), and the run writing into set.dir() without committing.
OutputSetOptions RefineOutputSetOptions(const RefineOptions& options);
RefineResult RefineIntoSet(const RefineOptions& options, OutputSet& set);
// Writes the solvers' problem (and p) into its own output set (--export-problem); lambda: the
// edge weight scale the problem was built with (GraphStats::lambda).
void ExportProblemSet(const RefineOptions& options, const RefineProblem& problem, double lambda,
                      const std::vector<double>* p);

// The same refinement from memory: one code path with the file-based RunRefine after loading, so
// both give identical masks for the same input. Writes the outputs only when options.out_dir is set.
RefineResult RunRefine(const RefineData& data, const RefineOptions& options);

}  // namespace al
