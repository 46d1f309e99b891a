// The shared max-flow (solvers/max_flow/max_flow.hpp), for each of its algorithms (the default hybrid,
// pseudoflow then BK, BK alone): against brute force on small random networks (cut value, and the
// returned source side is exactly the smallest minimum-cut source set when capacities are small
// integers, so arithmetic is exact), one network object reused across differently sized problems
// (buffer reuse must not leak state), the three algorithms against each other on kNN level cuts
// where the hybrid does hand over to pseudoflow, pseudoflow alone leaving the BK completion nothing
// to augment (it is a maximum-flow algorithm by itself), degenerate networks, and agreement with the
// independent Boost Boykov-Kolmogorov reference on a 3,000-node kNN level cut.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/max_flow/max_flow.hpp"
#include "al/graph/loss.hpp"
#include "al/fixtures/knn_problem.hpp"

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

using Algorithm = al::MaxFlow::Algorithm;
const Algorithm kAlgorithms[] = {Algorithm::kHybrid, Algorithm::kPseudoflowThenBk,
                                 Algorithm::kBoykovKolmogorov};

double Solve(al::MaxFlow& mf, const Net& n) {
  mf.Reset(n.V);
  for (int v = 0; v < n.V; ++v) {
    mf.AddTerminal(v, 0.5 * n.src[v], 0.25 * n.snk[v]);
    mf.AddTerminal(v, 0.5 * n.src[v], 0.75 * n.snk[v]);
  }
  for (const auto& e : n.edges) mf.AddEdge(e.u, e.v, e.cuv, e.cvu);
  return mf.Solve();
}

class MaxFlowAlgorithm : public ::testing::TestWithParam<Algorithm> {};

TEST_P(MaxFlowAlgorithm, MatchesBruteForceAndReturnsSmallestSourceSet) {
  std::mt19937 rng(2026);
  al::MaxFlow mf;  // one object for every trial: Reset must clear all state
  mf.set_algorithm(GetParam());
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
      // Exact arithmetic: a complete pseudoflow phase leaves no augmenting path for BK.
      if (GetParam() == Algorithm::kPseudoflowThenBk) {
        EXPECT_EQ(mf.stats().augmentations, 0) << "trial " << trial;
      }
    }
  }
}

