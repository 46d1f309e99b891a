// One interface for every solver (SPEC §5). Solvers live in solvers/<name>/ and register a
// factory here; the CLI and benchmarks choose them by name.
#pragma once
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

  // report.json's "solver" block: name, objective, iterations, converged, seconds, stats (not p).
  nlohmann::json ToJson() const;
  // One line: "cp: objective 133.614, 7 iterations, converged, 0.031 s".
  std::string BriefReport() const;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string name() const = 0;
  virtual SolverResult Solve(const RefineProblem& problem) const = 0;
};

// Solver options arrive as JSON so the CLI, sweeps and reports share one description
// (unknown keys are an error). Throws al::Error for an unknown name or bad options.
std::unique_ptr<Solver> MakeSolver(const std::string& name, const nlohmann::json& options = {});

// Names of the registered solvers.
std::vector<std::string> SolverNames();


}  // namespace al
