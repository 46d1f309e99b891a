// cp vs exact on a generated 100k-node kNN graph (k = 10, CUT_PURSUIT.md §10 setup, soft y, s = 0.1,
// w_e = 0.1). Reports medians over 5 repetitions and the relative objective gap of cp to exact
// (target: gap <= 1e-3 in < 1 s on 2 cores). The exact optimum is computed once and cached.
// Baselines in the same run (docs/solvers.md "cp speed"): BM_Cp/.../sat:0 is cp without the
// split-remainder saturation; .../maxflow:1 (and BM_Exact/maxflow:1) run every cut with
// Boykov-Kolmogorov alone, the max-flow before the hybrid with pseudoflow.
// BM_MaxFlowBalancedCut compares the shared max-flow (solvers/max_flow/max_flow.hpp, own
// Boykov-Kolmogorov) with Boost's boykov_kolmogorov_max_flow on the hardest kind of cut both solvers
// issue: the level cut at the best constant value, where sources and sinks balance and the flow has
// to travel across the whole graph (cp's re-splits of its large near-optimal component look alike).
//
// JSON medians: solver_bench --benchmark_format=json (or --benchmark_out=f.json
// --benchmark_out_format=json); the gap is the counter rel_gap_to_exact.
#include <benchmark/benchmark.h>

#include <ctime>
#include <vector>

#include "al/solver.hpp"
#include "solvers/max_flow/max_flow.hpp"
#include "al/graph/loss.hpp"
#include "al/fixtures/knn_problem.hpp"

namespace {

const al::RefineProblem& Problem() {
  static const al::RefineProblem pb = al::fixtures::MakeKnnProblem(100000, 10, 0.1, 0.1, false, 2024);
  return pb;
}

double ExactObjective() {
  static const double f = al::MakeSolver("exact")->Solve(Problem()).objective;
  return f;
}

double SumOf(const nlohmann::json& values) {
  double s = 0.0;
  for (const auto& v : values) s += v.get<double>();
  return s;
}

// Max-flow algorithm of an argument: 0 = the default hybrid, 1 = BK alone (the former algorithm).
const char* MaxFlowArg(std::int64_t arg) { return arg == 0 ? "hybrid" : "bk"; }

// Args: threads, saturate_split_remainders (1 = default; 0 = the spec's saturation rule only, the
// pre-change baseline measured in the same run), max-flow (0 = hybrid default, 1 = BK alone).
// process_cpu_s is the CPU time of all threads (Google Benchmark's CPU column counts the main thread
// only); split_nodes = vertices offered to the split over all iterations (the max-flow work the
// saturation rule removes).
void BM_Cp(benchmark::State& state) {
  const auto solver = al::MakeSolver("cp", {{"num_threads", state.range(0)},
                                            {"saturate_split_remainders", state.range(1) != 0},
                                            {"max_flow", MaxFlowArg(state.range(2))}});
  const double exact = ExactObjective();
  al::SolverResult r;
  double cpu = 0.0;
  for (auto _ : state) {
    const std::clock_t c0 = std::clock();
    r = solver->Solve(Problem());
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  }
  state.counters["process_cpu_s"] = cpu / static_cast<double>(state.iterations());
  state.counters["objective"] = r.objective;
  state.counters["rel_gap_to_exact"] = (r.objective - exact) / exact;
  state.counters["components"] = r.stats["components"].get<double>();
  state.counters["iterations"] = r.iterations;
  state.counters["edges"] = static_cast<double>(Problem().num_edges());
  state.counters["split_s"] = SumOf(r.stats["split_seconds"]);
  state.counters["pfdr_s"] = SumOf(r.stats["pfdr_seconds"]);
  state.counters["reduce_merge_s"] = SumOf(r.stats["reduce_seconds"]) + SumOf(r.stats["merge_seconds"]);
  state.counters["split_nodes"] = SumOf(r.stats["split_nodes"]);
  state.counters["remainder_saturations"] = r.stats["remainder_saturations"].get<double>();
}

// Arg: max-flow of the level cuts (0 = hybrid default, 1 = BK alone).
void BM_Exact(benchmark::State& state) {
  const auto solver = al::MakeSolver("exact", {{"max_flow", MaxFlowArg(state.range(0))}});
  al::SolverResult r;
  for (auto _ : state) r = solver->Solve(Problem());
  state.counters["objective"] = r.objective;
  state.counters["max_flows"] = r.stats["max_flows"].get<double>();
}

struct LevelCut {
  std::vector<double> source_cap, sink_cap, edge_cap;
};

// Level cut of the 1-D TV problem (CUT_PURSUIT.md §11) at the t where sum_v phi'_v(t) = 0.
const LevelCut& BalancedCut() {
  static const LevelCut cut = [] {
    const al::RefineProblem& pb = Problem();
    const al::Loss loss{pb.kl_smoothing, 2};
    const std::size_t V = pb.num_nodes();
    auto dphi = [&](std::size_t v, double t) {
      return loss.Grad(pb.y_remove[v], t) - loss.Grad(1.0 - pb.y_remove[v], 1.0 - t);
    };
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 60; ++it) {
      const double t = 0.5 * (lo + hi);
      double s = 0.0;
      for (std::size_t v = 0; v < V; ++v) s += dphi(v, t);
      (s < 0.0 ? lo : hi) = t;
    }
    LevelCut c;
    c.source_cap.resize(V);
    c.sink_cap.resize(V);
    for (std::size_t v = 0; v < V; ++v) {
      const double a = dphi(v, 0.5 * (lo + hi));
      c.source_cap[v] = a > 0.0 ? a : 0.0;
      c.sink_cap[v] = a < 0.0 ? -a : 0.0;
    }
    c.edge_cap.resize(pb.num_edges());
    for (std::size_t e = 0; e < pb.num_edges(); ++e) c.edge_cap[e] = 2.0 * pb.edge_weights[e];
    return c;
  }();
  return cut;
}

// Arg 0: the shared max-flow (MinCutLabels); 1: Boost (MinCutLabelsBoost).
void BM_MaxFlowBalancedCut(benchmark::State& state) {
  const al::RefineProblem& pb = Problem();
  const LevelCut& c = BalancedCut();
  al::MinCutResult r;
  for (auto _ : state) {
    r = state.range(0) == 0
            ? al::MinCutLabels(c.source_cap, c.sink_cap, pb.first_edge, pb.adj_vertices, c.edge_cap)
            : al::MinCutLabelsBoost(c.source_cap, c.sink_cap, pb.first_edge, pb.adj_vertices,
                                    c.edge_cap);
    benchmark::DoNotOptimize(r.source_side.data());
  }
  double source = 0.0;
  for (auto s : r.source_side) source += s;
  state.counters["cut_value"] = r.cut_value;
  state.counters["source_side"] = source;
  state.counters["build_s"] = r.build_seconds;
}

BENCHMARK(BM_Cp)->ArgNames({"threads", "sat", "maxflow"})->Args({1, 1, 0})->Args({2, 1, 0})
    ->Args({2, 1, 1})->Args({1, 0, 0})->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(5)
    ->ReportAggregatesOnly(true)->UseRealTime();
BENCHMARK(BM_Exact)->ArgName("maxflow")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1)
    ->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();
BENCHMARK(BM_MaxFlowBalancedCut)->ArgName("boost")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)
    ->Iterations(1)->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
