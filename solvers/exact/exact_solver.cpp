#include "solvers/exact/exact_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "al/core/error.hpp"
#include "al/graph/loss.hpp"

namespace al {
namespace {

class ExactSolver final : public Solver {
 public:
  explicit ExactSolver(ExactOptions o) : options_(std::move(o)) {}
  std::string name() const override { return "exact"; }
  SolverResult Solve(const RefineProblem& problem) const override {
    const auto start = std::chrono::steady_clock::now();
    ExactStats st;
    SolverResult out;
    out.solver = "exact";
    out.p = SolveExactTwoLabel(problem, options_, &st);
    out.objective = TwoLabelObjective(problem, out.p);
    out.iterations = static_cast<int>(st.max_flows);
    out.converged = true;
    out.objective_history = {out.objective};
    out.stats["max_flows"] = st.max_flows;
    out.stats["plateaus"] = st.plateaus;
    out.stats["max_depth"] = st.max_depth;
    out.stats["pivot"] = options_.pivot;
    out.stats["epsilon"] = options_.epsilon;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  ExactOptions options_;
};

}  // namespace

const OptionTable<ExactOptions>& ExactOptions::Table() {
  static const auto table =
      OptionTable<ExactOptions>("exact solver")
          .Real("epsilon", &ExactOptions::epsilon, NumericRange::Open(0, 1), "interval width at which a group is final")
          .Choice("pivot", &ExactOptions::pivot,
                  std::vector<std::pair<std::string, std::string>>{{"plateau", "plateau"}, {"bisection", "bisection"}},
                  "how an interval is split: at a plateau of the level cut, or halved")
          .Choice("max_flow", &ExactOptions::max_flow, MaxFlow::AlgorithmNames(), "max-flow of the level cuts");
  return table;
}

ExactOptions ParseExactOptions(const nlohmann::json& options) {
  ExactOptions o;
  ExactOptions::Table().Apply(o, options);
  return o;
}

double TwoLabelObjective(const RefineProblem& pb, const std::vector<double>& p) {
  const Loss loss{pb.kl_smoothing, 2};
  double data = 0.0, tv = 0.0;
  const std::size_t V = pb.num_nodes();
  for (std::size_t v = 0; v < V; ++v) {
    const double w = pb.node_weights.empty() ? 1.0 : pb.node_weights[v];
    data += w * (loss.Value(pb.y_remove[v], p[v]) + loss.Value(1.0 - pb.y_remove[v], 1.0 - p[v]));
  }
  for (std::size_t u = 0; u < V; ++u)
    for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e)
      tv += pb.edge_weights[e] * 2.0 * std::fabs(p[u] - p[pb.adj_vertices[e]]);
  return data + tv;
}

std::unique_ptr<Solver> MakeExactSolver(const nlohmann::json& options) {
  return std::make_unique<ExactSolver>(ParseExactOptions(options));
}

}  // namespace al
