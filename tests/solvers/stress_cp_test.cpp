// Numerical stability and determinism of the cp and exact solvers on hostile inputs: extreme
// smoothing, 0/1 observations, weights over 16 decades, isolated nodes, many components, tiny
// graphs, all- and none-removed; simplex geometry unit checks; option validation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "al/core/error.hpp"
#include "al/solver.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/cut_pursuit/cut_pursuit_solver.hpp"
#include "al/fixtures/knn_problem.hpp"
#include "solvers/exact/exact_solver.hpp"

namespace al {
namespace {

void CheckSane(const RefineProblem& pb, double s, const std::string& what) {
  RefineProblem p = pb;
  p.kl_smoothing = s;
  const cp::SimplexProblem sp = ToSimplexProblem(p);
  cp::CutPursuitOptions o;
  const cp::CutPursuitResult r = cp::RunCutPursuit(sp, o);
  ASSERT_FALSE(r.objective_history.empty()) << what;
  for (double f : r.objective_history) ASSERT_TRUE(std::isfinite(f)) << what;
  ASSERT_TRUE(std::isfinite(r.objective)) << what;
  for (std::int32_t c = 0; c < r.num_components; ++c) {
    const double a = r.rX[2 * c], b = r.rX[2 * c + 1];
    ASSERT_TRUE(std::isfinite(a) && std::isfinite(b)) << what;
    ASSERT_GE(a, 0.0) << what;
    ASSERT_GE(b, 0.0) << what;
    ASSERT_NEAR(a + b, 1.0, 1e-12) << what;
  }
  if (s < 1e-4) return;  // tiny s: only finiteness and termination are asserted
  // Never worse than the initial iterate (the best iterate is returned); F may round below 0.
  const double f0 = r.objective_history.front();
  EXPECT_LE(r.objective, f0 + 1e-12 * std::fabs(f0) + 1e-300) << what;
  const SolverResult ex = MakeSolver("exact")->Solve(p);
  for (double v : ex.p) ASSERT_TRUE(std::isfinite(v) && v >= 0.0 && v <= 1.0) << what;
  EXPECT_LE(ex.objective, r.objective * (1 + 1e-9) + 1e-9) << what;
}

RefineProblem Chain(int n, double w) {
  RefineProblem pb;
  pb.first_edge.assign(n + 1, 0);
  for (int i = 0; i + 1 < n; ++i) {
    pb.first_edge[i + 1] = pb.first_edge[i] + 1;
    pb.adj_vertices.push_back(i + 1);
    pb.edge_weights.push_back(w);
  }
  if (n > 0) pb.first_edge[n] = pb.first_edge[n - 1];
  pb.y_remove.assign(n, 0.0);
  for (int i = 0; i < n; ++i) pb.y_remove[i] = i < n / 2 ? 1.0 : 0.0;
  pb.node_weights.assign(n, 1.0);
  pb.node_ids.resize(n);
  return pb;
}

const double kSmoothings[] = {1e-6, 1e-3, 0.1, 0.5, 0.99, 1.0};

TEST(StressCp, SmoothingRangeOnKnn) {
  const RefineProblem pb = fixtures::MakeKnnProblem(400, 8, 0.1, 0.1, true, 9);
  for (double s : kSmoothings) CheckSane(pb, s, "knn s=" + std::to_string(s));
}

TEST(StressCp, ExtremeWeights) {
  RefineProblem pb = fixtures::MakeKnnProblem(300, 6, 1.0, 0.1, true, 10);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> ex(-8.0, 8.0);
  for (double& w : pb.edge_weights) w = std::pow(10.0, ex(rng));
  for (double& w : pb.node_weights) w = std::pow(10.0, ex(rng));
  for (double s : {0.1, 0.5, 1.0}) CheckSane(pb, s, "weights s=" + std::to_string(s));
}

TEST(StressCp, TinyGraphsAndUniformLabels) {
  for (double s : kSmoothings) {
    CheckSane(Chain(1, 1.0), s, "1 node");
    CheckSane(Chain(2, 0.3), s, "2 nodes");
    RefineProblem all = Chain(50, 0.2), none = Chain(50, 0.2);
    for (double& y : all.y_remove) y = 1.0;
    for (double& y : none.y_remove) y = 0.0;
    CheckSane(all, s, "all removed");
    CheckSane(none, s, "none removed");
  }
  // All removed: the optimum is p = 1 everywhere (the data term vanishes there).
  RefineProblem all = Chain(20, 0.5);
  for (double& y : all.y_remove) y = 1.0;
  const SolverResult r = MakeSolver("cp")->Solve(all);
  for (double p : r.p) EXPECT_DOUBLE_EQ(p, 1.0);
}

TEST(StressCp, IsolatedNodesAndManyComponents) {
  // 200 disjoint 3-node chains plus 50 isolated nodes: each piece is solved independently.
  RefineProblem pb;
  const int pieces = 200, iso = 50, n = pieces * 3 + iso;
  pb.first_edge.assign(n + 1, 0);
  std::mt19937_64 rng(2);
  for (int i = 0; i < n; ++i) {
    const bool link = i < pieces * 3 && i % 3 != 2;
    pb.first_edge[i + 1] = pb.first_edge[i] + (link ? 1 : 0);
    if (link) {
      pb.adj_vertices.push_back(i + 1);
      pb.edge_weights.push_back(0.05 + 0.5 * std::uniform_real_distribution<double>(0, 1)(rng));
    }
    pb.y_remove.push_back(std::bernoulli_distribution(0.4)(rng) ? 1.0 : 0.0);
  }
  pb.node_weights.assign(n, 1.0);
  pb.node_ids.resize(n);
  for (double s : {0.1, 0.5, 1.0}) CheckSane(pb, s, "pieces s=" + std::to_string(s));
  pb.kl_smoothing = 0.3;
  const SolverResult c = MakeSolver("cp", {{"cp_dif_tol", 1e-6}})->Solve(pb);
  const SolverResult e = MakeSolver("exact")->Solve(pb);
  EXPECT_LE((c.objective - e.objective) / e.objective, 1e-4);
  // Isolated nodes take their own observation (closed form).
  for (int i = pieces * 3; i < n; ++i) EXPECT_NEAR(c.p[i], pb.y_remove[i], 1e-12);
}

TEST(StressCp, GeneralDSimplex) {
  // D = 3 on a kNN graph: rows stay on the simplex, objective never above the start.
  const RefineProblem base = fixtures::MakeKnnProblem(300, 6, 0.05, 0.2, false, 21);
  cp::SimplexProblem sp;
  sp.D = 3;
  sp.first_edge = base.first_edge;
  sp.adj_vertices = base.adj_vertices;
  sp.edge_weights = base.edge_weights;
  sp.loss = 0.2;
  std::mt19937_64 rng(5);
  for (std::size_t v = 0; v < base.num_nodes(); ++v) {
    const int hot = std::uniform_int_distribution<int>(0, 2)(rng);
    for (int d = 0; d < 3; ++d) sp.y.push_back(d == hot ? 1.0 : 0.0);
  }
  const cp::CutPursuitResult r = cp::RunCutPursuit(sp, {});
  for (std::int32_t c = 0; c < r.num_components; ++c)
    EXPECT_NEAR(r.rX[3 * c] + r.rX[3 * c + 1] + r.rX[3 * c + 2], 1.0, 1e-12);
  EXPECT_LT(r.objective, r.objective_history.front());
  EXPECT_NEAR(r.objective, cp::SimplexObjective(sp, r.comp_assign, r.rX), 1e-9 * r.objective);
}

TEST(StressCp, DeterministicAcrossThreads) {
  const RefineProblem pb = fixtures::MakeKnnProblem(4000, 10, 0.1, 0.1, false, 33);
  const cp::SimplexProblem sp = ToSimplexProblem(pb);
  cp::CutPursuitOptions o1, o2;
  o1.num_threads = 1;
  o2.num_threads = 2;
  const cp::CutPursuitResult a = cp::RunCutPursuit(sp, o1), b = cp::RunCutPursuit(sp, o2);
  EXPECT_EQ(a.comp_assign, b.comp_assign);
  ASSERT_EQ(a.rX.size(), b.rX.size());
  for (std::size_t i = 0; i < a.rX.size(); ++i) EXPECT_EQ(a.rX[i], b.rX[i]) << i;  // bit-identical
  EXPECT_EQ(a.objective_history, b.objective_history);
}

TEST(StressCp, ProjectDirectionIsTangent) {
  const double eps = 1e-15;
  double z[3];
  // D = 2 interior: +-(1, -1)/sqrt(2) with the sign of G_1 - G_0 (r = -G).
  const double X2[2] = {0.3, 0.7}, r2[2] = {2.0, 5.0};
  cp::ProjectDirection(X2, r2, 2, eps, false, z);
  EXPECT_NEAR(z[0], -std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(z[1], std::sqrt(0.5), 1e-15);
  // Interior D = 3: sum zero, unit norm, aligned with r minus its mean.
  const double X3[3] = {0.2, 0.3, 0.5}, r3[3] = {4.0, 1.0, 1.5};
  cp::ProjectDirection(X3, r3, 3, eps, false, z);
  EXPECT_NEAR(z[0] + z[1] + z[2], 0.0, 1e-15);
  EXPECT_NEAR(z[0] * z[0] + z[1] * z[1] + z[2] * z[2], 1.0, 1e-14);
  EXPECT_GT(z[0], 0.0);
  // The upstream bug keeps a (1, ..., 1) component: not tangent.
  cp::ProjectDirection(X3, r3, 3, eps, true, z);
  EXPECT_GT(std::fabs(z[0] + z[1] + z[2]), 0.1);
  // Vertex of the simplex: only directions leaving the one coordinate are feasible.
  const double V3[3] = {1.0, 0.0, 0.0}, rv[3] = {0.0, 3.0, 1.0};
  cp::ProjectDirection(V3, rv, 3, eps, false, z);
  EXPECT_LT(z[0], 0.0);
  EXPECT_GT(z[1], 0.0);
  EXPECT_NEAR(z[0] + z[1] + z[2], 0.0, 1e-15);
  const double rn[3] = {3.0, 1.0, 0.0};  // wants to grow the coordinate at one: no descent
  cp::ProjectDirection(V3, rn, 3, eps, false, z);
  EXPECT_EQ(z[0], 0.0);
  EXPECT_EQ(z[1], 0.0);
}

TEST(StressCp, CorrectProjectionBeatsUpstreamBug) {
  const RefineProblem pb = fixtures::MakeKnnProblem(3000, 10, 0.1, 0.1, false, 44);
  const SolverResult good = MakeSolver("cp")->Solve(pb);
  const SolverResult bad = MakeSolver("cp", {{"emulate_upstream_projection_bug", true}})->Solve(pb);
  EXPECT_LE(good.objective, bad.objective * (1 + 1e-12));
}

TEST(StressCp, OptionsValidated) {
  EXPECT_THROW(MakeSolver("cp", {{"no_such_option", 1}}), Error);
  try {
    MakeSolver("cp", {{"cp_it_maxx", 3}});
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kUsage);
  }
  EXPECT_THROW(MakeSolver("cp", {{"cp_it_max", "ten"}}), Error);
  EXPECT_THROW(MakeSolver("cp", {{"K", 3}}), Error);
  EXPECT_THROW(MakeSolver("exact", {{"pivot", "golden"}}), Error);
  EXPECT_THROW(MakeSolver("exact", {{"tolerance", 1e-3}}), Error);
  EXPECT_NO_THROW(MakeSolver("cp", {{"cp_dif_tol", 1e-4}, {"pfdr_it_max", 500}, {"num_threads", 1}}));
  RefineProblem bad = Chain(3, 1.0);
  bad.edge_weights[0] = -1.0;
  EXPECT_THROW(MakeSolver("cp")->Solve(bad), Error);
  EXPECT_THROW(MakeSolver("exact")->Solve(bad), Error);
  bad = Chain(3, 1.0);
  bad.y_remove[1] = std::nan("");
  EXPECT_THROW(MakeSolver("cp")->Solve(bad), Error);
  EXPECT_THROW(MakeSolver("exact")->Solve(bad), Error);
}

}  // namespace
}  // namespace al
