// RunSweep (al/refine/sweep.hpp): the shard's points, each appended to results.jsonl as soon as it
// is done; inputs loaded once per scene, one graph per (k, δ, hops, radius_scale), λ applied by
// rescaling the λ = 1 weights.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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

// Graph statistics of a record: GraphStats::ToJson without its timings (those go to "seconds").
nlohmann::json GraphRecord(const GraphStats& stats, double lambda) {
  nlohmann::json g = stats.ToJson();
  g.erase("seconds");
  g["lambda"] = lambda;  // the graph is built at λ = 1 and rescaled per point
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

// Usage errors of the options, and one solver per grid solver (validates names and options).
std::map<std::string, std::unique_ptr<Solver>> CheckOptionsAndMakeSolvers(const SweepOptions& o) {
  o.Check();
  std::map<std::string, std::unique_ptr<Solver>> solvers;
  for (const auto& name : o.grid.solver) solvers[name] = MakeSolver(name, OptionsFor(o.solver_options, name));
  return solvers;
}

// results.jsonl is the sweep's journal: appended in place point by point (a kill loses at most the
// point in flight), so it lives in --out with shard.json, its identity; the rest of the set
// (results.csv, charts, report.json) is staged and committed (al/core/output_set.hpp).
OutputSetOptions SweepOutputSetOptions(const SweepOptions& o) {
  OutputSetOptions so("sweep");
  for (const auto& s : o.scenes)
    for (const auto& p : {s.options.scene, s.options.removed, s.options.labels, s.options.features, s.cameras,
                          s.object_masks})
      so.inputs.push_back(p);
  so.planned = {"results.csv", "report.json"};
  so.journals = {"results.jsonl", "shard.json"};
  return so;
}

nlohmann::json SweepParams(const SweepOptions& o) {
  nlohmann::json scenes = nlohmann::json::array();
  for (const auto& s : o.scenes)
    scenes.push_back({{"name", s.name}, {"scene", s.options.scene}, {"removed", s.options.removed},
                      {"method", s.options.method}, {"labels", s.options.labels}, {"cameras", s.cameras},
                      {"object_masks", s.object_masks}});
  return {{"grid", GridToJson(o.grid)}, {"shard", o.shard.ToString()}, {"scenes", scenes},
          {"solver_options", o.solver_options}, {"eval_views", o.eval_views}, {"out", o.out_dir},
          {"lambda_rescaled", true}};
}

// A folder being resumed must belong to this sweep and shard (its shard.json): mixing two sweeps' points (or two binaries' results) in one folder would be merged as one.
// An unsharded run may grow its grid (the documented way to add points): true then.
bool CheckOutDir(const std::string& dir, const ShardInfo& info) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(fs::path(dir) / "shard.json", ec))) {
    const ShardInfo old = ReadShardInfo(dir, Links::kRefuse);
    std::vector<std::string> diff = SweepDifferences(old, info);
    if (old.shard.index != info.shard.index && old.shard.count == info.shard.count)
      diff.insert(diff.begin(), "shard (" + old.shard.ToString() + " vs " + info.shard.ToString() + ")");
    const bool grid_grew = old.shard.count == 1 && info.shard.count == 1 &&
                           std::all_of(diff.begin(), diff.end(), [](const std::string& d) { return d.starts_with("grid"); });
    if (!diff.empty() && !grid_grew) {
      std::string what;
      for (const auto& d : diff) what += (what.empty() ? "" : "; ") + d;
      throw Error("--out " + dir + " already holds another shard or sweep (there vs here: " + what +
                      "); use a fresh --out, or the same flags, shard and binary to resume it",
                  ExitCode::kBadInput);
    }
    return !diff.empty();
  }
  return false;
}

// shard.json, the folder's identity: kept as a journal while it says what this run would write
// (or written first thing when missing, so that a killed shard can still be merged), staged as a
// whole when the grid grew, so the committed set is never rewritten in place before the commit.
void ClaimShardInfo(OutputSet& set, const std::string& out_dir, const ShardInfo& info) {
  if (CheckOutDir(out_dir, info)) {
    set.StageInsteadOfJournal("shard.json");
    WriteShardInfo(set.dir().string(), info);
    return;
  }
  const fs::path path = set.Journal("shard.json");
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) WriteShardInfo(path.parent_path().string(), info);
}

