// Unary: labelling v "remove" costs w_v KL_s(y_v || (1,0)), "keep" costs w_v KL_s(y_v || (0,1));
// pairwise: w_uv * 2 when the labels differ (sum_d |x_ud - x_vd| = 2 for opposite vertices).
// Source side of the cut = remove, so a node pays its remove cost as sink capacity.
#include "bk_solver.hpp"

#include <string>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al {
namespace {

class BkSolver final : public Solver {
 public:
  std::string name() const override { return "bk"; }

  SolverResult Solve(const RefineProblem& problem) const override {
    Timer timer;
    const std::size_t V = problem.num_nodes(), E = problem.num_edges();
    if (problem.node_weights.size() != V || problem.edge_weights.size() != E ||
        problem.first_edge.size() != V + 1)
      throw Error("bk: inconsistent RefineProblem sizes", ExitCode::kInternal);
    const double s = problem.kl_smoothing;
    std::vector<double> keep_cost(V), remove_cost(V), edge_cap(E);
    for (std::size_t v = 0; v < V; ++v) {
      remove_cost[v] = problem.node_weights[v] * DataTerm2(problem.y_remove[v], 1.0, s);
      keep_cost[v] = problem.node_weights[v] * DataTerm2(problem.y_remove[v], 0.0, s);
    }
    for (std::size_t e = 0; e < E; ++e) edge_cap[e] = 2.0 * problem.edge_weights[e];
    const MinCutResult cut = MinCutLabels(keep_cost, remove_cost, problem.first_edge,
                                          problem.adj_vertices, edge_cap);
    SolverResult result;
    result.solver = "bk";
    result.p.resize(V);
    std::size_t removed = 0;
    for (std::size_t v = 0; v < V; ++v) {
      result.p[v] = cut.source_side[v] ? 1.0 : 0.0;
      removed += cut.source_side[v];
    }
    result.objective = Objective(problem, result.p);
    result.iterations = 1;
    result.converged = true;
    result.objective_history = {result.objective};
    result.stats = {{"cut_value", cut.cut_value},
                    {"build_seconds", cut.build_seconds},
                    {"flow_seconds", cut.flow_seconds},
                    {"nodes_removed", removed}};
    result.seconds = timer.Seconds();
    return result;
  }
};

}  // namespace

std::unique_ptr<Solver> MakeBkSolver(const nlohmann::json& options) {
  if (!options.is_null() && !(options.is_object() && options.empty())) {
    std::string keys;
    if (options.is_object())
      for (const auto& [k, v] : options.items()) keys += (keys.empty() ? "" : ", ") + k;
    throw Error("bk: unknown solver option(s): " + (keys.empty() ? options.dump() : keys),
                ExitCode::kUsage);
  }
  return std::make_unique<BkSolver>();
}

}  // namespace al
