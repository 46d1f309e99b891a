#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "al/core/error.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al {
namespace {

double Num(const nlohmann::json& v, const std::string& key) {
  if (!v.is_number()) throw Error("cp solver: option '" + key + "' must be a number", ExitCode::kUsage);
  return v.get<double>();
}

int Int(const nlohmann::json& v, const std::string& key) {
  const double x = Num(v, key);
  if (x != std::floor(x) || std::fabs(x) > 1e9)
    throw Error("cp solver: option '" + key + "' must be an integer", ExitCode::kUsage);
  return static_cast<int>(x);
}

class CutPursuitSolver final : public Solver {
 public:
  explicit CutPursuitSolver(cp::CutPursuitOptions options) : options_(options) {}
  std::string name() const override { return "cp"; }

  SolverResult Solve(const RefineProblem& problem) const override {
    const auto start = std::chrono::steady_clock::now();
    const cp::SimplexProblem sp = ToSimplexProblem(problem);
    const cp::CutPursuitResult r = cp::RunCutPursuit(sp, options_);
    SolverResult out;
    out.solver = "cp";
    const std::size_t V = problem.num_nodes();
    out.p.resize(V);
    for (std::size_t v = 0; v < V; ++v) out.p[v] = r.rX[static_cast<std::size_t>(r.comp_assign[v]) * 2];
    out.objective = r.objective;
    out.iterations = r.iterations;
    out.converged = r.converged;
    out.objective_history = r.objective_history;
    out.warnings = r.warnings;
    out.stats["components"] = r.num_components;
    out.stats["dif_history"] = r.dif_history;
    out.stats["pfdr_iterations"] = r.pfdr_iterations;
    out.stats["split_seconds"] = r.split_seconds;
    out.stats["reduce_seconds"] = r.reduce_seconds;
    out.stats["pfdr_seconds"] = r.pfdr_seconds;
    out.stats["merge_seconds"] = r.merge_seconds;
    out.stats["split_nodes"] = r.split_nodes;
    out.stats["remainder_saturations"] = r.remainder_saturations;
    out.stats["non_monotone_steps"] = r.warnings.size();
    out.stats["emulate_upstream_projection_bug"] = options_.emulate_upstream_projection_bug;
    out.stats["max_flow"] = MaxFlow::AlgorithmName(options_.max_flow);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  cp::CutPursuitOptions options_;
};

}  // namespace

cp::CutPursuitOptions ParseCutPursuitOptions(const nlohmann::json& options) {
  cp::CutPursuitOptions o;
  if (options.is_null()) return o;
  if (!options.is_object()) throw Error("cp solver: options must be a JSON object", ExitCode::kUsage);
  for (const auto& [key, v] : options.items()) {
    if (key == "cp_dif_tol") o.cp_dif_tol = Num(v, key);
    else if (key == "cp_it_max") o.cp_it_max = Int(v, key);
    else if (key == "K") o.K = Int(v, key);
    else if (key == "split_iter_num") o.split_iter_num = Int(v, key);
    else if (key == "split_damp_ratio") o.split_damp_ratio = Num(v, key);
    else if (key == "split_values_init_num") o.split_values_init_num = Int(v, key);
    else if (key == "split_values_iter_num") o.split_values_iter_num = Int(v, key);
    else if (key == "pfdr_rho") o.pfdr_rho = Num(v, key);
    else if (key == "pfdr_cond_min") o.pfdr_cond_min = Num(v, key);
    else if (key == "pfdr_dif_rcd") o.pfdr_dif_rcd = Num(v, key);
    else if (key == "pfdr_dif_tol") o.pfdr_dif_tol = Num(v, key);
    else if (key == "pfdr_it_max") o.pfdr_it_max = Int(v, key);
    else if (key == "num_threads") o.num_threads = Int(v, key);
    else if (key == "emulate_upstream_projection_bug" || key == "saturate_split_remainders") {
      if (!v.is_boolean()) throw Error("cp solver: option '" + key + "' must be a boolean", ExitCode::kUsage);
      (key == "saturate_split_remainders" ? o.saturate_split_remainders : o.emulate_upstream_projection_bug) = v.get<bool>();
    } else if (key == "max_flow") {
      const auto algorithm = v.is_string() ? MaxFlow::AlgorithmFromName(v.get<std::string>()) : std::nullopt;
      if (!algorithm)
        throw Error("cp solver: option 'max_flow' must be \"hybrid\", \"pseudoflow\" or \"bk\"",
                    ExitCode::kUsage);
      o.max_flow = *algorithm;
    } else {
      throw Error("cp solver: unknown option '" + key + "'", ExitCode::kUsage);
    }
  }
  if (o.K != 2) throw Error("cp solver: only K = 2 is implemented", ExitCode::kUsage);
  if (!(o.cp_dif_tol >= 0.0) || o.cp_it_max < 0 || o.split_iter_num < 1 || o.split_values_init_num < 1 ||
      o.split_values_iter_num < 0 || !(o.split_damp_ratio > 0.0 && o.split_damp_ratio <= 1.0) ||
      !(o.pfdr_rho > 0.0 && o.pfdr_rho < 2.0) || !(o.pfdr_cond_min > 0.0 && o.pfdr_cond_min <= 1.0) ||
      !(o.pfdr_dif_rcd >= 0.0) || o.pfdr_it_max < 1 || o.num_threads < 0)
    throw Error("cp solver: option value out of range", ExitCode::kUsage);
  return o;
}

cp::SimplexProblem ToSimplexProblem(const RefineProblem& problem) {
  const std::size_t V = problem.num_nodes();
  if (problem.first_edge.size() != V + 1)
    throw Error("refine problem: first_edge must hold V + 1 entries");
  if (!problem.node_weights.empty() && problem.node_weights.size() != V)
    throw Error("refine problem: node_weights must hold V entries");
  cp::SimplexProblem sp;
  sp.D = 2;
  sp.first_edge = problem.first_edge;
  sp.adj_vertices = problem.adj_vertices;
  sp.edge_weights = problem.edge_weights;
  sp.node_weights = problem.node_weights;
  sp.loss = problem.kl_smoothing;
  sp.y.resize(2 * V);
  for (std::size_t v = 0; v < V; ++v) {
    sp.y[2 * v] = problem.y_remove[v];
    sp.y[2 * v + 1] = 1.0 - problem.y_remove[v];
  }
  return sp;
}

std::unique_ptr<Solver> MakeCutPursuitSolver(const nlohmann::json& options) {
  return std::make_unique<CutPursuitSolver>(ParseCutPursuitOptions(options));
}

}  // namespace al
