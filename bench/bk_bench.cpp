// bk (Boost Boykov-Kolmogorov on a CSR-built network) on the graph of the 1M-Gaussian scene with
// a ~100k-node candidate set, k = 10. The GPL maxflow comparison target is optional and not built;
// the network build alone is reported as the baseline share (stats.build_seconds).
#include <benchmark/benchmark.h>

#include "al/graph/graph.hpp"
#include "bench/refine_scene_1m.hpp"
#include "al/solver.hpp"

namespace {

using al::bench::BenchScene;
using al::bench::Scene1M;

void BM_Bk1M(benchmark::State& state) {
  const BenchScene& s = Scene1M();
  static const al::RefineProblem problem =
      al::BuildRefineGraph(s.scene, s.scene.features, s.removed, {}).problem;
  const auto solver = al::MakeSolver("bk");
  al::SolverResult r;
  for (auto _ : state) {
    r = solver->Solve(problem);
    benchmark::DoNotOptimize(r.p.data());
  }
  state.counters["nodes"] = static_cast<double>(problem.num_nodes());
  state.counters["edges"] = static_cast<double>(problem.num_edges());
  state.counters["build_s"] = r.stats["build_seconds"].get<double>();
  state.counters["flow_s"] = r.stats["flow_seconds"].get<double>();
}
BENCHMARK(BM_Bk1M)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
