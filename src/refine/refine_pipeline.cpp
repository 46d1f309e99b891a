// RunRefine: the whole `refine` flow as a library call (see al/refine/refine.hpp): the stages of
// al/refine/stages.hpp in a row, then the outputs.
#include <algorithm>
#include <filesystem>

#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/text.hpp"
#include "al/core/timer.hpp"
#include "al/graph/problem_io.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"

namespace al {

namespace fs = std::filesystem;

OutputSetOptions RefineOutputSetOptions(const RefineOptions& o) {
  OutputSetOptions so;
  so.command = "refine";
  so.inputs = {o.scene, o.removed, o.features, o.labels, o.prompt_embeddings};
  for (const auto& part : SplitTrimmed(o.decoder, ',')) so.inputs.push_back(part);
  so.planned = {"refined.npy", "refined.txt", "added.txt", "remaining.ply", "report.json"};
  return so;
}

namespace {

OutputSetOptions ExportSetOptions(const RefineOptions& o) {
  OutputSetOptions so = RefineOutputSetOptions(o);
  so.command = "export-problem";
  so.flag = "--export-problem";
  so.planned = {"first_edge.npy", "adj_vertices.npy", "edge_weights.npy", "y.npy", "node_weights.npy",
                "node_ids.npy", "p.npy", "params.json", "report.json"};
  return so;
}

}  // namespace

void ExportProblemSet(const RefineOptions& o, const RefineProblem& problem, const std::vector<double>* p) {
  OutputSet set(o.export_problem_dir, ExportSetOptions(o));
  ExportProblem(problem, p, set.dir().string(), o.graph.lambda);
  nlohmann::json report = NewReport("export-problem");
  report["params"] = {{"scene", o.scene}, {"removed", o.removed}, {"lambda", o.graph.lambda}};
  report["counts"] = {{"nodes", problem.num_nodes()}, {"edges", problem.num_edges()}};
  set.Commit(report);
}

RefineResult RunRefine(const RefineOptions& o) {
  OutputSet set(o.out_dir, RefineOutputSetOptions(o));
  RefineResult result = RefineIntoSet(o, set);
  result.report = set.Commit(result.report);
  return result;
}

RefineResult RefineIntoSet(const RefineOptions& o, OutputSet& set) {
  Timer total;
  nlohmann::json report = NewReport("refine");
  nlohmann::json& timings = report["timings_s"];
  nlohmann::json& warnings = report["warnings"];
  Timer t;
  auto stage_done = [&](const std::string& name) {
    const double s = t.Seconds();
    timings[name] = s;
    if (o.on_stage) o.on_stage(name, s);
    t.Reset();
  };
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  if (!o.export_problem_dir.empty()) OutputSet preflight(o.export_problem_dir, ExportSetOptions(o));
  const std::string solver_name = ResolveSolverName(o.solver);
  auto solver = MakeSolver(solver_name, o.solver_options);  // fails early on a bad name/options

  RefineInputs in = LoadRefineInputs(o, report);
  t.Reset();
  const std::size_t N = in.scene.size();
  const GraphOptions& go = o.graph;
  GraphResult graph = BuildGraphFor(in, go);
  const GraphStats& gs = graph.stats;
  for (const auto& w : graph.warnings) warnings.push_back(w);
  stage_done("graph");

  SolveOutcome solved = SolveAndDecide(in, graph, go, *solver, o.decision);
  for (const auto& w : solved.warnings) warnings.push_back(w);
  if (!solved.empty_graph) {
    // The solver times itself; the rest of this stage is the decision rule.
    const double solve_s = solved.solver.value("seconds", 0.0);
    timings["solve"] = solve_s;
    if (o.on_stage) o.on_stage("solve", solve_s);
    timings["decide"] = std::max(0.0, t.Seconds() - solve_s);
    t.Reset();
  } else {
    stage_done("decide");
  }

  RefineResult result;
  result.removed = in.removal.removed;
  result.refined = solved.refined;
  result.message = solved.message;
  if (solved.empty_graph) {
    result.status = "empty_graph";
    result.exit_code = static_cast<int>(ExitCode::kEmptyGraph);
  }
  if (in.ground_truth) {
    report["gt"] = ScoreAgainstGroundTruth(*in.ground_truth, in.removal.removed, result.refined);
    stage_done("ground_truth");
  }

  // Outputs: staged, published by the caller's commit.
  const fs::path out = set.dir();
  WriteNpyBool((out / "refined.npy").string(), result.refined);
  WriteIndexText((out / "refined.txt").string(), MaskToIndices(result.refined), "refined removed set");
  std::vector<bool> added(N, false), keep(N);
  std::size_t n_added = 0, n_restored = 0, n_refined = 0;
  for (std::size_t i = 0; i < N; ++i) {
    added[i] = result.refined[i] && !in.removal.removed[i];
    n_added += added[i];
    n_restored += in.removal.removed[i] && !result.refined[i];
    n_refined += result.refined[i];
    keep[i] = !result.refined[i];
  }
  WriteIndexText((out / "added.txt").string(), MaskToIndices(added), "Gaussians added by refinement");
  WritePly((out / "remaining.ply").string(), in.scene, keep);
  if (!o.export_problem_dir.empty()) ExportProblemSet(o, graph.problem, solved.empty_graph ? nullptr : &solved.p);
  stage_done("write");

  report["status"] = result.status;
  report["params"] = {
      {"scene", o.scene}, {"removed", o.removed},
      {"removed_is", in.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
      {"method", o.method}, {"preset", in.preset}, {"features", in.feature_spec},
      {"feature_source", in.feature_source}, {"colour_fallback", in.colour_fallback},
      {"decoder", o.decoder},
      {"k", go.k}, {"delta", go.delta},
      {"delta_mode", go.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
      {"lambda", go.lambda}, {"spatial", go.spatial}, {"hops", go.hops},
      {"radius_scale", go.radius_scale}, {"knn_checks", go.knn_checks},
      {"kl_smoothing", go.kl_smoothing}, {"solver", solver_name}, {"solver_options", o.solver_options},
      {"threshold", o.decision.rule.ToString()}, {"restore", o.decision.restore},
      {"labels", o.labels}, {"max_unmatched", o.max_unmatched}, {"match_tol", o.match_tol},
      {"prompt_embeddings", o.prompt_embeddings}, {"positive", o.positives},
      {"fgs_threshold", o.fgs_threshold}, {"out", o.out_dir},
      {"export_problem", o.export_problem_dir}};
  report["counts"] = {{"num_gaussians", N}, {"removed_input", in.removal.num_removed},
                      {"candidates", gs.nodes}, {"edges", gs.edges}, {"refined", n_refined},
                      {"added", n_added}, {"restored", n_restored},
                      {"excluded_nonfinite", gs.excluded_nonfinite}};
  report["removed_set"] = in.removal.stats;
  if (!in.fgs_mask.is_null()) report["fgs_mask"] = in.fgs_mask;
  report["graph"] = GraphStatsToJson(gs);
  report["solver"] = solved.solver;
  report["decision"] = solved.decision;
  report["message"] = result.message;
  timings["total"] = total.Seconds();
  result.report = report;
  return result;
}

}  // namespace al
