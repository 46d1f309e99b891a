// One interface for every solver (SPEC §5). Solvers live in solvers/<name>/ and register a
// factory here; the CLI and benchmarks choose them by name.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/graph/problem.hpp"

namespace al {

struct SolverResult {
  std::string solver;                     // "bk", "cp", "exact"
  std::vector<double> p;                  // p_v = x_v,remove in [0, 1], one per node
  double objective = 0.0;                 // F(p) (Objective() in problem.hpp)
  int iterations = 0;
  double seconds = 0.0;
  bool converged = false;
  std::vector<double> objective_history;  // per iteration, when the solver is iterative
  std::vector<std::string> warnings;
  nlohmann::json stats = nlohmann::json::object();  // solver-specific statistics
  // Piecewise-constant solvers (cp): the component of each node and which components were
  // saturated (not worth another split) at the end; what SolverWarmStart hands to a next solve.
  std::vector<std::int32_t> partition;
  std::vector<std::uint8_t> saturated;

  // report.json's "solver" block: name, objective, iterations, converged, seconds, stats (not p).
  nlohmann::json ToJson() const;
  // One line: "cp: objective 133.614, 7 iterations, converged, 0.031 s".
  std::string BriefReport() const;
};

// A previous solution carried to a related problem (the refine stages' candidate growth: the
// grown graph holds the old nodes, with slightly changed observations, and some new ones).
struct SolverWarmStart {
  std::vector<std::int32_t> component;  // per node of the new problem: its old component, -1 = new node
  std::vector<double> value;            // per old component: its p
  // Per old component (empty: none): saturated at the end of the old solve AND its data (its
  // nodes' observations and edges) changed too little to matter. A component marked here is not
  // split again unless its value moves (cut pursuit's desaturation rule), so a caller must clear
  // the flags of components whose data changed.
  std::vector<std::uint8_t> saturated;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string name() const = 0;
  virtual SolverResult Solve(const RefineProblem& problem) const = 0;
  // The same problem from a previous solution. Solvers that cannot use one solve from scratch;
  // cp starts from the old partition and values (docs/solvers.md, "Warm start").
  virtual SolverResult SolveFrom(const RefineProblem& problem, const SolverWarmStart& warm) const {
    (void)warm;
    return Solve(problem);
  }
};

// Solver options arrive as JSON so the CLI, sweeps and reports share one description
// (unknown keys are an error). Throws al::Error for an unknown name or bad options.
std::unique_ptr<Solver> MakeSolver(const std::string& name, const nlohmann::json& options = {});

// Names of the registered solvers.
std::vector<std::string> SolverNames();


}  // namespace al
