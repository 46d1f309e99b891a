// The solver comparison of `al-refine compare` as a benchmark: bk, cp over cp_dif_tol 1e-2/1e-3/1e-4
// and exact on the SAME refine graph of a deterministic 200k synthetic room (seed 1, FGS simulator
// removal, k = 10, δ = 0.8: ~46k nodes, ~260k edges). Each run is solve + 0.5 decision, 3 timed
// iterations; counters: median_s (median of the 3), ratio_to_exact (median_s / exact's median_s,
// exact runs first in the same process), rel_gap_to_exact, added, f1 (ground truth after the
// decision). Usage: compare_bench [--benchmark_format=json].
#include <memory>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>
#include <vector>

#include "al/core/timer.hpp"
#include "al/fixtures/synth.hpp"
#include "al/refine/compare.hpp"
#include "al/solver.hpp"

namespace {

struct Fixture {
  al::RefineInputs inputs;
  al::GraphOptions go;
  al::GraphResult graph;
};

const Fixture& Scene() {
  static const Fixture f = [] {
    al::fixtures::SynthOptions so;
    so.num_gaussians = 200000;
    so.seed = 1;
    so.num_views = 2;
    so.width = 32;
    so.height = 24;
    so.compute_masks = false;  // FGS simulator only; masks are not needed
    al::fixtures::SynthScene s = al::fixtures::Synthesize(so);
    Fixture x;
    x.inputs.removal.removed = s.removed.at("fgs");
    for (bool b : x.inputs.removal.removed) x.inputs.removal.num_removed += b;
    x.inputs.SetFeatures(s.scene.features);
    x.inputs.ground_truth = al::GroundTruth{
        s.labels, s.target_id,
        std::vector<float>(s.scene.opacity_logits.data(), s.scene.opacity_logits.data() + s.scene.size())};
    x.inputs.scene = std::make_shared<const al::Scene>(std::move(s.scene));
    x.graph = al::BuildGraphFor(x.inputs, x.go);
    return x;
  }();
  return f;
}

double exact_objective = 0.0, exact_median_s = 0.0;  // set by the exact run, which is registered first

void BM_Compare(benchmark::State& state, al::SolverRun run) {
  const Fixture& f = Scene();
  const auto solver = al::MakeSolver(run.solver, run.options);
  state.SetLabel(run.options.dump());
  std::vector<double> seconds;
  al::SolveOutcome out;
  for (auto _ : state) {
    al::Timer t;
    out = al::SolveAndDecide(f.inputs, f.graph, f.go, *solver, {});
    seconds.push_back(t.Seconds());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  const double objective = out.solver["objective"].get<double>();
  if (run.solver == "exact") {
    exact_objective = objective;
    exact_median_s = median;
  }
  state.counters["median_s"] = median;
  state.counters["objective"] = objective;
  state.counters["rel_gap_to_exact"] = (objective - exact_objective) / exact_objective;
  state.counters["ratio_to_exact"] = median / exact_median_s;
  state.counters["added"] = static_cast<double>(out.added);
  state.counters["f1"] = al::ScoreAgainstGroundTruth(*f.inputs.ground_truth, f.inputs.removal.removed,
                                                     out.refined)["after"]["f1"].get<double>();
  state.counters["nodes"] = static_cast<double>(f.graph.stats.nodes);
  state.counters["edges"] = static_cast<double>(f.graph.stats.edges);
}

// exact first (the baseline of the ratios), then the runs `compare` plans by default. Called from
// main, not a static initialiser: the solver registry is filled by other translation units.
void RegisterAll() {
  al::CompareOptions o;
  o.solvers = {"exact", "bk", "cp"};
  o.grid = al::DefaultSolverGrid();
  for (const auto& run : al::PlanSolverRuns(o))
    benchmark::RegisterBenchmark(("BM_Compare/" + run.id).c_str(), BM_Compare, run)
        ->Iterations(3)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RegisterAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
