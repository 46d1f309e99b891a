#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "al/core/error.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al {
namespace {

class CutPursuitSolver final : public Solver {
 public:
  explicit CutPursuitSolver(cp::CutPursuitOptions options) : options_(options) {}
  std::string name() const override { return "cp"; }

  SolverResult Solve(const RefineProblem& problem) const override { return Run(problem, nullptr); }

  SolverResult SolveFrom(const RefineProblem& problem, const SolverWarmStart& warm) const override {
    cp::WarmStart w{warm.component, std::vector<double>(2 * warm.value.size()),
                    std::vector<char>(warm.saturated.begin(), warm.saturated.end())};
    for (std::size_t c = 0; c < warm.value.size(); ++c) {
      w.values[2 * c] = warm.value[c];
      w.values[2 * c + 1] = 1.0 - warm.value[c];
    }
    return Run(problem, &w);
  }

 private:
  SolverResult Run(const RefineProblem& problem, const cp::WarmStart* warm) const {
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> y;
    cp::CutPursuitResult r = cp::RunCutPursuit(SimplexViewOf(problem, y), options_, warm);
    SolverResult out;
    out.solver = "cp";
    const std::size_t V = problem.num_nodes();
    out.p.resize(V);
    for (std::size_t v = 0; v < V; ++v) out.p[v] = r.rX[static_cast<std::size_t>(r.comp_assign[v]) * 2];
    out.objective = Objective(problem, out.p);  // the one definition (problem.hpp); r.objective is
                                                // the same energy summed over D-label components
    out.iterations = r.iterations;
    out.converged = r.converged;
    out.objective_history = r.objective_history;
    out.warnings = r.warnings;
    out.stats["components"] = r.num_components;
    out.stats["dif_history"] = r.dif_history;
    out.stats["pfdr_iterations"] = r.pfdr_iterations;
    out.stats["reduced_max_flows"] = r.reduced_max_flows;
    out.stats["init_seconds"] = r.init_seconds;
    out.stats["init_max_flows"] = r.init_max_flows;
    out.stats["init_pieces"] = r.init_pieces;
    out.stats["init_plateaus"] = r.init_plateaus;
    out.stats["split_seconds"] = r.split_seconds;
    out.stats["reduce_seconds"] = r.reduce_seconds;
    out.stats["pfdr_seconds"] = r.pfdr_seconds;
    out.stats["merge_seconds"] = r.merge_seconds;
    out.stats["split_nodes"] = r.split_nodes;
    out.stats["remainder_saturations"] = r.remainder_saturations;
    out.stats["non_monotone_steps"] = r.non_monotone_steps;
    out.stats["emulate_upstream_projection_bug"] = options_.emulate_upstream_projection_bug;
    out.stats["max_flow"] = MaxFlow::AlgorithmName(options_.max_flow);
    out.stats["warm_start"] = warm != nullptr;
    out.partition = std::move(r.comp_assign);
    out.saturated.assign(r.saturated.begin(), r.saturated.end());
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

  cp::CutPursuitOptions options_;
};

}  // namespace

const OptionTable<cp::CutPursuitOptions>& cp::CutPursuitOptions::Table() {
  using O = cp::CutPursuitOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("cp solver")
          .Real("cp_dif_tol", &O::cp_dif_tol, R::AtLeast(0), "outer stop on the mean l1 change; merge tolerance")
          .Int("cp_it_max", &O::cp_it_max, R::Closed(0, 1e6), "maximum outer iterations")
          .Int("K", &O::K, R::Closed(2, 2), "candidate directions per component (only 2 is implemented)")
          .Int("split_iter_num", &O::split_iter_num, R::Closed(1, 1e6), "partition/update rounds per split")
          .Real("split_damp_ratio", &O::split_damp_ratio, R::LeftOpen(0, 1), "edge-capacity damping of the first round")
          .Int("split_values_init_num", &O::split_values_init_num, R::Closed(1, 1e6), "k-means++ restarts")
          .Int("split_values_iter_num", &O::split_values_iter_num, R::Closed(0, 1e6), "Lloyd iterations per restart")
          .Real("pfdr_rho", &O::pfdr_rho, R::Open(0, 2), "PFDR relaxation")
          .Real("pfdr_cond_min", &O::pfdr_cond_min, R::LeftOpen(0, 1), "PFDR preconditioner floor ratio")
          .Real("pfdr_dif_rcd", &O::pfdr_dif_rcd, R::AtLeast(0), "PFDR reconditioning threshold (0 = never)")
          .Real("pfdr_dif_tol", &O::pfdr_dif_tol, R::Any(), "PFDR stop; < 0 means 1e-2 * cp_dif_tol")
          .Int("pfdr_it_max", &O::pfdr_it_max, R::Closed(1, 1e9), "PFDR maximum iterations")
          .Int("num_threads", &O::num_threads, R::Closed(0, 4096), "0 = OpenMP default; results never depend on it")
          .Flag("emulate_upstream_projection_bug", &O::emulate_upstream_projection_bug,
                "reproduce the upstream projection bug (CUT_PURSUIT.md 4.2)")
          .Flag("saturate_split_remainders", &O::saturate_split_remainders,
                "saturate a split's remainder that moved by <= cp_dif_tol (docs/solvers.md)")
          .Choice("max_flow", &O::max_flow, MaxFlow::AlgorithmNames(), "max-flow of the splits; all give the same cut")
          .Choice("reduced_solver", &O::reduced_solver,
                  std::vector<std::pair<std::string, O::Reduced>>{{"level_sets", O::Reduced::kLevelSets},
                                                                 {"pfdr", O::Reduced::kPfdr}},
                  "reduced problem: exact level cuts (D = 2) or PFDR")
          .Choice("init", &O::init,
                  std::vector<std::pair<std::string, O::Init>>{{"level_sets", O::Init::kLevelSets},
                                                              {"one_component", O::Init::kOneComponent}},
                  "cold start: coarse level-set partition (D = 2) or one component")
          .Real("init_epsilon", &O::init_epsilon, R::Closed(0, 1), "interval width of the level-set cold start; 0 = cp_dif_tol / 2");
  return table;
}

cp::CutPursuitOptions ParseCutPursuitOptions(const nlohmann::json& options) {
  cp::CutPursuitOptions o;
  cp::CutPursuitOptions::Table().Apply(o, options);
  return o;
}

cp::SimplexProblemView SimplexViewOf(const RefineProblem& problem, std::vector<double>& y) {
  const std::size_t V = problem.num_nodes();
  if (problem.first_edge.size() != V + 1)
    throw Error("refine problem: first_edge must hold V + 1 entries");
  if (!problem.node_weights.empty() && problem.node_weights.size() != V)
    throw Error("refine problem: node_weights must hold V entries");
  y.resize(2 * V);
  for (std::size_t v = 0; v < V; ++v) {
    y[2 * v] = problem.y_remove[v];
    y[2 * v + 1] = 1.0 - problem.y_remove[v];
  }
  return {2, problem.first_edge, problem.adj_vertices, problem.edge_weights, y, problem.node_weights, {},
          problem.kl_smoothing};
}

cp::SimplexProblem ToSimplexProblem(const RefineProblem& problem) {
  std::vector<double> y;
  const cp::SimplexProblemView view = SimplexViewOf(problem, y);
  cp::SimplexProblem sp;
  sp.first_edge = problem.first_edge;
  sp.adj_vertices = problem.adj_vertices;
  sp.edge_weights = problem.edge_weights;
  sp.node_weights = problem.node_weights;
  sp.loss = view.loss;
  sp.y = std::move(y);
  return sp;
}

std::unique_ptr<Solver> MakeCutPursuitSolver(const nlohmann::json& options) {
  return std::make_unique<CutPursuitSolver>(ParseCutPursuitOptions(options));
}

}  // namespace al
