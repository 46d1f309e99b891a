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
    out.objective = Objective(problem, out.p);
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
          .Choice("max_flow", &ExactOptions::max_flow, MaxFlow::AlgorithmNames(), "max-flow of the level cuts")
          .Int("num_threads", &ExactOptions::num_threads, NumericRange::Closed(0, 4096),
               "0 = OpenMP default; results never depend on it");
  return table;
}

ExactOptions ParseExactOptions(const nlohmann::json& options) {
  ExactOptions o;
  ExactOptions::Table().Apply(o, options);
  return o;
}

std::unique_ptr<Solver> MakeExactSolver(const nlohmann::json& options) {
  return std::make_unique<ExactSolver>(ParseExactOptions(options));
}

}  // namespace al
