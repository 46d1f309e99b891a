// The evaluator's sections of report.json (SPEC §1 keys): the effective options under "params"
// and one summary object per evaluated column under "metrics.columns".
#pragma once
#include <nlohmann/json.hpp>

#include "al/eval/eval.hpp"

namespace al::eval {

// Adds every effective evaluation option to report["params"] (keeps what the caller put there).
void AddEvalParams(nlohmann::json& report, const std::vector<EvalColumn>& columns, const ObjectSource& object,
                   const EvalOptions& options);

// {name, label, num_removed, depth (8-bit), depth_float, collateral_psnr, [semantic], [feature], [sim_sam]}.
nlohmann::json ColumnSummaryJson(const EvalColumn& column, const ColumnSummary& summary, const EvalOptions& options);

}  // namespace al::eval
