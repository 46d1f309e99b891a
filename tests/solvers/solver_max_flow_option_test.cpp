// The "max_flow" option of cp and exact (solvers/max_flow/max_flow.hpp algorithms): every algorithm returns
// the same minimum cut, so cut pursuit must take the same partitions (bit-identical values and
// objective history) and the exact solver the same solution whichever runs the cuts ("pseudoflow"
// sends every cut through the pseudoflow phase, "bk" none). Bad values are usage errors.
#include <gtest/gtest.h>

#include <string>

#include "al/core/error.hpp"
#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"
#include "al/fixtures/knn_problem.hpp"

namespace al {
namespace {

const char* const kAlgorithms[] = {"hybrid", "pseudoflow", "bk"};
const MaxFlow::Algorithm kAlgorithmValues[] = {MaxFlow::Algorithm::kHybrid,
                                               MaxFlow::Algorithm::kPseudoflowThenBk,
                                               MaxFlow::Algorithm::kBoykovKolmogorov};

TEST(MaxFlowOption, CutPursuitTakesTheSameSplitsWithEveryAlgorithm) {
  for (bool one_hot : {false, true}) {
    const RefineProblem pb = fixtures::MakeKnnProblem(20000, 10, 0.1, 0.1, one_hot, 2024);
    const cp::SimplexProblem sp = ToSimplexProblem(pb);
    cp::CutPursuitResult results[3];
    for (int a = 0; a < 3; ++a) {
      cp::CutPursuitOptions o;
      o.max_flow = kAlgorithmValues[a];
      results[a] = cp::RunCutPursuit(sp, o);
    }
    for (int a = 1; a < 3; ++a) {
      SCOPED_TRACE(std::string(kAlgorithms[a]) + (one_hot ? ", one-hot" : ", soft"));
      EXPECT_EQ(results[a].comp_assign, results[0].comp_assign);
      EXPECT_EQ(results[a].rX, results[0].rX);
      EXPECT_EQ(results[a].objective_history, results[0].objective_history);
    }
    EXPECT_GT(results[0].num_components, 10);
  }
}

TEST(MaxFlowOption, ExactSolverGivesTheSameSolutionWithEveryAlgorithm) {
  const RefineProblem pb = fixtures::MakeKnnProblem(10000, 10, 0.1, 0.1, false, 7);
  const SolverResult ref = MakeSolver("exact", {{"max_flow", "bk"}})->Solve(pb);
  for (const char* name : {"hybrid", "pseudoflow"}) {
    const SolverResult r = MakeSolver("exact", {{"max_flow", name}})->Solve(pb);
    EXPECT_NEAR(r.objective, ref.objective, 1e-11 * ref.objective) << name;
    ASSERT_EQ(r.p.size(), ref.p.size());
    double worst = 0.0;
    for (std::size_t v = 0; v < r.p.size(); ++v) worst = std::max(worst, std::abs(r.p[v] - ref.p[v]));
    EXPECT_LE(worst, 1e-9) << name;
  }
}

TEST(MaxFlowOption, RejectsUnknownValues) {
  for (const char* solver : {"cp", "exact"}) {
    EXPECT_THROW(MakeSolver(solver, {{"max_flow", "dinic"}}), Error) << solver;
    EXPECT_THROW(MakeSolver(solver, {{"max_flow", 1}}), Error) << solver;
    try {
      MakeSolver(solver, {{"max_flow", "push-relabel"}});
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::kUsage) << solver;
    }
  }
}

}  // namespace
}  // namespace al