// results.jsonl through the descriptor the output set opened (never a link, never a FIFO): the
// ids it holds, and appends that fail loudly (a full disk is exit 2, not a silent loss).
class ResultsFile {
 public:
  ResultsFile(int fd, fs::path path) : fd_(fd), path_(std::move(path)) {}
  ~ResultsFile() { ::close(fd_); }
  ResultsFile(const ResultsFile&) = delete;
  ResultsFile& operator=(const ResultsFile&) = delete;
  std::string ReadAll() const;
  void Truncate(std::uintmax_t bytes) const;
  void Append(const std::string& text) const;
  std::set<std::string> done;

 private:
  int fd_;
  fs::path path_;
};

std::string ResultsFile::ReadAll() const {
  std::string text;
  char buffer[1 << 16];
  for (off_t at = 0;;) {
    const ssize_t got = ::pread(fd_, buffer, sizeof buffer, at);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw FileError(path_.string(), std::string("cannot read: ") + std::strerror(errno));
    if (got == 0) return text;
    text.append(buffer, static_cast<std::size_t>(got));
    at += got;
  }
}

void ResultsFile::Truncate(std::uintmax_t bytes) const {
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0)
    throw FileError(path_.string(), std::string("cannot cut off the truncated line: ") + std::strerror(errno));
}

void ResultsFile::Append(const std::string& text) const {
  for (std::size_t done_bytes = 0; done_bytes < text.size();) {
    const ssize_t put = ::write(fd_, text.data() + done_bytes, text.size() - done_bytes);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) throw FileError(path_.string(), std::string("write failed: ") + std::strerror(errno));
    done_bytes += static_cast<std::size_t>(put);
  }
}

// Opens results.jsonl after a killed run's half line is dropped; the ids it holds.
std::unique_ptr<ResultsFile> OpenResults(OutputSet& set, nlohmann::json& warnings) {
  auto f = std::make_unique<ResultsFile>(set.OpenJournal("results.jsonl"), set.out() / "results.jsonl");
  const std::string text = f->ReadAll();
  const JsonlContents existing = ParseResultsJsonl(text, (set.out() / "results.jsonl").string());
  if (existing.truncated_tail) {
    // Drop the half line of a killed run so the next append starts on a fresh line.
    f->Truncate(existing.good_bytes);
    warnings.push_back("results.jsonl ended in a truncated line (a killed or failed run); it was dropped and that "
                       "point re-run");
  }
  // A complete last record without its newline (kept): end it first.
  if (!existing.truncated_tail && existing.good_bytes > 0 && text[existing.good_bytes - 1] != '\n') f->Append("\n");
  for (const auto& r : existing.records) f->done.insert(r["id"].get<std::string>());
  return f;
}

// Inputs of the current scene and the current graph, rebuilt only when the scene or a graph axis
// changes; λ is applied by rescaling the λ = 1 weights.
class PointRunner {
 public:
  PointRunner(const SweepOptions& o, nlohmann::json& report, fs::path scratch)
      : o_(o), report_(report), scratch_(std::move(scratch)) {}
  std::size_t graphs_built() const { return graphs_built_; }
  const nlohmann::json& load_seconds() const { return load_seconds_; }

  // The record of job j (scene j / P, point p), with its timings and run details.
  nlohmann::json Run(std::size_t scene, const SweepPoint& p, const std::string& id, Solver& solver) {
    Timer point_timer;
    if (scene_ != scene) LoadScene(scene);
    const SweepScene& sc = o_.scenes[scene];
    GraphOptions go = sc.options.graph;
    go.k = p.k;
    go.delta = p.delta;
    go.hops = p.hops;
    go.radius_scale = p.radius_scale;
    // λ auto: the scene's preset decides per solver, as a refine run with these flags would.
    const double lambda = p.lambda ? *p.lambda : inputs_->preset.LambdaFor(p.solver);
    const bool reused = PrepareGraph(p, lambda, go);
    go.lambda = lambda;
    DecisionOptions decision = sc.options.decision;
    decision.rule = ParseDecisionRule(p.threshold);
    decision.min_segment_share = p.segment_share;
    Timer solve_timer;
    // Candidate growth as refine does it (--grow-rounds), from a copy of the shared graph.
    const GrownSolve grown = SolveAndGrow(*inputs_, go, solver, decision, *graph_);
    const SolveOutcome& solved = grown.outcome;
    const double solve_and_decide = std::max(0.0, solve_timer.Seconds() - grown.graph_seconds);
    nlohmann::json solver_timings = nlohmann::json::object();
    nlohmann::json record = Record(id, sc, p, go, decision, solved, solver_timings);
    record["growth"] = {{"rounds", grown.rounds}, {"capped", grown.capped}, {"stop", grown.growth_stop},
                        {"nodes", grown.graph.stats.nodes}};
    Timer score_timer;
    if (inputs_->ground_truth)
      record["gt"] = ScoreAgainstGroundTruth(*inputs_->ground_truth, inputs_->removal.removed, solved.refined);
    const double score_seconds = score_timer.Seconds();
    Timer eval_timer;
    if (eval_setup_) record["eval"] = EvaluatePoint(*inputs_->scene, *eval_setup_, solved.refined);
    // graph: the build time of the graph this point used (also when reused), so graph + solve is
    // what the setting costs on its own; point: wall time this run spent on the point.
    // grow: the builds of the growth rounds' graphs.
    record["seconds"] = {{"graph", graph_seconds_},
                         {"grow", grown.graph_seconds},
                         {"solve", grown.solve_seconds},
                         {"decide", std::max(0.0, solve_and_decide - grown.solve_seconds)},
                         {"score", score_seconds},
                         {"eval", eval_timer.Seconds()},
                         {"solver_stages", solver_timings},
                         {"point", point_timer.Seconds()}};
    record["run"] = {{"graph_reused", reused}, {"shard", o_.shard.ToString()}};
    return record;
  }

