// The evaluator (SPEC §6): renders every view before removal, after the removal and after each
// refinement with the project's rasterizer (the "after" renders incrementally from the "before"
// cache), computes every metric of METRICS.md whose inputs exist, and writes report.json,
// metrics.csv, table.md / table.tex and per-view images. `al-refine eval` and `al-refine demo`
// are thin wrappers around RunEval.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/output_set.hpp"
#include "al/eval/feature_eval.hpp"
#include "al/io/camera.hpp"
#include "al/metrics/depth.hpp"
#include "al/metrics/residual.hpp"
#include "al/metrics/semantic.hpp"
#include "al/metrics/sim_sam.hpp"
#include "al/render/render.hpp"
#include "al/scene/scene.hpp"

namespace al::eval {

// One evaluated removal ("column" of the paper's tables): the removal method's own set, or a
// refinement of it.
struct EvalColumn {
  std::string name;             // file-name part and CSV prefix: "after", "refined", "bk", ...
  std::string label;            // table header, e.g. "fgs" or "fgs+cp"
  std::vector<bool> removed;    // N, true = removed
  // Optional segmentations of this column's renders (empty = none): GroundedSAM-style detector
  // masks (X.png or GroundedSAM X.json) and SAM segment lists (X.json or merged.json).
  std::string seg_dir, sam_dir;
};

// Where the per-view object mask comes from: a folder of PNGs joined by view name (> 0 = object),
// or ground-truth labels rendered per view (share Σ α·T of the object's Gaussians >= 0.5 in the
// full "before" composite, the rule `synth` uses for masks/<view>.png).
struct ObjectSource {
  std::string masks_dir;
  std::vector<std::int32_t> labels;  // N ids (used when masks_dir is empty)
  int object_id = 0;
};

struct EvalOptions {
  std::string out_dir;                 // required; one output set (al/core/output_set.hpp)
  std::vector<std::string> input_paths;  // refused when inside out_dir where the run would replace them
  std::string row_name = "scene";      // table row ("Scene-Object")
  RenderOptions render;                // background, SH degree, threads
  metrics::GhtOptions ght;             // published GHT parameters by default
  metrics::FloatDepthOptions float_depth;  // float mode (METRICS.md §5); alpha_hit also used for 8-bit depth
  // Which missing depths zero |Δ|, in both modes (float_depth.holes is overridden by it). kBefore =
  // the released evaluator: a pixel hit before and empty after counts as a depth change.
  metrics::DepthHoles depth_holes = metrics::DepthHoles::kBefore;
  metrics::DepthTrustOptions trust;    // per-view trust flags of acc_Δdepth (both modes)
  metrics::SemanticOptions semantic;
  metrics::SimSamOptions sim_sam;
  FeatureEvalOptions feature;          // feature metrics (IoU_drop_feat, acc_seg_feat, residual_feat)
  // residual_gt (with labels), residual_est (ideal = the first refinement) and residual_px (object
  // masks only): al/metrics/residual.hpp; alpha_hit follows float_depth.alpha_hit.
  metrics::ResidualOptions residual;
  std::string seg_before_dir, sam_before_dir;  // segmentations of the "before" renders
  std::string seg_class;               // GroundedSAM JSON class (empty = every instance)
  bool export_renders = false;         // renders/<column>/<view>.png for external segmenters
  bool write_images = true;            // images/<view>_*.png (tests may turn it off)
  bool write_depth_pngs = true;        // depth/<column>/{before,after}/<view>.png (8-bit pairs, METRICS.md §6)
  bool progress = true;                // progress bar on stderr
  void Check() const;  // out_dir given; render, GHT, float-depth, trust, semantic, sim_SAM and feature options
};

// Per view and column.
struct ColumnViewMetrics {
  metrics::DepthScore depth8, depth_float;
  double threshold8 = 0, threshold_float = 0;
  bool constant8 = false;
  metrics::DepthTrust trust8, trust_float;  // when acc_Δdepth of this view cannot be trusted
  std::size_t holes_before8 = 0, holes_before_float = 0;  // pixels without depth before
  std::size_t holes_after8 = 0, holes_after_float = 0;    // pixels with depth before and none after
  std::optional<double> collateral_psnr;  // empty when identical outside the object
  bool identical = false;
  std::optional<metrics::SemanticRecord> semantic;
  std::optional<metrics::SimSamResult> sim_sam;
  std::optional<FeatureViewMetrics> feature;  // when the feature metrics run
  // What is left of the object (al/metrics/residual.hpp): residual_gt needs labels, residual_est a
  // refinement (none for the column that is its ideal), residual_px runs always.
  std::optional<metrics::ViewResidual> residual_gt, residual_est, residual_px;
  std::vector<std::optional<double>> view_metrics;  // one per ViewMetrics() entry (al/eval/view_metric.hpp)
  std::size_t tiles_rendered = 0;
};

struct ViewRecord {
  std::string name;
  int width = 0, height = 0;
  std::size_t object_pixels = 0;
  bool evaluated = false;        // false: empty (or missing) object mask, excluded from the means
  bool object_mask_missing = false;
  std::vector<ColumnViewMetrics> columns;  // one per EvalSpec column when evaluated
};

struct ColumnSummary {
  metrics::DepthSummary depth8, depth_float;
  metrics::MeanStd collateral_psnr;
  std::size_t identical = 0;
  std::optional<metrics::SemanticSummary> semantic;
  std::optional<metrics::MeanStd> sim_sam;
  std::optional<metrics::FeatureSummary> feature;
  std::optional<metrics::ResidualSummary> residual_gt, residual_est, residual_px;
  std::size_t sim_sam_dropped = 0, sim_sam_missing = 0;
  std::size_t num_removed = 0;
  std::vector<metrics::MeanStd> view_metrics;  // one per ViewMetrics() entry, over the views defining it
};

struct SkippedMetric {
  std::string metric, column, reason;
};

struct EvalResult {
  std::vector<ViewRecord> views;
  std::vector<ColumnSummary> summaries;  // one per column
  std::vector<SkippedMetric> skipped;
  std::vector<std::string> warnings;
  // The residual that leads the tables, report.html and the printed summary: "residual_gt" with
  // labels, else "residual_est" with a refinement, else "residual_px" (al/eval/residuals.hpp).
  std::string headline;
  std::size_t evaluated = 0, skipped_empty_object = 0, missing_object_masks = 0;
  double seconds_object_masks = 0, seconds_render = 0, seconds_metrics = 0, seconds_io = 0, seconds_total = 0;
  double seconds_features = 0;           // feature channels and prototypes (once per scene)
  nlohmann::json feature;                // FeatureScorer::ToJson(): channels, prototypes (or why skipped)
  nlohmann::json report;                 // exactly what was written to report.json
  std::vector<std::string> outputs;      // files written, relative to out_dir

