// RunSweep (al/refine/sweep.hpp): the shard's points, each appended to results.jsonl as soon as it
// is done; inputs loaded once per scene, one graph per (k, δ, hops, radius_scale), λ applied by
// rescaling the λ = 1 weights.
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/refine/stages.hpp"
#include "al/refine/sweep.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

// Graph statistics of a record: GraphStatsToJson without its timings (those go to "seconds").
nlohmann::json GraphRecord(const GraphStats& stats) {
  nlohmann::json g = GraphStatsToJson(stats);
  g.erase("seconds");
  return g;
}

// Solver statistics of a record: without timings (moved to `timings`, so that everything outside
// "seconds" is reproducible) and per-iteration histories (one line per point should stay short).
nlohmann::json SolverRecord(const nlohmann::json& solver, nlohmann::json& timings) {
  nlohmann::json s = solver;
  s.erase("seconds");
  if (s.contains("stats") && s["stats"].is_object())
    for (auto it = s["stats"].begin(); it != s["stats"].end();) {
      const std::string key = it.key();
      if (key.ends_with("_seconds")) timings[key] = it.value();
      it = key.ends_with("_history") || key.ends_with("_seconds") ? s["stats"].erase(it) : std::next(it);
    }
  return s;
}

// Solver options for one solver: the object's entry under the solver's name (options differ by
// solver, and unknown keys are an error).
nlohmann::json OptionsFor(const nlohmann::json& all, const std::string& solver) {
  if (all.is_object() && all.contains(solver)) return all[solver];
  return nlohmann::json::object();
}

void CheckInputsExist(const SweepScene& s) {
  auto need = [&](const std::string& path, const char* what) {
    if (!path.empty() && !fs::exists(path))
      throw Error("scene '" + s.name + "': " + what + " " + path + " does not exist", ExitCode::kBadInput);
  };
  need(s.options.scene, "scene");
  need(s.options.removed, "removed set");
  need(s.options.labels, "labels");
  need(s.cameras, "cameras");
  need(s.object_masks, "object masks");
}

// results.jsonl is the sweep's journal: appended in place point by point (a kill loses at most
// the point in flight), so it lives in --out; the rest of the set is staged and committed.
OutputSetOptions SweepOutputSetOptions(const SweepOptions& o) {
  OutputSetOptions so;
  so.command = "sweep";
  for (const auto& s : o.scenes)
    for (const auto& p : {s.options.scene, s.options.removed, s.options.labels, s.options.features, s.cameras,
                          s.object_masks})
      so.inputs.push_back(p);
  so.planned = {"results.csv", "report.json"};
  so.journals = {"results.jsonl"};
  return so;
}

nlohmann::json GridJson(const SweepGrid& g) {
  return {{"k", g.k}, {"delta", g.delta}, {"hops", g.hops}, {"radius_scale", g.radius_scale},
          {"lambda", g.lambda}, {"solver", g.solver}, {"threshold", g.threshold},
          {"segment_share", g.segment_share}};
}

}  // namespace