 private:
  void LoadScene(std::size_t scene) {
    Timer timer;
    const SweepScene& sc = o_.scenes[scene];
    graph_.reset();
    inputs_.reset();
    nlohmann::json scene_report = NewReport("refine");
    inputs_ = LoadRefineInputs(sc.options, scene_report);
    scene_ = scene;
    report_["inputs"][sc.name] = scene_report["inputs"];
    for (const auto& w : scene_report["warnings"]) report_["warnings"].push_back(sc.name + ": " + w.get<std::string>());
    eval_setup_.reset();
    if (!sc.cameras.empty())
      eval_setup_ = MakePointEvalSetup(sc.cameras, o_.eval_views, sc.object_masks, *inputs_, scratch_.string());
    load_seconds_[sc.name] = timer.Seconds();
  }

  // Builds the graph of p unless the current one is p's (returns true: reused), then applies λ.
  bool PrepareGraph(const SweepPoint& p, double lambda, GraphOptions go) {
    bool reused = true;
    if (!graph_ || !SameGraph(*graph_point_, p)) {
      graph_.reset();
      go.lambda = 1.0;
      graph_ = BuildGraphFor(*inputs_, go);
      graph_point_ = p;
      unit_weights_ = graph_->problem.edge_weights;
      applied_lambda_ = 1.0;
      graph_seconds_ = graph_->stats.seconds_total;
      ++graphs_built_;
      reused = false;
    }
    if (applied_lambda_ != lambda) {
      // λ multiplies every weight (SPEC §4.6): rescaling equals a rebuild up to the rounding of one
      // product (bit-identical for powers of two).
      auto& w = graph_->problem.edge_weights;
      for (std::size_t e = 0; e < w.size(); ++e) w[e] = lambda == 1.0 ? unit_weights_[e] : unit_weights_[e] * lambda;
      applied_lambda_ = lambda;
    }
    return reused;
  }

  nlohmann::json Record(const std::string& id, const SweepScene& sc, const SweepPoint& p, const GraphOptions& go,
                        const DecisionOptions& decision, const SolveOutcome& solved, nlohmann::json& solver_timings) {
    std::size_t refined = 0;
    for (bool b : solved.refined) refined += b;
    return {
        {"id", id},
        {"scene", sc.name},
        {"params",
         {{"k", p.k}, {"delta", p.delta}, {"hops", p.hops}, {"radius_scale", p.radius_scale},
          {"lambda", go.Lambda()}, {"lambda_auto", !p.lambda}, {"solver", p.solver}, {"threshold", p.threshold},
          {"segment_share", p.segment_share},
          {"delta_mode", go.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
          {"spatial", go.spatial}, {"knn_checks", go.knn_checks}, {"kl_smoothing", go.kl_smoothing},
          {"grow_rounds", go.grow_rounds},
          {"restore", solved.decision.value("restore", decision.Restores())},  // as the preset resolved it
          {"method", sc.options.method}}},
        {"status", solved.empty_graph ? "empty_graph" : "ok"},
        {"graph", GraphRecord(graph_->stats, go.Lambda())},
        {"solver", SolverRecord(solved.solver, solver_timings)},
        {"decision", solved.decision},
        {"counts",
         {{"removed_input", inputs_->removal.num_removed}, {"added", solved.added},
          {"restored", solved.restored}, {"refined", refined}}},
    };
  }

  const SweepOptions& o_;
  nlohmann::json& report_;
  fs::path scratch_;  // RunEval's folder per evaluated point, inside the staging folder
  std::optional<RefineInputs> inputs_;
  std::size_t scene_ = SIZE_MAX;
  std::optional<PointEvalSetup> eval_setup_;
  std::optional<GraphResult> graph_;
  std::optional<SweepPoint> graph_point_;
  std::vector<double> unit_weights_;  // edge weights at λ = 1
  double applied_lambda_ = 1.0, graph_seconds_ = 0.0;
  std::size_t graphs_built_ = 0;
  nlohmann::json load_seconds_ = nlohmann::json::object();
};

// results.csv, charts (unsharded runs only) and report.json from every record of the folder.
void FinishSweep(const SweepOptions& o, OutputSet& set, const fs::path& jsonl, SweepResult& result,
                 nlohmann::json& report, const Timer& total_timer, const nlohmann::json& load_seconds) {
  std::vector<nlohmann::json> records = ReadResultsJsonl(jsonl.string(), Links::kRefuse).records;
  SortRecords(records);
  // A shard's charts would show only its slice: shards write the CSV, `merge` draws the charts.
  const nlohmann::json summaries = WriteSweepSummaries(set.dir().string(), records, /*charts=*/o.shard.count == 1);
  for (const auto& s : summaries["skipped_charts"])
    report["warnings"].push_back("chart " + s["name"].get<std::string>() + " skipped: " + s["reason"].get<std::string>());
  report["outputs"] = summaries;
  report["counts"] = {{"points_total", result.total}, {"points_in_shard", result.in_shard},
                      {"already_done", result.already_done}, {"ran", result.ran},
                      {"empty_graphs", result.empty_graphs}, {"graphs_built", result.graphs_built},
                      {"records", records.size()}};
  report["timings_s"] = {{"load", load_seconds}, {"total", total_timer.Seconds()}};
  result.report = set.Commit(report);
}

}  // namespace