  // What `eval` prints: views evaluated, one line per removal (removed, acc_Δdepth 8-bit and float,
  // collateral depth, IoU_drop, IoU_drop_feat, residual_feat), the metrics the method's column skipped.
  std::string BriefReport(const std::string& row, std::size_t num_views) const;
};

// Runs the evaluation of `columns` (at least one; by convention the removal method's set first,
// then its refinements) on `cameras`. Validates every input first (al::Error, nothing written);
// outputs are staged and moved into out_dir only when the whole run succeeded. `report` (may be
// null) is the caller's report skeleton (params, inputs): RunEval adds counts, metrics, timings.
// The output-set options of a run (inputs, planned names): the CLI checks --out with them first.
OutputSetOptions EvalOutputSetOptions(const EvalOptions& o);
EvalResult RunEval(const Scene& scene, const std::vector<Camera>& cameras, const std::vector<EvalColumn>& columns,
                   const ObjectSource& object, const EvalOptions& options, const nlohmann::json* report = nullptr);

// ---- Tables in the paper's layout (rows Scene-Object; first the residuals that were computed,
// the headline one leading — residual_gt↓ with labels, residual_est↓ with a refinement,
// residual_px↓ —, then the paper's groups IoU_drop↑, acc_Δdepth↑, sim_SAM↓, then the feature
// metrics IoU_drop_feat↑ and residual_feat↓; one column per method; per row and group the best
// value bold, the second underlined).
struct TableRow {
  std::string name;
  std::vector<std::optional<double>> iou_drop, acc_delta_depth, sim_sam;  // one per method
  std::vector<std::optional<double>> iou_drop_feat, residual_feat;
  std::vector<int> acc_delta_depth_note;  // per method: footnote number (1-based into Table::notes) or 0
  std::vector<std::vector<std::optional<double>>> view_metrics;  // per ViewMetrics() entry, one per method
  std::vector<std::optional<double>> residual_gt, residual_est, residual_px;  // lead the table when computed
};
// Footnote of an acc_Δdepth cell: the views whose value cannot be trusted (metrics::DepthTrust).
struct DepthTrustNote {
  std::string method;
  std::size_t flagged = 0, views = 0;
  std::vector<std::pair<std::string, std::vector<std::string>>> views_by_flag;  // flag → views
  std::optional<double> trusted_mean;  // mean over the views without a flag (none: all flagged)
};
struct Table {
  std::string headline = "residual_px";  // EvalResult::headline: the residual group that leads
  std::vector<std::string> methods;
  std::vector<TableRow> rows;
  std::vector<DepthTrustNote> notes;
};
Table TableFromResult(const std::string& row_name, const std::vector<EvalColumn>& columns, const EvalResult& result);
// Ranks of the values of one group: 1 = best (ties share it), 2 = second best, 0 otherwise/missing.
std::vector<int> RankValues(const std::vector<std::optional<double>>& values, bool higher_is_better);
std::string TableMarkdown(const Table& table);
std::string TableLatex(const Table& table);

// metrics.csv: one row per view, columns per method (prefix = column name).
std::string MetricsCsv(const std::vector<EvalColumn>& columns, const EvalResult& result);

}  // namespace al::eval
