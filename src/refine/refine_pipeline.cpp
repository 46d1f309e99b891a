// RunRefine: the whole `refine` flow as a library call (see al/refine/refine.hpp): the stages of
// al/refine/stages.hpp in a row, then the outputs. Files and memory differ only in how the inputs
// are loaded; from there on both run RefineLoaded, so the CLI and the Python module agree.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <optional>

#include "al/core/error.hpp"
#include "al/core/heap.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/text.hpp"
#include "al/core/timer.hpp"
#include "al/graph/problem_io.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

struct RefineCounts {
  std::vector<bool> added;
  std::size_t added_count = 0, restored = 0, refined = 0;
};

RefineCounts CountChanges(const std::vector<bool>& removed, const std::vector<bool>& refined) {
  RefineCounts c;
  c.added.assign(refined.size(), false);
  for (std::size_t i = 0; i < refined.size(); ++i) {
    c.added[i] = refined[i] && !removed[i];
    c.added_count += c.added[i];
    c.restored += removed[i] && !refined[i];
    c.refined += refined[i];
  }
  return c;
}

OutputSetOptions ExportSetOptions(const RefineOptions& o) {
  OutputSetOptions so = RefineOutputSetOptions(o);
  so.command = "export-problem";
  so.flag = "--export-problem";
  so.planned = {"first_edge.npy", "adj_vertices.npy", "edge_weights.npy", "y.npy", "node_weights.npy",
                "node_ids.npy", "p.npy", "params.json", "report.json"};
  return so;
}

// remaining.ply into the staging folder, on a thread of its own: the biggest output spends most of
// its time waiting on the disk (3M scene: 557 MB, ~0.2 s at half a core), while the scores and the
// small outputs are computed beside it. The caller waits on the future before committing; its
// destructor waits too, so an exception elsewhere never leaves the writer running.
// The writer has its own copy of the mask (375 KB at 3M), so the caller may release the solve's
// memory while it writes.
std::future<void> StartRemainingPly(const RefineInputs& in, const std::vector<bool>& refined, const fs::path& out) {
  return std::async(std::launch::async, [&in, refined, out] {
    std::vector<bool> keep(refined.size());
    for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = !refined[i];
    WritePly((out / "remaining.ply").string(), *in.scene, keep);
  });
}

// refined.npy, refined.txt, added.txt into the staging folder of the run's output set, and the
// optional problem export (its own set).
void WriteRefineOutputs(const RefineOptions& o, const GraphResult& graph, const SolveOutcome& solved,
                        const RefineCounts& counts, const fs::path& out) {
  WriteNpyBool((out / "refined.npy").string(), solved.refined);
  WriteIndexText((out / "refined.txt").string(), MaskToIndices(solved.refined), "refined removed set");
  WriteIndexText((out / "added.txt").string(), MaskToIndices(counts.added), "Gaussians added by refinement");
  if (!o.export_problem_dir.empty())
    ExportProblemSet(o, graph.problem, graph.stats.lambda, solved.empty_graph ? nullptr : &solved.p);
}