SweepResult RunSweep(const SweepOptions& o) {
  Timer total_timer;
  const auto solvers = CheckOptionsAndMakeSolvers(o);
  const std::vector<SweepPoint> points = EnumeratePoints(o.grid);
  const std::size_t P = points.size();
  SweepResult result;
  result.total = o.scenes.size() * P;
  const auto [begin, end] = ShardRange(result.total, o.shard);
  result.in_shard = end - begin;
  // A dry run checks every scene: it stands for all the shards about to be submitted.
  for (std::size_t s = o.dry_run ? 0 : begin / P; s < o.scenes.size() && (o.dry_run || s * P < end); ++s)
    CheckInputsExist(o.scenes[s]);
  const ShardInfo info = MakeShardInfo(o);
  if (o.dry_run) {
    if (fs::exists(o.out_dir)) CheckOutDir(o.out_dir, info);
    return result;
  }

  OutputSet set(o.out_dir, SweepOutputSetOptions(o));  // one writer at a time from here
  nlohmann::json report = NewReport("sweep");
  report["params"] = SweepParams(o);
  ClaimShardInfo(set, o.out_dir, info);
  const fs::path jsonl = set.out() / "results.jsonl";
  const auto results = OpenResults(set, report["warnings"]);
  PointRunner runner(o, report, set.dir() / ".al-eval-scratch");
  for (std::size_t j = begin; j < end; ++j) {
    const SweepPoint& p = points[j % P];
    SweepProgress progress{j - begin + 1, end - begin, nullptr, PointId(o.scenes[j / P].name, p)};
    if (results->done.count(progress.id)) {
      ++result.already_done;
      if (o.on_point) o.on_point(progress);
      continue;
    }
    const nlohmann::json record = runner.Run(j / P, p, progress.id, *solvers.at(p.solver));
    results->Append(record.dump() + "\n");
    ++result.ran;
    result.empty_graphs += record["status"] == "empty_graph";
    progress.record = &record;
    if (o.on_point) o.on_point(progress);
  }
  result.graphs_built = runner.graphs_built();
  FinishSweep(o, set, jsonl, result, report, total_timer, runner.load_seconds());
  return result;
}

void SweepOptions::Check() const {
  if (out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  if (scenes.empty()) throw Error("sweep: no scene (give --scene/--removed or --manifest)", ExitCode::kUsage);
  if (grid.size() == 0) throw Error("--grid: empty grid", ExitCode::kUsage);
  for (const SweepScene& scene : scenes) scene.options.Check();
  if (!solver_options.is_object()) throw Error("--solver-options: expected a JSON object {solver: {...}}", ExitCode::kUsage);
  for (const auto& [name, value] : solver_options.items())
    if (std::find(grid.solver.begin(), grid.solver.end(), name) == grid.solver.end())
      throw Error("--solver-options: '" + name + "' is not a solver of the grid", ExitCode::kUsage);
}

}  // namespace al
