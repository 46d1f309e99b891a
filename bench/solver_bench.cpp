// cp vs exact on a generated 100k-node kNN graph (k = 10, CUT_PURSUIT.md §10 setup, soft y, s = 0.1,
// w_e = 0.1). Reports medians over 5 repetitions and the relative objective gap of cp to exact
// (target SPEC §8: gap <= 1e-3 in < 1 s on 2 cores). The exact optimum is computed once and cached.
#include <benchmark/benchmark.h>

#include "al/solver.hpp"
#include "solvers/cut_pursuit/synthetic_knn.hpp"

namespace {

const al::RefineProblem& Problem() {
  static const al::RefineProblem pb = al::cp::MakeKnnProblem(100000, 10, 0.1, 0.1, false, 2024);
  return pb;
}

double ExactObjective() {
  static const double f = al::MakeSolver("exact")->Solve(Problem()).objective;
  return f;
}

void BM_Cp(benchmark::State& state) {
  const auto solver = al::MakeSolver("cp", {{"num_threads", state.range(0)}});
  const double exact = ExactObjective();
  al::SolverResult r;
  for (auto _ : state) r = solver->Solve(Problem());
  state.counters["objective"] = r.objective;
  state.counters["rel_gap_to_exact"] = (r.objective - exact) / exact;
  state.counters["components"] = r.stats["components"].get<double>();
  state.counters["iterations"] = r.iterations;
  state.counters["edges"] = static_cast<double>(Problem().num_edges());
}

void BM_Exact(benchmark::State& state) {
  const auto solver = al::MakeSolver("exact");
  al::SolverResult r;
  for (auto _ : state) r = solver->Solve(Problem());
  state.counters["objective"] = r.objective;
  state.counters["max_flows"] = r.stats["max_flows"].get<double>();
}

BENCHMARK(BM_Cp)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Exact)->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
