// Parameter sweeps (`al-refine sweep`, `al-refine merge`): a grid of refine settings over one scene
// or a manifest of scenes, one JSON line per point in results.jsonl, results.csv and gnuplot charts.
// The work a parameter does not change is not repeated: inputs are loaded once per scene, the graph
// is built once per (k, δ, hops, radius_scale) and λ only rescales its edge weights (λ is a pure
// factor of every weight, SPEC §4.6), so solver, λ and threshold settings share one graph.
// Runs are resumable (points already in results.jsonl are skipped) and can be split into
// deterministic shards whose outputs `merge` combines.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/input_file.hpp"

#include "al/eval/eval.hpp"
#include "al/io/camera.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"

namespace al {

// The axes of a grid; an axis the grid text does not name has the single value of the base options.
struct SweepGrid {
  std::vector<int> k;
  std::vector<double> delta;
  std::vector<int> hops;
  std::vector<double> radius_scale;
  std::vector<std::optional<double>> lambda;  // unset = auto (the scene's preset, per solver)
  std::vector<std::string> solver;     // resolved names (al/solver.hpp)
  std::vector<std::string> threshold;  // decision rules, canonical ("0.5", "percentile:95")
  std::vector<double> segment_share;   // the decision's min_segment_share (0 = plain rule)
  std::size_t size() const;
};

// "k=4,6,10;delta=0.8,1.0;lambda=0.5,1,2;solver=bk,cp" (keys k, delta, hops, radius_scale,
// lambda, solver, threshold, segment_share; values deduplicated in the given order). Each value is
// parsed and range-checked by its options table (GraphOptions, DecisionOptions), like the CLI flag
// of the same name ("lambda=auto" as --lambda auto). Throws al::Error (usage) on unknown keys,
// repeated keys, empty or invalid values.
SweepGrid ParseSweepGrid(const std::string& text, const RefineOptions& base);

// One grid point (the axes of SweepGrid).
struct SweepPoint {
  int k = 10;
  double delta = 0.8;
  int hops = 1;
  double radius_scale = 1.0;
  std::optional<double> lambda;  // unset = auto: MethodPreset::LambdaFor(solver) of each scene
  std::string solver;
  std::string threshold = "0.5";
  double segment_share = 2.0 / 3.0;
};

// Every point, graph axes outermost (k, δ, hops, radius_scale), then λ, solver, threshold,
// segment_share, so points sharing a graph are consecutive.
std::vector<SweepPoint> EnumeratePoints(const SweepGrid& grid);

// True when a and b need the same graph (they differ at most in λ, solver, threshold).
bool SameGraph(const SweepPoint& a, const SweepPoint& b);

// The key results.jsonl is resumed and merged on: "scene|k=4|delta=0.8|hops=1|radius_scale=1|
// lambda=0.5|solver=bk|threshold=0.5|segment_share=0.6666666666666666" (numbers in shortest
// round-trip form).
std::string PointId(const std::string& scene, const SweepPoint& point);

// A scene of the sweep: its refine options (method, features, removed set, labels, ...) and,
// for evaluation, cameras and object masks.
struct SweepScene {
  std::string name;
  RefineOptions options;
  std::string cameras, object_masks;   // evaluator metrics per point when cameras are given
};

// A manifest: a JSON list of {name, scene, removed, removed_is?, method?, features?, labels?,
// object_id?, cameras?, object_masks?}. Relative paths are relative to the manifest's folder;
// unnamed fields take the base options. Names must be unique and non-empty.
std::vector<SweepScene> ReadSweepManifest(const std::string& path, const RefineOptions& base);
// The same on the manifest's text (fuzzing); relative paths resolve against path's folder.
std::vector<SweepScene> ParseSweepManifest(const std::string& text, const std::string& path, const RefineOptions& base);

// "--shard i/n": the i-th (0-based, 0 <= i < n) of n slices.
struct Shard {
  std::size_t index = 0, count = 1;
  std::string ToString() const;  // "i/n"
};
Shard ParseShard(const std::string& text);

// The jobs (scene × point, scenes outermost) of shard `shard` out of `total`: the contiguous block
// [floor(i·total/n), floor((i+1)·total/n)). Contiguous blocks keep the points of one graph in one
// shard (each shard rebuilds at most one graph it shares with a neighbour) and sizes differ by ≤ 1.
std::pair<std::size_t, std::size_t> ShardRange(std::size_t total, const Shard& shard);

// ---- Evaluator metrics of one refined set (al/eval/eval.hpp), for sweeps with cameras and `--auto`.

struct PointEvalSetup {
  std::vector<Camera> cameras;
  eval::ObjectSource object;   // object masks folder, else the ground-truth labels' target
  std::string work_dir;        // RunEval's output folder (scratch, removed after each evaluation)
};

// Cameras (all views, or the comma-separated `views`) and the object: the masks folder when given,
// else the ground truth of inputs. Throws al::Error when there is neither.
PointEvalSetup MakePointEvalSetup(const std::string& cameras, const std::string& views,
                                  const std::string& object_masks, const RefineInputs& inputs,
                                  const std::string& work_dir);

// Renders before / after `removed` (no images written) and returns the means over the evaluated
// views: {acc_delta_depth (8-bit, published), acc_delta_depth_float, collateral_depth (fraction of
// non-object pixels whose depth changed), collateral_psnr, views_evaluated, views_skipped}.
// Also: views_flagged_float and views[] = {view, acc_delta_depth_float, collateral_depth,
// flags_float} (the float-mode trust flags of docs/metrics.md, per evaluated view).
nlohmann::json EvaluatePoint(const Scene& scene, const PointEvalSetup& setup, const std::vector<bool>& removed);

// The "eval" criterion of `refine --auto` on views no candidate may game: acc_delta_depth_float
// averaged over the views that no evaluation flags (the same views for every candidate, so a
// candidate cannot win by getting a bad view flagged), minus collateral_depth over all evaluated
// views (damage counts everywhere). Writes score_views and acc_delta_depth_float_trusted into each
// evaluation. nullopt when every view is flagged somewhere: the criterion cannot be used.
std::optional<std::vector<double>> TrustedViewScores(const std::vector<nlohmann::json*>& evals);

struct SweepProgress {
  std::size_t position = 0, count = 0;  // 1-based position among this run's points
  const nlohmann::json* record = nullptr;  // null when skipped (already in results.jsonl)
  std::string id;
};

struct SweepOptions {
  std::vector<SweepScene> scenes;      // at least one
  SweepGrid grid;
  Shard shard;
  std::string out_dir;                 // required
  nlohmann::json solver_options = nlohmann::json::object();  // {solver name: options}
  std::string eval_views = "all";      // views evaluated when a scene has cameras
  std::function<void(const SweepProgress&)> on_point;        // progress (one call per point)
  bool dry_run = false;                // check options, every scene's inputs and out_dir; run and write nothing
  void Check() const;  // out_dir, scenes and grid given; solver options only for the grid's solvers; every scene's options
};

struct SweepResult {
  std::size_t total = 0;        // scenes × grid points
  std::size_t in_shard = 0;     // this shard's share
  std::size_t already_done = 0; // skipped: in results.jsonl from an earlier run
  std::size_t ran = 0, empty_graphs = 0;
  std::size_t graphs_built = 0; // graph builds (≤ distinct graph settings in the shard)
  nlohmann::json report;        // exactly what was written to report.json
};

// Runs the shard's points not yet in out_dir/results.jsonl, appending one flushed line per point
// (a killed run loses at most the point it was computing), then rewrites results.csv, the charts
// and report.json from every record in results.jsonl. Validates options and inputs (al::Error)
// before appending anything, writes out_dir/shard.json (ShardInfo) before the first point and
// refuses an out_dir whose shard.json is another sweep's or shard's.
SweepResult RunSweep(const SweepOptions& options);

// ---- results.jsonl and the derived outputs (shared by sweep and merge)

struct JsonlContents {
  std::vector<nlohmann::json> records;
  bool truncated_tail = false;   // the last line had no newline and did not parse (killed writer)
  std::uintmax_t good_bytes = 0; // bytes up to and including the last complete line
};

// Reads results.jsonl (missing file: no records). A last line without its newline that does not
// parse is the remnant of a killed run and is reported, not fatal; any other bad line is an
// al::Error naming the line.
JsonlContents ReadResultsJsonl(const std::string& path, Links links = Links::kFollow);
// The same on text already read (`path` names it in errors).
JsonlContents ParseResultsJsonl(const std::string& text, const std::string& path);

// Canonical order of records (scene name, then the numeric parameters, then solver, threshold):
// the order of merged outputs and of results.csv.
void SortRecords(std::vector<nlohmann::json>& records);

// A record without its execution details ("seconds", "run"): what must be equal between a
// sharded and an unsharded run.
nlohmann::json RecordWithoutTimings(const nlohmann::json& record);

// results.csv: one row per record, fixed columns (empty cells where a value is absent).
std::string ResultsCsv(const std::vector<nlohmann::json>& records);

// Writes results.csv, the charts (pareto.png: run time against error; heatmap_f1_<solver>.png:
// F1 over k × δ, one panel per λ; charts = false: none) and report.html for the records into dir.
// Returns {"csv", "charts": [...], "skipped_charts": [{name, reason}], "html"} for the report.
nlohmann::json WriteSweepSummaries(const std::string& dir, const std::vector<nlohmann::json>& records,
                                   bool charts = true);

// One setting (the grid parameters without the scene) averaged over the scenes that have
// ground-truth F1: mean run time (graph build + solve) and mean error 1 − F1.
struct ParetoPoint {
  std::string solver, label;    // label: "k=10 d=0.8 l=1" (h= when hops != 1)
  nlohmann::json params;        // the setting's parameters (of one of its records)
  double seconds = 0, error = 0;
  int scenes = 0;
  bool on_front = false;        // no other setting is both at least as fast and more accurate
};
std::vector<ParetoPoint> ParetoPoints(const std::vector<nlohmann::json>& records);

// report.html of sweep / merge (docs/sweep.md): the charts WriteSweepSummaries drew (`summaries`
// = its result), the Pareto table (front first), the best settings per scene and the skipped charts.
// One self-contained page (al/core/html.hpp) beside results.csv.
std::string SweepReportHtml(const std::vector<nlohmann::json>& records, const nlohmann::json& summaries);

// ---- shard.json: which sweep an output folder is a slice of

// Written by RunSweep into --out before its first point, so that even a killed shard says which
// sweep it belongs to. merge refuses folders whose sweeps differ; sweep refuses to resume a folder
// of another sweep (except an unsharded run whose grid grew).
struct ShardInfo {
  Shard shard;
  std::size_t points_total = 0;          // scenes × grid points
  std::size_t first = 0, end = 0;        // this shard's jobs [first, end) (ShardRange)
  nlohmann::json grid;                   // the axes (GridToJson)
  nlohmann::json scenes;                 // per scene: name, fixed refine flags, inputs (absolute
                                         // path, bytes, sha256 for files up to 64 MiB)
  nlohmann::json fixed;                  // sweep-wide flags: solver_options, eval_views
  nlohmann::json binary;                 // {version, sha256 of the executable}
  nlohmann::json ToJson() const;
  std::size_t points_in_shard() const { return end - first; }
};

nlohmann::json GridToJson(const SweepGrid& grid);
SweepGrid GridFromJson(const nlohmann::json& grid);  // throws al::Error (bad input)

// The identity of options' sweep and shard (hashes the scenes' inputs of up to 64 MiB).
ShardInfo MakeShardInfo(const SweepOptions& options);

// DIR/shard.json. Throws al::Error (bad input) naming the folder when it is absent or malformed.
ShardInfo ReadShardInfo(const std::string& dir, Links links = Links::kFollow);
void WriteShardInfo(const std::string& dir, const ShardInfo& info);

// What differs between the sweeps of a and b, one entry per group in the order shard count, grid,
// scenes, fixed flags, binary, each with its first differing value: "grid (k: [6,10] vs [6,14])".
// Empty when a and b are slices of one sweep (their shard indices may differ).
std::vector<std::string> SweepDifferences(const ShardInfo& a, const ShardInfo& b);

// The point ids of jobs [first, end) of info's sweep (scenes outermost, then EnumeratePoints).
std::vector<std::string> SweepPointIds(const ShardInfo& info, std::size_t first, std::size_t end);

// ---- merge

struct MergeOptions {
  std::vector<std::string> shard_dirs;   // sweep outputs, each with shard.json and results.jsonl
  std::string out_dir;                   // required unless check_only
  bool allow_partial = false;            // merge an incomplete set (report: complete false)
  bool check_only = false;               // only report the set's status; write nothing
  void Check() const;                    // al::Error (usage)
};

// One shard folder given to merge.
struct MergedShard {
  std::string dir;
  Shard shard;
  std::size_t points_in_shard = 0;
  std::size_t points_found = 0;          // this folder's records that are points of its slice
  std::size_t records = 0;
  bool truncated_tail = false;           // a killed writer's half line at the end
  nlohmann::json ToJson() const;
};

struct MergeResult {
  bool complete = false;                 // every shard present and every point found
  bool written = false;                  // out_dir written (complete, or allow_partial)
  int exit_code = 0;                     // 0, or 2 for an incomplete set without allow_partial
  std::string message;                   // why the exit code is not 0
  std::size_t shard_count = 0, points_total = 0, points_found = 0;
  std::size_t records = 0, duplicates = 0, conflicts = 0;
  std::size_t foreign_records = 0;       // ids that are not points of the sweep (left out)
  std::vector<MergedShard> shards;       // in the order given
  std::vector<std::size_t> missing_shards;     // indices no folder was given for
  std::vector<std::size_t> incomplete_shards;  // indices with a point not found (missing ones too)
  std::vector<std::string> warnings;
  nlohmann::json report;                 // exactly what was written to report.json (when written)
  std::string BriefReport() const;       // status lines, incl. "incomplete shards: 1 4" when any
};

// Combines the results.jsonl of shard folders into out_dir. First checks that every folder is a
// shard of one sweep (shard.json: shard count, grid, scenes, fixed flags, binary; al::Error exit 2
// naming what differs), then which shards and points are missing. An incomplete set is written
// only with allow_partial (report.json: complete false); otherwise nothing is written and
// exit_code is 2. Records are deduplicated by id (first occurrence wins; a duplicate whose
// non-timing content differs is a conflict and warned about), in canonical order, with
// results.csv, charts and report.json.
MergeResult MergeSweeps(const MergeOptions& options);

}  // namespace al
