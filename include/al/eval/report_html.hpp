// report.html of `eval` (docs/eval.md): one self-contained page (al/core/html.hpp) with the summary
// table (the paper's metrics, collateral damage, ground truth), feature metrics and any other
// metric report.json holds, warnings and skipped metrics, and per view the before / after /
// refined renders side by side with the residual overlays and the added / restored Gaussians, a
// wipe slider between any two of them, views sorted by residual (worst first) and views that an
// evaluator trust flag marks outlined. Built from report.json and metrics.csv records only, so
// metrics other evaluator parts add to them show up without a change here.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace al::eval {

// view_records: ViewRecords() (records.hpp). view_images: per evaluated view
// {"view": name, "images": [{"key", "label", "src"}]} with src relative to the page, in display
// order; keys "before", "<column>", "<column>_residual", "<column>_added", "<column>_depthdiff".
std::string EvalReportHtml(const nlohmann::json& report, const nlohmann::json& view_records,
                           const nlohmann::json& view_images);

// Views an evaluator flag marks: every "flagged" array in report.json's column summaries
// (entries {"view"|"image": name, "flags": [...]} or a plain name), labelled "<column label>,
// <summary>"; when report.json has none, every non-empty text cell of a view record whose column
// name holds "flag". view → "label: flag" texts.
std::map<std::string, std::vector<std::string>> FlaggedViews(const nlohmann::json& report,
                                                             const nlohmann::json& view_records);

}  // namespace al::eval
