// cp's level-set cold start and level-cut reduced solver (docs/solvers.md "cp speed (3)"): every
// combination of start and reduced solver reaches the exact optimum within cp's tolerance, on
// graphs with several components, a coarse start interval still converges, weights over twelve
// decades and degenerate observations stay sane, and the new options are validated.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "al/core/error.hpp"
#include "al/fixtures/knn_problem.hpp"
#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"

namespace al {
namespace {

using Options = cp::CutPursuitOptions;

double RelGap(double f, double exact) { return (f - exact) / std::max(1.0, std::fabs(exact)); }

cp::CutPursuitResult SolveCp(const RefineProblem& pb, Options::Init init, Options::Reduced reduced,
                         double init_epsilon = 0.0) {
  Options o;
  o.init = init;
  o.reduced_solver = reduced;
  o.init_epsilon = init_epsilon;
  return cp::RunCutPursuit(ToSimplexProblem(pb), o);
}

TEST(CpLevelSetStart, EveryStartAndReducedSolverReachesExact) {
  for (std::uint64_t seed : {3u, 17u, 41u}) {
    const RefineProblem pb = fixtures::MakeKnnProblem(3000, 8, 0.1, 0.1, seed % 2 == 1, seed);
    const double exact = MakeSolver("exact")->Solve(pb).objective;
    for (auto init : {Options::Init::kLevelSets, Options::Init::kOneComponent}) {
      for (auto reduced : {Options::Reduced::kLevelSets, Options::Reduced::kPfdr}) {
        const cp::CutPursuitResult r = SolveCp(pb, init, reduced);
        const std::string what = "seed " + std::to_string(seed) + " init " +
                                 std::to_string(int(init)) + " reduced " + std::to_string(int(reduced));
        EXPECT_GE(RelGap(r.objective, exact), -1e-9) << what;  // never below the optimum
        EXPECT_LE(RelGap(r.objective, exact), 1e-3) << what;
        EXPECT_NEAR(r.objective, cp::SimplexObjective(ToSimplexProblem(pb), r.comp_assign, r.rX),
                    1e-9 * std::fabs(r.objective)) << what;
      }
    }
  }
}

TEST(CpLevelSetStart, CoarseStartIntervalsStillConverge) {
  const RefineProblem pb = fixtures::MakeKnnProblem(2000, 10, 0.1, 0.1, false, 5);
  const double exact = MakeSolver("exact")->Solve(pb).objective;
  for (double eps : {1e-6, 0.05, 0.5, 1.0}) {
    const cp::CutPursuitResult r = SolveCp(pb, Options::Init::kLevelSets, Options::Reduced::kLevelSets, eps);
    EXPECT_LE(RelGap(r.objective, exact), 1e-3) << "init_epsilon " << eps;
  }
}

TEST(CpLevelSetStart, ExtremeWeightsAndDegenerateObservations) {
  for (double scale : {1e-6, 1.0, 1e6}) {
    RefineProblem pb = fixtures::MakeKnnProblem(1500, 6, 0.1, 0.1, true, 8);
    for (double& w : pb.edge_weights) w *= scale;
    for (std::size_t i = 0; i < pb.y_remove.size(); i += 7) pb.y_remove[i] = i % 2 ? 0.0 : 1.0;
    const double exact = MakeSolver("exact")->Solve(pb).objective;
    const cp::CutPursuitResult r = SolveCp(pb, Options::Init::kLevelSets, Options::Reduced::kLevelSets);
    ASSERT_TRUE(std::isfinite(r.objective)) << scale;
    for (double v : r.rX) ASSERT_TRUE(std::isfinite(v) && v >= 0.0 && v <= 1.0) << scale;
    EXPECT_LE(RelGap(r.objective, exact), 1e-3) << "weights x" << scale;
  }
}

TEST(CpLevelSetStart, AllRemovedAndNoneRemovedAreOnePlateau) {
  for (double y : {0.0, 1.0}) {
    RefineProblem pb = fixtures::MakeKnnProblem(500, 6, 0.1, 0.1, false, 2);
    pb.y_remove.assign(pb.y_remove.size(), y);
    const cp::CutPursuitResult r = SolveCp(pb, Options::Init::kLevelSets, Options::Reduced::kLevelSets);
    for (std::size_t v = 0; v < pb.y_remove.size(); ++v)
      ASSERT_NEAR(r.Value(v, 1, 2), r.Value(0, 1, 2), 1e-12) << "y " << y << " node " << v;
  }
}

TEST(CpLevelSetStart, OptionsValidated) {
  EXPECT_THROW(MakeSolver("cp", {{"init", "halfway"}}), Error);
  EXPECT_THROW(MakeSolver("cp", {{"reduced_solver", "newton"}}), Error);
  EXPECT_THROW(MakeSolver("cp", {{"init_epsilon", -0.1}}), Error);
  EXPECT_THROW(MakeSolver("cp", {{"init_epsilon", 2.0}}), Error);
  EXPECT_NO_THROW(MakeSolver("cp", {{"init", "one_component"}, {"reduced_solver", "pfdr"}}));
}

}  // namespace
}  // namespace al
