// The table of solvers. Each solver folder exposes one factory in its header; add it here.
#include <utility>

#include "al/core/error.hpp"
#include "al/solver.hpp"
#include "bk/bk_solver.hpp"
#include "cut_pursuit/cut_pursuit_solver.hpp"
#include "exact/exact_solver.hpp"

namespace al {
namespace {

using Factory = std::unique_ptr<Solver> (*)(const nlohmann::json& options);

const std::vector<std::pair<std::string, Factory>>& Table() {
  static const std::vector<std::pair<std::string, Factory>> table = {
      {"bk", &MakeBkSolver},
      {"cp", &MakeCutPursuitSolver},
      {"exact", &MakeExactSolver},
  };
  return table;
}

}  // namespace

std::unique_ptr<Solver> MakeSolver(const std::string& name, const nlohmann::json& options) {
  for (const auto& [solver_name, factory] : Table())
    if (solver_name == name) return factory(options.is_null() ? nlohmann::json::object() : options);
  std::string known;
  for (const auto& entry : Table()) known += (known.empty() ? "" : ", ") + entry.first;
  throw Error("unknown solver '" + name + "' (known: " + known + ")", ExitCode::kUsage);
}

std::vector<std::string> SolverNames() {
  std::vector<std::string> names;
  for (const auto& entry : Table()) names.push_back(entry.first);
  return names;
}

}  // namespace al
