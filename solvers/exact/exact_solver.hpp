// The "exact" solver (CUT_PURSUIT.md §11): the exact relaxed optimum for two labels by level-set
// minimum cuts. For every group U of vertices known to lie in [lo, hi] it cuts at a pivot t: the
// upper side lies in [t, hi], the lower in [lo, t] (monotone level sets). Two pivot rules:
//  - "plateau" (default): t = the best constant value of U given its boundary; if the cut at t
//    does not split U (min cut energy >= 0) U is an optimal plateau at t, exact up to rounding;
//  - "bisection": t = (lo + hi) / 2 until hi - lo <= epsilon (the spec's reference procedure).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/solver.hpp"
#include "al/core/option_table.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al {

struct ExactOptions {
  double epsilon = 1e-10;          // interval width at which a group is final
  std::string pivot = "plateau";   // "plateau" or "bisection"
  // Max-flow of the level cuts (JSON "hybrid", "pseudoflow" or "bk"; all give the same cuts).
  MaxFlow::Algorithm max_flow = MaxFlow::Algorithm::kHybrid;
  int num_threads = 0;  // pieces of one depth cut in parallel; 0 = OpenMP default; never changes p

  // The JSON keys of --solver-options, their ranges and help (exact_solver.cpp).
  static const OptionTable<ExactOptions>& Table();
  void Check() const { Table().Check(*this); }
};

struct ExactStats {
  long long max_flows = 0;
  long long plateaus = 0;  // final pieces (connected, constant)
  int max_depth = 0;
};

// Options from JSON (keys epsilon, pivot, max_flow); unknown keys -> al::Error(kUsage).
ExactOptions ParseExactOptions(const nlohmann::json& options);

// p minimising F for the two-label problem (s == 0 linear, s == 1 quadratic, else smoothed KL).
std::vector<double> SolveExactTwoLabel(const RefineProblem& problem, const ExactOptions& options,
                                       ExactStats* stats = nullptr);


std::unique_ptr<Solver> MakeExactSolver(const nlohmann::json& options);

}  // namespace al