// The graph and decision fields come from their options tables (the same names as the flags).
nlohmann::json RefineParams(const RefineOptions& o, const RefineInputs& in, const std::string& solver_name) {
  nlohmann::json params = {
      {"scene", o.scene}, {"removed", o.removed},
      {"removed_is", in.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
      {"method", o.method}, {"preset", in.preset.ToJson()}, {"features", in.feature_spec},
      {"feature_source", in.feature_source}, {"colour_fallback", in.colour_fallback},
      {"decoder", o.decoder}, {"solver", solver_name}, {"solver_options", o.solver_options},
      {"labels", o.labels}, {"max_unmatched", o.max_unmatched}, {"match_tol", o.match_tol},
      {"prompt_embeddings", o.prompt_embeddings}, {"positive", o.positives},
      {"fgs_threshold", o.fgs_threshold}, {"out", o.out_dir},
      {"export_problem", o.export_problem_dir}};
  params.update(GraphOptions::Table().ToJson(o.graph));
  params.update(DecisionOptions::Table().ToJson(o.decision));
  return params;
}

// The report's counts, parameters and the graph's, solver's and decision's sections.
void FillRefineReport(const RefineOptions& o, const RefineInputs& in, const std::string& solver_name,
                      const GrownSolve& grown, const RefineResult& result, const RefineCounts& counts,
                      nlohmann::json& report) {
  const GraphStats& gs = grown.graph.stats;
  report["status"] = result.status;
  report["params"] = RefineParams(o, in, solver_name);
  report["counts"] = {{"num_gaussians", in.scene->size()}, {"removed_input", in.removal.num_removed},
                      {"candidates", gs.nodes}, {"edges", gs.edges}, {"refined", counts.refined},
                      {"added", counts.added_count}, {"restored", counts.restored},
                      {"excluded_nonfinite", gs.excluded_nonfinite}};
  report["removed_set"] = in.removal.stats;
  if (!in.fgs_mask.is_null()) report["fgs_mask"] = in.fgs_mask;
  report["graph"] = gs.ToJson();
  report["graph"]["rounds"] = grown.rounds;
  report["graph"]["growth_capped"] = grown.capped;
  report["graph"]["growth_stop"] = grown.growth_stop;
  report["solver"] = grown.outcome.solver;
  report["decision"] = grown.outcome.decision;
  report["message"] = result.message;
}

// Graph → solve → decide → ground-truth scores → outputs (into set, when given) → report (the
// caller commits it with the set).
RefineResult RefineLoaded(const RefineInputs& in, const RefineOptions& o, Solver& solver,
                          const std::string& solver_name, nlohmann::json report, const Timer& total,
                          OutputSet* set) {
  nlohmann::json& timings = report["timings_s"];
  nlohmann::json& warnings = report["warnings"];
  Timer t;
  auto stage_done = [&](const std::string& name) {
    const double s = t.Seconds();
    timings[name] = s;
    if (o.on_stage) o.on_stage(name, s);
    t.Reset();
  };
  GrownSolve grown = BuildAndSolve(in, o.graph, solver, o.decision);
  const GraphResult& graph = grown.graph;
  const SolveOutcome& solved = grown.outcome;
  for (const auto& w : graph.warnings) warnings.push_back(w);
  for (const auto& w : solved.warnings) warnings.push_back(w);
  {
    // Graph builds and solves alternate when the candidate set grows: report their sums.
    const double total_s = t.Seconds();
    timings["graph"] = grown.graph_seconds;
    timings["solve"] = grown.solve_seconds;
    timings["decide"] = std::max(0.0, total_s - grown.graph_seconds - grown.solve_seconds);
    report["decide_seconds"] = {{"last_steps", grown.outcome.last_steps_seconds}};  // part of timings_s.decide
    if (o.on_stage) o.on_stage("graph", grown.graph_seconds), o.on_stage("solve", grown.solve_seconds);
    t.Reset();
  }

  std::future<void> remaining;  // reads `in` (the caller's) and its own mask; waited for on every way out
  if (set) remaining = StartRemainingPly(in, solved.refined, set->dir());
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
  const RefineCounts counts = CountChanges(in.removal.removed, result.refined);
  for (std::size_t i = 0; i < result.refined.size(); ++i) {
    if (counts.added[i]) result.added.push_back(std::int64_t(i));
    else if (in.removal.removed[i] && !result.refined[i]) result.restored.push_back(std::int64_t(i));
  }
  if (set) WriteRefineOutputs(o, graph, solved, counts, set->dir());
  FillRefineReport(o, in, solver_name, grown, result, counts, report);
  if (set) {
    // Everything the graph and the solve made is written and reported: their pages go back to the
    // system while remaining.ply is still being written (this thread would only wait), instead of
    // at exit (3M scene: ~0.1 s of page freeing on one thread after the run).
    grown = GrownSolve{};
    ReleaseFreeHeap();
    remaining.get();  // rethrows the writer's error
    stage_done("write");
  }
  timings["total"] = total.Seconds();
  result.report = std::move(report);
  return result;
}

}  // namespace

