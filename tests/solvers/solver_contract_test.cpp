// The contract every registered solver keeps (al/solver.hpp), checked for each name SolverNames()
// returns, so a new solver is held to it the moment it is added to solvers/registry.cpp:
// one p_v in [0, 1] per node, the reported objective is Objective(problem, p), never below the
// exact solver's minimum, the same answer twice, and degenerate graphs (empty, no edges,
// disconnected, zero weights) solved without error.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "al/core/error.hpp"
#include "al/fixtures/knn_problem.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

// Two copies of a kNN problem side by side, with no edge between them, and isolated nodes after.
RefineProblem Disconnected() {
  const RefineProblem a = fixtures::MakeKnnProblem(300, 6, 0.2, 0.1, true, 11);
  RefineProblem p = a;
  const auto shift = static_cast<std::int32_t>(a.num_nodes());
  for (std::size_t v = 0; v < a.num_nodes(); ++v) {
    for (std::int64_t e = a.first_edge[v]; e < a.first_edge[v + 1]; ++e) {
      p.adj_vertices.push_back(a.adj_vertices[e] + shift);
      p.edge_weights.push_back(a.edge_weights[e]);
    }
    p.first_edge.push_back(static_cast<std::int64_t>(p.adj_vertices.size()));
    p.y_remove.push_back(1.0 - a.y_remove[v]);
    p.node_weights.push_back(a.node_weights[v]);
    p.node_ids.push_back(a.node_ids[v] + shift);
  }
  for (int i = 0; i < 5; ++i) {  // isolated nodes: the data term alone decides them
    p.first_edge.push_back(p.first_edge.back());
    p.y_remove.push_back(i % 2);
    p.node_weights.push_back(1.0);
    p.node_ids.push_back(static_cast<std::int64_t>(p.node_ids.size()));
  }
  return p;
}

RefineProblem ZeroWeights() {
  RefineProblem p = fixtures::MakeKnnProblem(400, 8, 0.0, 0.1, false, 3);
  for (double& w : p.edge_weights) w = 0.0;
  return p;
}

struct Case {
  std::string name;
  RefineProblem problem;
};

std::vector<Case> Cases() {
  RefineProblem empty;
  empty.first_edge = {0};
  return {{"empty", empty},
          {"soft", fixtures::MakeKnnProblem(2000, 10, 0.1, 0.1, false, 7)},
          {"one_hot_strong_edges", fixtures::MakeKnnProblem(1500, 10, 1.0, 0.1, true, 8)},
          {"disconnected", Disconnected()},
          {"zero_edge_weights", ZeroWeights()}};
}

TEST(SolverContract, EveryRegisteredSolverKeepsIt) {
  const auto names = SolverNames();
  ASSERT_FALSE(names.empty());
  for (const Case& c : Cases()) {
    const double minimum = MakeSolver("exact")->Solve(c.problem).objective;
    for (const std::string& name : names) {
      SCOPED_TRACE(name + " on " + c.name);
      const auto solver = MakeSolver(name);
      EXPECT_EQ(solver->name(), name);
      const SolverResult r = solver->Solve(c.problem);
      ASSERT_EQ(r.p.size(), c.problem.num_nodes());
      for (double p : r.p) ASSERT_TRUE(p >= 0.0 && p <= 1.0) << p;
      const double f = Objective(c.problem, r.p);
      EXPECT_NEAR(r.objective, f, 1e-9 * std::max(1.0, std::fabs(f)));
      EXPECT_GE(f, minimum - 1e-9 * std::max(1.0, std::fabs(minimum)));
      EXPECT_EQ(solver->Solve(c.problem).p, r.p) << "not deterministic";
    }
  }
}

TEST(SolverContract, UnknownNamesAndOptionsAreUsageErrors) {
  EXPECT_THROW(MakeSolver("no-such-solver"), Error);
  for (const std::string& name : SolverNames()) EXPECT_THROW(MakeSolver(name, {{"no_such_option", 1}}), Error) << name;
}

}  // namespace
}  // namespace al
