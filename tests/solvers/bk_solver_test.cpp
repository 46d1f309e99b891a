// bk must return a global minimiser of the integral energy: compared with brute force over all
// 2^V labelings on small random graphs; MinCutLabels against brute-force cuts (incl. asymmetric
// arcs and infinite capacities).
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/graph/problem.hpp"
#include "al/solver.hpp"
#include "solvers/bk/bk_solver.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace {

al::RefineProblem RandomProblem(std::mt19937& rng, int V, double density, double lambda) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  al::RefineProblem p;
  p.first_edge.assign(V + 1, 0);
  for (int u = 0; u < V; ++u) {
    for (int v = u + 1; v < V; ++v)
      if (uni(rng) < density) {
        p.adj_vertices.push_back(v);
        p.edge_weights.push_back(lambda * uni(rng));
      }
    p.first_edge[u + 1] = static_cast<std::int64_t>(p.adj_vertices.size());
    p.y_remove.push_back(uni(rng) < 0.4 ? 1.0 : 0.0);
    p.node_weights.push_back(0.5 + uni(rng));
    p.node_ids.push_back(u);
  }
  p.kl_smoothing = 0.05 + 0.3 * uni(rng);
  return p;
}

TEST(BkSolver, MatchesBruteForceOverAllLabelings) {
  std::mt19937 rng(12345);
  auto solver = al::MakeSolver("bk");
  for (int trial = 0; trial < 60; ++trial) {
    const int V = 1 + trial % 16;
    const al::RefineProblem p = RandomProblem(rng, V, 0.3 + 0.01 * trial, 0.2 + 0.05 * trial);
    const al::SolverResult r = solver->Solve(p);
    ASSERT_EQ(r.p.size(), static_cast<std::size_t>(V));
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> x(V);
    for (std::uint32_t mask = 0; mask < (1u << V); ++mask) {
      for (int v = 0; v < V; ++v) x[v] = (mask >> v) & 1u ? 1.0 : 0.0;
      best = std::min(best, al::Objective(p, x));
    }
    for (double pv : r.p) EXPECT_TRUE(pv == 0.0 || pv == 1.0);
    EXPECT_NEAR(r.objective, best, 1e-9 * (1 + best)) << "trial " << trial;
    EXPECT_NEAR(r.objective, al::Objective(p, r.p), 1e-12);
    EXPECT_TRUE(r.converged);
  }
}

TEST(BkSolver, NoEdgesKeepsObservations) {
  std::mt19937 rng(7);
  al::RefineProblem p = RandomProblem(rng, 12, 0.0, 1.0);
  const auto r = al::MakeSolver("bk")->Solve(p);
  for (std::size_t v = 0; v < p.num_nodes(); ++v) EXPECT_EQ(r.p[v], p.y_remove[v]);
}

TEST(BkSolver, RejectsUnknownOptions) {
  EXPECT_THROW(al::MakeSolver("bk", {{"foo", 1}}), al::Error);
  EXPECT_NO_THROW(al::MakeSolver("bk", nlohmann::json::object()));
}

TEST(MinCutLabels, MatchesBruteForceCutsWithAsymmetricAndInfiniteArcs) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 80; ++trial) {
    const int V = 1 + trial % 12;
    std::vector<double> src(V), snk(V), fwd, rev;
    std::vector<std::int64_t> first(V + 1, 0);
    std::vector<std::int32_t> adj;
    for (int u = 0; u < V; ++u) {
      src[u] = uni(rng) < 0.1 ? inf : uni(rng) * 2;
      snk[u] = std::isinf(src[u]) ? 0.0 : (uni(rng) < 0.1 ? inf : uni(rng) * 2);
      for (int v = u + 1; v < V; ++v)
        if (uni(rng) < 0.4) {
          adj.push_back(v);
          fwd.push_back(uni(rng));
          rev.push_back(uni(rng) < 0.3 ? 0.0 : uni(rng));
        }
      first[u + 1] = static_cast<std::int64_t>(adj.size());
    }
    const auto cut = al::MinCutLabels(src, snk, first, adj, fwd, rev);
    auto cost = [&](const std::vector<std::uint8_t>& S) {
      double c = 0;
      for (int v = 0; v < V; ++v) c += S[v] ? snk[v] : src[v];
      for (int u = 0; u < V; ++u)
        for (auto e = first[u]; e < first[u + 1]; ++e) {
          if (S[u] && !S[adj[e]]) c += fwd[e];
          if (!S[u] && S[adj[e]]) c += rev[e];
        }
      return c;
    };
    double best = inf;
    std::vector<std::uint8_t> S(V);
    for (std::uint32_t m = 0; m < (1u << V); ++m) {
      for (int v = 0; v < V; ++v) S[v] = (m >> v) & 1u;
      best = std::min(best, cost(S));
    }
    ASSERT_TRUE(std::isfinite(best));  // constructed so that a finite cut always exists
    EXPECT_NEAR(cost(cut.source_side), best, 1e-9 * (1 + best)) << "trial " << trial;
    EXPECT_NEAR(cut.cut_value, best, 1e-9 * (1 + best)) << "trial " << trial;
  }
}

TEST(MinCutLabels, RejectsNegativeCapacity) {
  std::vector<double> src{1.0, -1.0}, snk{0.0, 0.0}, cap{1.0};
  std::vector<std::int64_t> first{0, 1, 1};
  std::vector<std::int32_t> adj{1};
  EXPECT_THROW(al::MinCutLabels(src, snk, first, adj, cap), al::Error);
}

}  // namespace
