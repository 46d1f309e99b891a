// Accuracy of cut pursuit against the exact level-set solver on generated kNN problems, the 2-node
// closed form, and bk's integral optimum bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"
#include "al/fixtures/knn_problem.hpp"
#include "solvers/exact/exact_solver.hpp"

namespace al {
namespace {

// Brute-force minimiser of F for two nodes joined by one edge: nested ternary searches (F convex).
std::pair<double, double> TwoNodeBruteForce(const RefineProblem& pb) {
  auto F = [&](double a, double b) { return Objective(pb, {a, b}); };
  auto inner = [&](double a) {
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 100; ++i) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (F(a, m1) < F(a, m2)) hi = m2; else lo = m1;
    }
    return 0.5 * (lo + hi);
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 100; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (F(m1, inner(m1)) < F(m2, inner(m2))) hi = m2; else lo = m1;
  }
  const double a = 0.5 * (lo + hi);
  return {a, inner(a)};
}

RefineProblem TwoNodes(double y0, double y1, double w, double s) {
  RefineProblem pb;
  pb.first_edge = {0, 1, 1};
  pb.adj_vertices = {1};
  pb.edge_weights = {w};
  pb.y_remove = {y0, y1};
  pb.node_weights = {1.0, 1.0};
  pb.node_ids = {0, 1};
  pb.kl_smoothing = s;
  return pb;
}

TEST(CpAccuracy, TwoNodeClosedForm) {
  for (double s : {0.1, 0.5, 1.0})
    for (double w : {0.01, 0.2, 5.0}) {
      const RefineProblem pb = TwoNodes(1.0, 0.0, w, s);
      const auto [a, b] = TwoNodeBruteForce(pb);
      const SolverResult ex = MakeSolver("exact")->Solve(pb);
      const SolverResult cpr = MakeSolver("cp", {{"cp_dif_tol", 1e-6}})->Solve(pb);
      EXPECT_NEAR(ex.p[0], a, 1e-6) << "s=" << s << " w=" << w;
      EXPECT_NEAR(ex.p[1], b, 1e-6) << "s=" << s << " w=" << w;
      EXPECT_NEAR(cpr.p[0], a, 1e-4) << "s=" << s << " w=" << w;
      EXPECT_NEAR(cpr.p[1], b, 1e-4) << "s=" << s << " w=" << w;
      const double fb = Objective(pb, {a, b});
      EXPECT_LE(ex.objective, fb + 1e-9);
      EXPECT_LE(cpr.objective, fb * (1 + 1e-6) + 1e-9);
    }
}

TEST(CpAccuracy, ObjectiveMatchesContract) {
  const RefineProblem pb = fixtures::MakeKnnProblem(500, 6, 0.1, 0.1, false, 3);
  const SolverResult r = MakeSolver("cp")->Solve(pb);
  EXPECT_NEAR(r.objective, Objective(pb, r.p), 1e-10 * r.objective);
  const SolverResult e = MakeSolver("exact")->Solve(pb);
  EXPECT_NEAR(e.objective, Objective(pb, e.p), 1e-10 * e.objective);
}

struct Case {
  int n;
  double s;
  bool one_hot;
};

class CpVsExact : public ::testing::TestWithParam<Case> {};

TEST_P(CpVsExact, WithinOneThousandth) {
  const Case c = GetParam();
  const RefineProblem pb = fixtures::MakeKnnProblem(c.n, 10, 0.1, c.s, c.one_hot, 1234 + c.n);
  const SolverResult ex = MakeSolver("exact")->Solve(pb);
  const SolverResult cpr = MakeSolver("cp")->Solve(pb);
  const double gap = (cpr.objective - ex.objective) / ex.objective;
  EXPECT_GE(gap, -1e-9) << "exact must be optimal";
  EXPECT_LE(gap, 1e-3) << "n=" << c.n << " s=" << c.s << " one_hot=" << c.one_hot
                       << " cp=" << cpr.objective << " exact=" << ex.objective;
  RecordProperty("gap", std::to_string(gap));
}

INSTANTIATE_TEST_SUITE_P(Knn, CpVsExact,
                         ::testing::Values(Case{2000, 0.1, false}, Case{2000, 0.5, true}, Case{10000, 0.1, false},
                                           Case{10000, 0.1, true}, Case{20000, 0.5, false}));

TEST(CpAccuracy, ExactBisectionAgreesWithPlateau) {
  const RefineProblem pb = fixtures::MakeKnnProblem(1500, 8, 0.1, 0.2, true, 77);
  const SolverResult a = MakeSolver("exact")->Solve(pb);
  const SolverResult b = MakeSolver("exact", {{"pivot", "bisection"}})->Solve(pb);
  EXPECT_NEAR(a.objective, b.objective, 1e-9 * a.objective);
  double worst = 0.0;
  for (std::size_t v = 0; v < a.p.size(); ++v) worst = std::max(worst, std::fabs(a.p[v] - b.p[v]));
  EXPECT_LT(worst, 1e-6);
}

TEST(CpAccuracy, BkIntegralBoundsExact) {
  const auto names = SolverNames();
  if (std::find(names.begin(), names.end(), "bk") == names.end()) GTEST_SKIP() << "bk not registered";
  for (bool one_hot : {false, true}) {
    const RefineProblem pb = fixtures::MakeKnnProblem(3000, 10, 0.1, 0.1, one_hot, 5);
    const SolverResult ex = MakeSolver("exact")->Solve(pb);
    const SolverResult bk = MakeSolver("bk")->Solve(pb);
    EXPECT_GE(Objective(pb, bk.p), ex.objective * (1 - 1e-12));
    // Level set p >= 0.5 of the relaxed optimum is an integral optimum (SPEC §5).
    std::vector<double> level(pb.num_nodes());
    for (std::size_t v = 0; v < level.size(); ++v) level[v] = ex.p[v] >= 0.5 ? 1.0 : 0.0;
    EXPECT_GE(Objective(pb, level), ex.objective * (1 - 1e-12));
  }
}

}  // namespace
}  // namespace al
