// Flat records of an evaluation, one object per row with scalar values only: what a data frame
// takes directly (pandas.DataFrame(records)) and what report.html tabulates. They are derived from
// report.json and metrics.csv, the evaluator's own outputs, so a metric added there appears here
// without a change.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/eval/eval.hpp"

namespace al::eval {

// One record per evaluated column (report["metrics"]["columns"]): every scalar leaf under its
// dotted path ("depth.mean_acc_delta_depth", "gt.f1", "feature.mean_residual"); arrays are left out.
nlohmann::json ColumnRecords(const nlohmann::json& report);

// One record per view: the columns of metrics.csv (MetricsCsv) with numbers as numbers, "1"/"0"
// flags as numbers and empty cells as null.
nlohmann::json ViewRecords(const std::vector<EvalColumn>& columns, const EvalResult& result);

// The scalar leaves of a JSON value under dotted paths (prefix + "." + key); arrays are skipped.
void FlattenScalars(const nlohmann::json& value, const std::string& prefix, nlohmann::json& out);

}  // namespace al::eval
