// Solver comparison (issue #5 part 7, SPEC §5): every solver on the SAME graph, each cp setting of a
// grid of cut-pursuit tolerances, with run time, objective F, relative gap to the exact relaxed
// optimum and, with ground truth, F1 after the decision. `al-refine compare` is this plus output
// files; `sweep` can reuse CompareSolvers on its own graphs.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/decision.hpp"
#include "al/graph/graph.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"

namespace al {

// Cut-pursuit option grid: (option key, values) pairs, expanded as a Cartesian product in the given
// order (the last key varies fastest). Keys are cp's JSON option names (docs/solvers.md).
using SolverGrid = std::vector<std::pair<std::string, std::vector<double>>>;

// "cp_dif_tol=1e-2,1e-3;pfdr_dif_tol=1e-3,1e-4" -> grid. An empty text gives an empty grid.
// Throws al::Error (usage) on syntax errors, non-numeric or non-finite values, empty value lists
// or repeated keys. Unknown keys are caught later by MakeSolver (also usage).
SolverGrid ParseSolverGrid(const std::string& text);
std::string SolverGridToString(const SolverGrid& grid);

// The grid `compare` uses when --grid is not given: three cp stop tolerances around cp's default
// 1e-3 (pfdr_dif_tol follows as 1e-2·cp_dif_tol), enough for a run-time/error trade-off curve.
SolverGrid DefaultSolverGrid();

// One solver run of the comparison: the solver and the options it got.
struct SolverRun {
  std::string id;          // file-safe and unique: "bk", "exact", "cp", "cp_1", "cp_2", ...
  std::string solver;      // registered name
  nlohmann::json options = nlohmann::json::object();
  bool reference = false;  // the exact run added only to measure the gap (not in --solvers)
};

struct CompareOptions {
  std::vector<std::string> solvers;   // e.g. {"bk", "cp", "exact"}; unique, registered
  SolverGrid grid;                    // applied to cp (one cp run per grid point)
  // Per-solver base options, {"cp": {...}, "exact": {...}}; grid values override cp's.
  nlohmann::json solver_options = nlohmann::json::object();
  // Run "exact" for the gap even when it is not in solvers (true), or report gap = null with
  // gap_reason (false).
  bool reference = true;
  DecisionOptions decision;
  // Called before / after each run (progress lines): run, index, total, finished row or null.
  std::function<void(const SolverRun&, std::size_t, std::size_t, const nlohmann::json* row)> on_run;
  void Check() const;  // registered, unique solvers; a valid grid and per-solver options (PlanSolverRuns)
};

// The runs the options describe, in order: each solver of `solvers` in the given order (cp once
// per grid point), then the reference exact run if needed. Validates names and options by building
// every solver (al::Error usage on unknown names, duplicates, bad options, or a grid without cp).
std::vector<SolverRun> PlanSolverRuns(const CompareOptions& options);

struct CompareResult {
  std::vector<SolverRun> runs;
  // One row per run (same order): id, solver, options, seconds (solver's own), wall_seconds
  // (solve + decision), objective, iterations, converged, gap (relative (F − F*)/|F*|, or null),
  // decision {rule, threshold, added, restored, selected, at_threshold}, refined_count, and with
  // ground truth gt {f1, f1_w, precision, recall, iou, ...} after the decision.
  std::vector<nlohmann::json> rows;
  std::vector<std::vector<double>> p;  // per run, per graph node
  std::optional<double> reference_objective;
  std::string gap_reason;             // why gaps are null (empty when they are not)
  nlohmann::json gt_before;           // ground-truth scores of the input removal (null without)
  bool empty_graph = false;
  std::string message;                // empty-graph explanation, or a one-line summary
  std::vector<std::string> warnings;
};

// Runs every planned solver on graph (built from inputs with graph_options). An edgeless graph
// gives empty_graph with the refine message and no rows.
CompareResult CompareSolvers(const RefineInputs& inputs, const GraphResult& graph,
                             const GraphOptions& graph_options, const CompareOptions& options);

// Output files into dir (each atomic): compare.csv (one line per row), compare.json ({"rows": [...]})
// and the run-time/error chart tradeoff.png with tradeoff.gp and tradeoff.dat. Returns the chart
// status {"drawn", "message"}.
void WriteCompareTables(const std::filesystem::path& dir, const CompareResult& result);
nlohmann::json WriteCompareChart(const std::filesystem::path& dir, const CompareResult& result);

// `compare` end to end: inputs → one graph → every planned run → compare.csv/.json, tradeoff.png,
// report.json as one output set in refine.out_dir (and the problem plus one p per run in
// refine.export_problem_dir when set). Options are checked before anything is loaded.
struct CompareRunResult {
  CompareResult compare;
  nlohmann::json report;      // what report.json holds
  bool chart_drawn = false;
  std::string out_dir;
  int exit_code = 0;          // 3 for an empty graph (the message says what to try)
  std::string BriefReport() const;  // the table of runs (seconds, objective, gap, added, F1) and what was written
};
CompareRunResult RunCompare(const RefineOptions& refine, const CompareOptions& options);

}  // namespace al