SweepResult RunSweep(const SweepOptions& o) {
  Timer total_timer;
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  if (o.scenes.empty()) throw Error("sweep: no scene (give --scene/--removed or --manifest)", ExitCode::kUsage);
  if (o.grid.size() == 0) throw Error("--grid: empty grid", ExitCode::kUsage);
  if (!o.solver_options.is_object()) throw Error("--solver-options: expected a JSON object {solver: {...}}", ExitCode::kUsage);
  for (const auto& [name, value] : o.solver_options.items()) {
    if (std::find(o.grid.solver.begin(), o.grid.solver.end(), name) == o.grid.solver.end())
      throw Error("--solver-options: '" + name + "' is not a solver of the grid", ExitCode::kUsage);
  }
  std::map<std::string, std::unique_ptr<Solver>> solvers;  // validates names and options up front
  for (const auto& name : o.grid.solver) solvers[name] = MakeSolver(name, OptionsFor(o.solver_options, name));

  const std::vector<SweepPoint> points = EnumeratePoints(o.grid);
  const std::size_t P = points.size();
  SweepResult result;
  result.total = o.scenes.size() * P;
  const auto [begin, end] = ShardRange(result.total, o.shard);
  result.in_shard = end - begin;
  for (std::size_t s = begin / P; s < o.scenes.size() && s * P < end; ++s) CheckInputsExist(o.scenes[s]);

  nlohmann::json report = NewReport("sweep");
  nlohmann::json& warnings = report["warnings"];
  nlohmann::json scenes = nlohmann::json::array();
  for (const auto& s : o.scenes)
    scenes.push_back({{"name", s.name}, {"scene", s.options.scene}, {"removed", s.options.removed},
                      {"method", s.options.method}, {"labels", s.options.labels}, {"cameras", s.cameras},
                      {"object_masks", s.object_masks}});
  report["params"] = {{"grid", GridJson(o.grid)}, {"shard", o.shard.ToString()}, {"scenes", scenes},
                      {"solver_options", o.solver_options}, {"eval_views", o.eval_views}, {"out", o.out_dir},
                      {"lambda_rescaled", true}};

  OutputSet set(o.out_dir, SweepOutputSetOptions(o));
  const fs::path jsonl = set.Journal("results.jsonl");
  const JsonlContents existing = ReadResultsJsonl(jsonl.string());
  if (existing.truncated_tail) {
    // Drop the half line of a killed run so the next append starts on a fresh line.
    fs::resize_file(jsonl, existing.good_bytes);
    warnings.push_back("results.jsonl ended in a truncated line (a killed run); it was dropped and that point re-run");
  }
  bool needs_newline = false;  // a complete last record without its newline (kept): end it first
  if (!existing.truncated_tail && existing.good_bytes > 0) {
    std::ifstream last(jsonl, std::ios::binary);
    last.seekg(static_cast<std::streamoff>(existing.good_bytes) - 1);
    needs_newline = last.get() != '\n';
  }
  std::set<std::string> done;
  for (const auto& r : existing.records) done.insert(r["id"].get<std::string>());

  std::ofstream out(jsonl, std::ios::app | std::ios::binary);
  if (!out) throw FileError(jsonl.string(), "cannot open for appending");
  if (needs_newline) out << '\n' << std::flush;

  // Per-scene and per-graph state, rebuilt only when the scene or a graph axis changes.
  std::optional<RefineInputs> inputs;
  std::size_t inputs_scene = SIZE_MAX;
  std::optional<GraphResult> graph;
  std::optional<SweepPoint> graph_point;
  std::vector<double> unit_weights;  // edge weights at λ = 1
  double applied_lambda = 1.0, graph_seconds = 0.0;
  nlohmann::json load_seconds = nlohmann::json::object();
  std::optional<PointEvalSetup> eval_setup;

  for (std::size_t j = begin; j < end; ++j) {
    const SweepScene& sc = o.scenes[j / P];
    const SweepPoint& p = points[j % P];
    SweepProgress progress{j - begin + 1, end - begin, nullptr, PointId(sc.name, p)};
    if (done.count(progress.id)) {
      ++result.already_done;
      if (o.on_point) o.on_point(progress);
      continue;
    }
    Timer point_timer;
    if (inputs_scene != j / P) {
      graph.reset();
      inputs.reset();
      nlohmann::json scene_report = NewReport("refine");
      inputs = LoadRefineInputs(sc.options, scene_report);
      inputs_scene = j / P;
      report["inputs"][sc.name] = scene_report["inputs"];
      for (const auto& w : scene_report["warnings"]) warnings.push_back(sc.name + ": " + w.get<std::string>());
      eval_setup.reset();
      if (!sc.cameras.empty())
        eval_setup = MakePointEvalSetup(sc.cameras, o.eval_views, sc.object_masks, *inputs,
                                        (set.dir() / ".al-eval-scratch").string());
      load_seconds[sc.name] = point_timer.Seconds();
    }
    GraphOptions go = sc.options.graph;
    go.k = p.k;
    go.delta = p.delta;
    go.hops = p.hops;
    go.radius_scale = p.radius_scale;
    bool reused = true;
    if (!graph || !SameGraph(*graph_point, p)) {
      graph.reset();
      go.lambda = 1.0;
      graph = BuildGraphFor(*inputs, go);
      graph_point = p;
      unit_weights = graph->problem.edge_weights;
      applied_lambda = 1.0;
      graph_seconds = graph->stats.seconds_total;
      ++result.graphs_built;
      reused = false;
    }
    go.lambda = p.lambda;
    if (applied_lambda != p.lambda) {
      // λ multiplies every weight (SPEC §4.6): rescaling equals a rebuild up to the rounding of one
      // product (bit-identical for powers of two).
      auto& w = graph->problem.edge_weights;
      for (std::size_t e = 0; e < w.size(); ++e) w[e] = p.lambda == 1.0 ? unit_weights[e] : unit_weights[e] * p.lambda;
      applied_lambda = p.lambda;
    }
    DecisionOptions decision = sc.options.decision;
    decision.rule = ParseDecisionRule(p.threshold);
    decision.min_segment_share = p.segment_share;
    Timer solve_timer;
    const SolveOutcome solved = SolveAndDecide(*inputs, *graph, go, *solvers.at(p.solver), decision);
    const double solve_and_decide = solve_timer.Seconds();
    const double solve_seconds = solved.solver.value("seconds", solve_and_decide);

    nlohmann::json solver_timings = nlohmann::json::object();
    std::size_t refined = 0;
    for (bool b : solved.refined) refined += b;
    nlohmann::json record = {
        {"id", progress.id},
        {"scene", sc.name},
        {"params",
         {{"k", p.k}, {"delta", p.delta}, {"hops", p.hops}, {"radius_scale", p.radius_scale},
          {"lambda", p.lambda}, {"solver", p.solver}, {"threshold", p.threshold},
          {"segment_share", p.segment_share},
          {"delta_mode", go.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
          {"spatial", go.spatial}, {"knn_checks", go.knn_checks}, {"kl_smoothing", go.kl_smoothing},
          {"restore", decision.restore}, {"method", sc.options.method}}},
        {"status", solved.empty_graph ? "empty_graph" : "ok"},
        {"graph", GraphRecord(graph->stats)},
        {"solver", SolverRecord(solved.solver, solver_timings)},
        {"decision", solved.decision},
        {"counts",
         {{"removed_input", inputs->removal.num_removed}, {"added", solved.added},
          {"restored", solved.restored}, {"refined", refined}}},
    };
    Timer score_timer;
    if (inputs->ground_truth)
      record["gt"] = ScoreAgainstGroundTruth(*inputs->ground_truth, inputs->removal.removed, solved.refined);
    const double score_seconds = score_timer.Seconds();
    Timer eval_timer;
    if (eval_setup) record["eval"] = EvaluatePoint(inputs->scene, *eval_setup, solved.refined);
    // graph: the build time of the graph this point used (also when reused), so graph + solve is
    // what the setting costs on its own; point: wall time this run spent on the point.
    record["seconds"] = {{"graph", graph_seconds},
                         {"solve", solve_seconds},
                         {"decide", std::max(0.0, solve_and_decide - solve_seconds)},
                         {"score", score_seconds},
                         {"eval", eval_timer.Seconds()},
                         {"solver_stages", solver_timings},
                         {"point", point_timer.Seconds()}};
    record["run"] = {{"graph_reused", reused}, {"shard", o.shard.ToString()}};

    out << record.dump() << '\n';
    out.flush();
    if (!out) throw FileError(jsonl.string(), "write failed (disk full?)");
    ++result.ran;
    result.empty_graphs += solved.empty_graph;
    progress.record = &record;
    if (o.on_point) o.on_point(progress);
  }
  out.close();

  std::vector<nlohmann::json> records = ReadResultsJsonl(jsonl.string()).records;
  SortRecords(records);
  // A shard's charts would show only its slice: shards write the CSV, `merge` draws the charts.
  const nlohmann::json summaries = WriteSweepSummaries(set.dir().string(), records, /*charts=*/o.shard.count == 1);
  for (const auto& s : summaries["skipped_charts"])
    warnings.push_back("chart " + s["name"].get<std::string>() + " skipped: " + s["reason"].get<std::string>());
  report["outputs"] = summaries;
  report["counts"] = {{"points_total", result.total}, {"points_in_shard", result.in_shard},
                      {"already_done", result.already_done}, {"ran", result.ran},
                      {"empty_graphs", result.empty_graphs}, {"graphs_built", result.graphs_built},
                      {"records", records.size()}};
  report["timings_s"] = {{"load", load_seconds}, {"total", total_timer.Seconds()}};
  result.report = set.Commit(report);
  return result;
}

}  // namespace al
