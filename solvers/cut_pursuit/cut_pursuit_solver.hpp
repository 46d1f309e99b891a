// The "cp" solver: cut pursuit (CUT_PURSUIT.md) on the two-label RefineProblem.
#pragma once
#include <memory>

#include <nlohmann/json.hpp>

#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"

namespace al {

// Options (JSON keys = CutPursuitOptions fields, defaults there): cp_dif_tol, cp_it_max, K,
// split_iter_num, split_damp_ratio, split_values_init_num, split_values_iter_num, pfdr_rho,
// pfdr_cond_min, pfdr_dif_rcd, pfdr_dif_tol, pfdr_it_max, num_threads,
// emulate_upstream_projection_bug. Unknown keys or wrong types: al::Error(kUsage).
cp::CutPursuitOptions ParseCutPursuitOptions(const nlohmann::json& options);

// Two-label simplex problem of a RefineProblem: y_v = (y_remove, 1 - y_remove), unit metric.
// The view reads the problem's arrays in place (y is built in `y`, which must outlive the view);
// ToSimplexProblem copies them.
cp::SimplexProblemView SimplexViewOf(const RefineProblem& problem, std::vector<double>& y);
cp::SimplexProblem ToSimplexProblem(const RefineProblem& problem);

std::unique_ptr<Solver> MakeCutPursuitSolver(const nlohmann::json& options);

}  // namespace al