nlohmann::json RefineResult::Summary() const {
  nlohmann::json s = {{"status", status}, {"message", message}};
  const nlohmann::json counts = report.value("counts", nlohmann::json::object());
  for (const auto& [key, value] : counts.items()) s[key] = value;
  if (report.contains("gt"))
    for (const char* when : {"before", "after"})
      for (const char* metric : {"f1", "iou", "precision", "recall"})
        s[std::string("gt_") + metric + "_" + when] = report["gt"][when][metric];
  s["seconds"] = report.value("timings_s", nlohmann::json::object()).value("total", 0.0);
  return s;
}

OutputSetOptions RefineOutputSetOptions(const RefineOptions& o) {
  OutputSetOptions so("refine", {o.scene, o.removed, o.features, o.labels, o.prompt_embeddings},
                      {"refined.npy", "refined.txt", "added.txt", "remaining.ply", "report.json"});
  for (const auto& part : SplitTrimmed(o.decoder, ',')) so.inputs.push_back(part);
  return so;
}

void ExportProblemSet(const RefineOptions& o, const RefineProblem& problem, double lambda,
                      const std::vector<double>* p) {
  OutputSet set(o.export_problem_dir, ExportSetOptions(o));
  ExportProblem(problem, p, set.dir().string(), lambda);
  nlohmann::json report = NewReport("export-problem");
  report["params"] = {{"scene", o.scene}, {"removed", o.removed}, {"lambda", lambda}};
  report["counts"] = {{"nodes", problem.num_nodes()}, {"edges", problem.num_edges()}};
  set.Commit(report);
}

RefineResult RefineIntoSet(const RefineOptions& o, OutputSet& set) {
  Timer total;
  nlohmann::json report = NewReport("refine");
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  o.Check();
  if (!o.export_problem_dir.empty()) OutputSet preflight(o.export_problem_dir, ExportSetOptions(o));
  const std::string solver_name = ResolveSolverName(o.solver);
  auto solver = MakeSolver(solver_name, o.solver_options);  // fails early on a bad name/options
  const RefineInputs in = LoadRefineInputs(o, report, SceneColumns::kRefine);  // nothing here renders
  return RefineLoaded(in, o, *solver, solver_name, std::move(report), total, &set);
}

std::string RefineResult::BriefReport() const {
  const nlohmann::json& c = report["counts"];
  std::string text = "nodes " + c["candidates"].dump() + ", edges " + c["edges"].dump() + ", removed " +
                     c["removed_input"].dump() + " -> " + c["refined"].dump() + "\n";
  if (!report.contains("gt")) return text;
  const nlohmann::json& gt = report["gt"];
  const nlohmann::json& ch = gt["change"];
  return text + "ground truth F1 " + gt["before"]["f1"].dump() + " -> " + gt["after"]["f1"].dump() +
         "; misses recovered " + ch["misses_recovered"].dump() + ", precision of the added " +
         ch["precision_added"].dump() + ", of the restored " + ch["precision_restored"].dump() + "\n";
}

RefineResult RunRefine(const RefineOptions& o) {
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  o.Check();  // bad options are refused before --out is touched
  OutputSet set(o.out_dir, RefineOutputSetOptions(o));  // --out checked before anything is loaded
  RefineResult result = RefineIntoSet(o, set);
  result.report = set.Commit(result.report);
  return result;
}

RefineResult RunRefine(const RefineData& data, const RefineOptions& options) {
  Timer total;
  nlohmann::json report = NewReport("refine");
  options.Check();
  RefineOptions o = options;
  if (o.scene.empty()) o.scene = data.scene && !data.scene->source_path.empty() ? data.scene->source_path : data.name;
  if (o.removed.empty() && data.removed.data != nullptr) o.removed = data.name;
  const std::string solver_name = ResolveSolverName(o.solver);
  auto solver = MakeSolver(solver_name, o.solver_options);
  std::optional<OutputSet> set;
  if (!o.out_dir.empty()) set.emplace(o.out_dir, RefineOutputSetOptions(o));
  const RefineInputs in = InputsFromData(data, o, report);
  RefineResult result = RefineLoaded(in, o, *solver, solver_name, std::move(report), total, set ? &*set : nullptr);
  if (set) result.report = set->Commit(result.report);
  return result;
}

}  // namespace al
