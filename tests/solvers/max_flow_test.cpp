// The shared max-flow (solvers/bk/max_flow.hpp): al::MaxFlow against brute force on small random
// networks (cut value, and the returned source side is exactly the smallest minimum-cut source set
// when capacities are small integers, so arithmetic is exact), one network object reused across
// differently sized problems (buffer reuse must not leak state), and agreement with the independent
// Boost Boykov-Kolmogorov reference on a 3,000-node kNN level cut.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/bk/max_flow.hpp"
#include "solvers/cut_pursuit/loss.hpp"
#include "solvers/cut_pursuit/synthetic_knn.hpp"

namespace {

struct Net {
  int V = 0;
  std::vector<double> src, snk;
  struct Edge { int u, v; double cuv, cvu; };
  std::vector<Edge> edges;
};

// Cost of a source-side indicator S (1 = source side), MaxFlow's cut convention.
double CutCost(const Net& n, std::uint32_t S) {
  double c = 0.0;
  for (int v = 0; v < n.V; ++v) c += ((S >> v) & 1u) ? n.snk[v] : n.src[v];
  for (const auto& e : n.edges) {
    const bool su = (S >> e.u) & 1u, sv = (S >> e.v) & 1u;
    if (su && !sv) c += e.cuv;
    if (!su && sv) c += e.cvu;
  }
  return c;
}

Net RandomNet(std::mt19937& rng, int V, bool integral) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto cap = [&](double scale) { return integral ? std::floor(uni(rng) * scale * 4) : uni(rng) * scale; };
  Net n;
  n.V = V;
  for (int v = 0; v < V; ++v) {
    // Several terminal calls per node exercise the folding of the common part into the flow.
    n.src.push_back(cap(2.0));
    n.snk.push_back(cap(2.0));
  }
  for (int u = 0; u < V; ++u)
    for (int v = u + 1; v < V; ++v)
      if (uni(rng) < 0.45) n.edges.push_back({u, v, cap(1.0), uni(rng) < 0.3 ? 0.0 : cap(1.0)});
  return n;
}

double Solve(al::MaxFlow& mf, const Net& n) {
  mf.Reset(n.V);
  for (int v = 0; v < n.V; ++v) {
    mf.AddTerminal(v, 0.5 * n.src[v], 0.25 * n.snk[v]);
    mf.AddTerminal(v, 0.5 * n.src[v], 0.75 * n.snk[v]);
  }
  for (const auto& e : n.edges) mf.AddEdge(e.u, e.v, e.cuv, e.cvu);
  return mf.Solve();
}

TEST(MaxFlow, MatchesBruteForceAndReturnsSmallestSourceSet) {
  std::mt19937 rng(2026);
  al::MaxFlow mf;  // one object for every trial: Reset must clear all state
  for (int trial = 0; trial < 300; ++trial) {
    const bool integral = trial % 2 == 0;
    const Net n = RandomNet(rng, 1 + trial % 13, integral);
    const double value = Solve(mf, n);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t smallest = ~0u;  // intersection of all minimum-cut source sets
    for (std::uint32_t S = 0; S < (1u << n.V); ++S) {
      const double c = CutCost(n, S);
      if (c < best - 1e-12) { best = c; smallest = S; }
      else if (std::fabs(c - best) <= 1e-12) smallest &= S;
    }
    std::uint32_t got = 0;
    for (int v = 0; v < n.V; ++v) got |= mf.SourceSide(v) ? (1u << v) : 0u;
    EXPECT_NEAR(value, best, 1e-9 * (1.0 + best)) << "trial " << trial;
    EXPECT_NEAR(CutCost(n, got), best, 1e-9 * (1.0 + best)) << "trial " << trial;
    if (integral) {
      EXPECT_EQ(got, smallest) << "trial " << trial;
    }
  }
}

TEST(MaxFlow, AgreesWithBoostOnKnnLevelCut) {
  const al::RefineProblem pb = al::cp::MakeKnnProblem(3000, 10, 0.1, 0.1, false, 7);
  const al::cp::Loss loss{0.1, 2};
  const std::size_t V = pb.num_nodes();
  for (double t : {0.3, 0.4, 0.5, 0.6}) {
    std::vector<double> src(V), snk(V), cap(pb.adj_vertices.size(), 0.2);
    for (std::size_t v = 0; v < V; ++v) {
      const double a = loss.Grad(pb.y_remove[v], t) - loss.Grad(1.0 - pb.y_remove[v], 1.0 - t);
      src[v] = a > 0.0 ? a : 0.0;
      snk[v] = a < 0.0 ? -a : 0.0;
    }
    const auto own = al::MinCutLabels(src, snk, pb.first_edge, pb.adj_vertices, cap);
    const auto ref = al::MinCutLabelsBoost(src, snk, pb.first_edge, pb.adj_vertices, cap);
    EXPECT_NEAR(own.cut_value, ref.cut_value, 1e-9 * ref.cut_value) << "t = " << t;
    std::size_t differ = 0, source = 0;
    for (std::size_t v = 0; v < V; ++v) {
      differ += own.source_side[v] != ref.source_side[v];
      source += own.source_side[v];
    }
    EXPECT_EQ(differ, 0u) << "t = " << t;
    EXPECT_GT(source, 0u) << "t = " << t;  // a real split, not a trivial cut
    EXPECT_LT(source, V) << "t = " << t;
  }
}

}  // namespace
