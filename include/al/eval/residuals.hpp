// The evaluator's residuals (docs/eval.md, "Residuals"; the formulas: al/metrics/residual.hpp):
//  * residual_gt  — ideal = the render without the labels' target (needs --labels);
//  * residual_est — ideal = the render of the first refinement (column 1): the refinement is the
//    detector, no labels, masks or external segmenter; not computed for column 1 itself;
//  * residual_px  — the object mask's pixels whose colour and depth did not change (masks only).
// One of them is the headline: residual_gt when labels are given, else residual_est when a
// refinement is given, else residual_px.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/eval/eval.hpp"
#include "al/metrics/residual.hpp"
#include "al/render/render.hpp"

namespace al::eval {

// "residual_gt", "residual_est" or "residual_px".
std::string HeadlineResidual(bool has_labels, std::size_t num_columns);

// The renders of one view and column a residual reads. ideal_gt / ideal_est are null when that
// residual is not computed for this column.
struct ResidualInput {
  const RenderOutput& before;
  const RenderOutput& after;
  const RenderOutput* ideal_gt = nullptr;
  const RenderOutput* ideal_est = nullptr;
  const metrics::Mask& object;
};

// Scores the residuals of one view and column into m; `share` receives the headline residual per
// pixel (-1 outside its footprint; residual_px: 1 on the mask pixels still there, 0 on the others).
void ScoreResiduals(const ResidualInput& in, const metrics::ResidualOptions& options, const std::string& headline,
                    ColumnViewMetrics& m, std::vector<float>& share);

// The three summaries of column c over the evaluated views (each only when some view has it).
void SummarizeResiduals(const std::vector<ViewRecord>& views, std::size_t c, ColumnSummary& s);

// report.json's residual_gt / residual_est / residual_px of a column: {mean (null when no view was
// scored), std, views, views_not_scored, per_view: [{view, residual, pixels}]}.
void AddResidualJson(const std::vector<ViewRecord>& views, std::size_t c, const ColumnSummary& s, nlohmann::json& out);

// What each residual is and where it was skipped, for report.json's metrics.residuals.
nlohmann::json ResidualsInfoJson(const std::string& headline, const std::vector<EvalColumn>& columns,
                                 bool has_labels, const metrics::ResidualOptions& options);

}  // namespace al::eval
