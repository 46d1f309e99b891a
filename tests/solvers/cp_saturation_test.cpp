// Saturation of split remainders (al-refine extension of CUT_PURSUIT.md §7, docs/solvers.md "cp
// speed"): the rule must remove max-flow work (vertices offered to the split) without costing
// accuracy against the exact solver, keep the objective history monotone and stay thread-independent.
#include <gtest/gtest.h>

#include <numeric>

#include "al/core/error.hpp"
#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"
#include "al/fixtures/knn_problem.hpp"

namespace al {
namespace {

std::int64_t Total(const std::vector<std::int64_t>& v) { return std::accumulate(v.begin(), v.end(), std::int64_t{0}); }

cp::CutPursuitResult RunCp(const cp::SimplexProblem& sp, bool rule, int threads) {
  cp::CutPursuitOptions o;
  o.saturate_split_remainders = rule;
  o.init = cp::CutPursuitOptions::Init::kOneComponent;  // the rule acts in the spec's loop
  o.num_threads = threads;
  return cp::RunCutPursuit(sp, o);
}

TEST(CpSaturation, RemaindersSaturatedWithLessWorkAndSameAccuracy) {
  // The bench's setting (soft y, s = 0.1, w_e = 0.1) at 20k nodes: one large near-constant component.
  const RefineProblem pb = fixtures::MakeKnnProblem(20000, 10, 0.1, 0.1, false, 2024);
  const cp::SimplexProblem sp = ToSimplexProblem(pb);
  const double exact = MakeSolver("exact")->Solve(pb).objective;
  const cp::CutPursuitResult on = RunCp(sp, true, 1), off = RunCp(sp, false, 1);

  EXPECT_GT(on.remainder_saturations, 0);
  EXPECT_EQ(off.remainder_saturations, 0);
  EXPECT_LT(Total(on.split_nodes), Total(off.split_nodes));
  for (std::size_t i = 1; i < on.objective_history.size(); ++i)
    EXPECT_LE(on.objective_history[i], on.objective_history[i - 1]) << "iteration " << i;
  const double gap_on = (on.objective - exact) / exact, gap_off = (off.objective - exact) / exact;
  EXPECT_GE(gap_on, -1e-9);
  EXPECT_LE(gap_on, 1e-3);
  // Saturation only skips cuts that bought nothing at cp_dif_tol: the gap stays at the rule-free level.
  EXPECT_LE(gap_on, gap_off + 1e-4) << "on " << gap_on << " off " << gap_off;
  RecordProperty("gap_on", std::to_string(gap_on));
  RecordProperty("gap_off", std::to_string(gap_off));
  RecordProperty("split_nodes_on", std::to_string(Total(on.split_nodes)));
  RecordProperty("split_nodes_off", std::to_string(Total(off.split_nodes)));

  const cp::CutPursuitResult two = RunCp(sp, true, 2);
  EXPECT_EQ(on.comp_assign, two.comp_assign);
  EXPECT_EQ(on.rX, two.rX);  // bit-identical
  EXPECT_EQ(on.split_nodes, two.split_nodes);
  EXPECT_EQ(on.remainder_saturations, two.remainder_saturations);
}

TEST(CpSaturation, OptionParsedAsBoolean) {
  EXPECT_FALSE(ParseCutPursuitOptions({{"saturate_split_remainders", false}}).saturate_split_remainders);
  EXPECT_TRUE(ParseCutPursuitOptions(nlohmann::json::object()).saturate_split_remainders);
  try {
    ParseCutPursuitOptions({{"saturate_split_remainders", 1}});
    ADD_FAILURE() << "a number must be rejected";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kUsage);
  }
}

}  // namespace
}  // namespace al