// Degenerate networks: no nodes, no edges, zero capacities, isolated nodes, parallel edges, one-sided
// terminals, capacities spread over 16 orders of magnitude, hard constraints (terminal capacities of
// 2 * sum + 1, MinCutLabels' stand-in for infinity: pseudoflow gathers such excess at tree roots).
// Every algorithm must return a cut whose cost is the brute-force minimum and the same source side
// as the others.
TEST_P(MaxFlowAlgorithm, DegenerateNetworks) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  al::MaxFlow mf, reference;
  mf.set_algorithm(GetParam());
  reference.set_algorithm(Algorithm::kBoykovKolmogorov);
  for (int trial = 0; trial < 200; ++trial) {
    Net n;
    n.V = trial % 12;  // 0 included: an empty network
    const int kind = trial % 6;
    auto cap = [&]() {
      if (kind == 4) return std::pow(10.0, -8.0 + 16.0 * uni(rng));  // 1e-8 .. 1e8
      return uni(rng) < 0.3 ? 0.0 : uni(rng);
    };
    for (int v = 0; v < n.V; ++v) {
      n.src.push_back(kind == 1 ? cap() : (kind == 2 ? 0.0 : cap()));
      n.snk.push_back(kind == 2 ? cap() : (kind == 1 ? 0.0 : cap()));
    }
    if (kind != 0)
      for (int u = 0; u < n.V; ++u)
        for (int v = u + 1; v < n.V; ++v)
          if (uni(rng) < 0.4) {
            n.edges.push_back({u, v, cap(), cap()});
            if (kind == 3) n.edges.push_back({v, u, cap(), cap()});  // parallel, reversed
          }
    if (kind == 5) {
      double sum = 0.0;
      for (int v = 0; v < n.V; ++v) sum += n.src[v] + n.snk[v];
      for (const auto& e : n.edges) sum += e.cuv + e.cvu;
      for (int v = 0; v < n.V; ++v)
        if (uni(rng) < 0.3) (uni(rng) < 0.5 ? n.src[v] : n.snk[v]) = 2.0 * sum + 1.0;
    }
    const double value = Solve(mf, n);
    Solve(reference, n);
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t S = 0; S < (1u << n.V); ++S) best = std::min(best, CutCost(n, S));
    std::uint32_t got = 0, ref = 0;
    for (int v = 0; v < n.V; ++v) {
      got |= mf.SourceSide(v) ? (1u << v) : 0u;
      ref |= reference.SourceSide(v) ? (1u << v) : 0u;
    }
    const double tol = 1e-12 * (1.0 + best) + (kind == 4 ? 1e-7 : 0.0);
    EXPECT_NEAR(value, best, tol) << "trial " << trial;
    EXPECT_NEAR(CutCost(n, got), best, tol) << "trial " << trial;
    if (kind != 4) {
      EXPECT_EQ(got, ref) << "trial " << trial;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Algorithms, MaxFlowAlgorithm, ::testing::ValuesIn(kAlgorithms),
                         [](const ::testing::TestParamInfo<Algorithm>& info) {
                           switch (info.param) {
                             case Algorithm::kHybrid: return std::string("Hybrid");
                             case Algorithm::kPseudoflowThenBk: return std::string("PseudoflowThenBk");
                             case Algorithm::kBoykovKolmogorov: return std::string("BoykovKolmogorov");
                           }
                           return std::string("Unknown");
                         });

// Cuts of a 20k-node kNN graph: level cuts of its refinement problem (most excess stranded: BK's
// kind of cut) and a balanced cut of zero-mean noise, where excess and deficit interleave everywhere
// and the flow has to travel across the graph, as in cut pursuit's re-splits (BK needs many sweeps,
// so the hybrid hands over to pseudoflow). All algorithms return the same source side and cut value.
TEST(MaxFlow, AlgorithmsAgreeOnKnnCuts) {
  const al::RefineProblem pb = al::fixtures::MakeKnnProblem(20000, 10, 0.1, 0.1, false, 11);
  const al::Loss loss{0.1, 2};
  const std::int32_t V = static_cast<std::int32_t>(pb.num_nodes());
  std::vector<std::vector<double>> unaries;
  for (double t : {0.3, 0.45, 0.6}) {
    unaries.emplace_back(V);
    for (std::int32_t v = 0; v < V; ++v)
      unaries.back()[v] = loss.Grad(pb.y_remove[v], t) - loss.Grad(1.0 - pb.y_remove[v], 1.0 - t);
  }
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  unaries.emplace_back(V);
  double mean = 0.0;
  for (auto& a : unaries.back()) mean += (a = noise(rng)) / V;
  for (auto& a : unaries.back()) a -= mean;
  bool handed_over = false;
  for (std::size_t k = 0; k < unaries.size(); ++k) {
    al::MaxFlow mf[3];
    double value[3];
    for (int a = 0; a < 3; ++a) {
      mf[a].set_algorithm(kAlgorithms[a]);
      mf[a].Reset(V);
      for (std::int32_t v = 0; v < V; ++v) mf[a].AddUnary(v, unaries[k][v]);
      for (std::int32_t u = 0; u < V; ++u)
        for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e)
          mf[a].AddEdge(u, pb.adj_vertices[e], 2.0 * pb.edge_weights[e], 2.0 * pb.edge_weights[e]);
      value[a] = mf[a].Solve();
    }
    handed_over = handed_over || mf[0].stats().mergers > 0;
    EXPECT_EQ(mf[1].stats().augmentations, 0) << "cut " << k;  // pseudoflow finished the job
    std::int32_t differ = 0, source = 0;
    for (std::int32_t v = 0; v < V; ++v) {
      differ += mf[0].SourceSide(v) != mf[2].SourceSide(v);
      differ += mf[1].SourceSide(v) != mf[2].SourceSide(v);
      source += mf[2].SourceSide(v);
    }
    EXPECT_EQ(differ, 0) << "cut " << k;
    EXPECT_GT(source, 0) << "cut " << k;
    EXPECT_LT(source, V) << "cut " << k;
    EXPECT_NEAR(value[0], value[2], 1e-12 * value[2]) << "cut " << k;
    EXPECT_NEAR(value[1], value[2], 1e-12 * value[2]) << "cut " << k;
  }
  EXPECT_TRUE(handed_over) << "no cut was hard enough to exercise the hybrid's pseudoflow phase";
}

TEST(MaxFlow, AgreesWithBoostOnKnnLevelCut) {
  const al::RefineProblem pb = al::fixtures::MakeKnnProblem(3000, 10, 0.1, 0.1, false, 7);
  const al::Loss loss{0.1, 2};
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

// SetEdges lays out large networks on several threads (ranges of sources, edges stored at their
// smaller end): the same arcs in the same order as the serial fill, so the same augmentations,
// source side and cut value on any thread count, and the same cut as the AddEdge network.
TEST(MaxFlow, CsrNetworkIsTheSameOnAnyThreadCount) {
  const al::RefineProblem pb = al::fixtures::MakeKnnProblem(20000, 10, 0.1, 0.1, false, 13);
  ASSERT_GE(pb.adj_vertices.size(), std::size_t{1} << 16);  // large enough for the parallel layout
  const al::Loss loss{0.1, 2};
  const std::int32_t V = static_cast<std::int32_t>(pb.num_nodes());
  std::vector<double> cap(pb.edge_weights.size());
  for (std::size_t e = 0; e < cap.size(); ++e) cap[e] = 2.0 * pb.edge_weights[e];
  auto solve = [&](int threads, bool csr, std::vector<char>& side, std::int64_t& augmentations) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    al::MaxFlow mf;
    mf.set_algorithm(Algorithm::kBoykovKolmogorov);
    mf.Reset(V);
    for (std::int32_t v = 0; v < V; ++v)
      mf.AddUnary(v, loss.Grad(pb.y_remove[v], 0.45) - loss.Grad(1.0 - pb.y_remove[v], 0.55));
    if (csr) {
      mf.SetEdges(pb.first_edge, pb.adj_vertices, cap);
    } else {
      for (std::int32_t u = 0; u < V; ++u)
        for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e) mf.AddEdge(u, pb.adj_vertices[e], cap[e], cap[e]);
    }
    const double value = mf.Solve();
    omp_set_num_threads(before);
    side.resize(V);
    for (std::int32_t v = 0; v < V; ++v) side[v] = mf.SourceSide(v);
    augmentations = mf.num_augmentations();
    return value;
  };
  std::vector<char> serial_side, side, edge_side;
  std::int64_t serial_aug = 0, aug = 0, edge_aug = 0;
  const double serial = solve(1, true, serial_side, serial_aug);
  for (int threads : {2, 3, 8}) {
    EXPECT_EQ(solve(threads, true, side, aug), serial) << threads << " threads";
    EXPECT_EQ(aug, serial_aug) << threads << " threads";
    EXPECT_EQ(side, serial_side) << threads << " threads";
  }
  EXPECT_NEAR(solve(2, false, edge_side, edge_aug), serial, 1e-12 * serial);
  EXPECT_EQ(edge_side, serial_side);
  EXPECT_GT(std::count(serial_side.begin(), serial_side.end(), 1), 0);  // a real split
  EXPECT_LT(std::count(serial_side.begin(), serial_side.end(), 1), V);
}

}  // namespace
