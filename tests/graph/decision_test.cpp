// Decision rules: fixed threshold, nearest-rank percentile with plateaus, restore, the segment
// rule, parsing.
#include <cmath>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/decision.hpp"

namespace {

al::RefineProblem Nodes(std::vector<std::int64_t> ids) {
  al::RefineProblem p;
  p.node_ids = ids;
  p.y_remove.assign(ids.size(), 0.0);
  p.first_edge.assign(ids.size() + 1, 0);
  return p;
}

// Undirected edges (a < b) into the CSR arrays of p; y_remove from R (p.node_ids index R).
void SetEdges(al::RefineProblem& p, const std::vector<std::pair<int, int>>& edges, const std::vector<bool>& R) {
  const std::size_t V = p.node_ids.size();
  p.first_edge.assign(V + 1, 0);
  p.adj_vertices.clear();
  for (std::size_t u = 0; u < V; ++u) {
    for (const auto& [a, b] : edges)
      if (a == int(u)) p.adj_vertices.push_back(b);
    p.first_edge[u + 1] = std::int64_t(p.adj_vertices.size());
  }
  p.edge_weights.assign(p.adj_vertices.size(), 1.0);
  p.node_weights.assign(V, 1.0);
  for (std::size_t v = 0; v < V; ++v) p.y_remove[v] = R[std::size_t(p.node_ids[v])] ? 1.0 : 0.0;
}

TEST(Decision, DefaultsRestoreWithoutTheSegmentRule) {
  const al::DecisionOptions d;
  EXPECT_TRUE(d.Restores());  // auto: on for a direct caller
  EXPECT_EQ(d.min_segment_share, 0.0);
}

TEST(Decision, FixedThresholdAddsOnlyUnlessRestore) {
  std::vector<bool> R{true, true, false, false, false, true};
  const auto prob = Nodes({0, 1, 2, 3, 5});
  const std::vector<double> p{1.0, 0.2, 0.5, 0.49, 0.0};
  al::DecisionOptions plain;  // SPEC §5's rule alone (add only)
  plain.restore = al::Restore::kOff;
  const auto d = al::ApplyDecision(R, prob, p, plain);
  EXPECT_EQ(d.refined, (std::vector<bool>{true, true, true, false, false, true}));
  EXPECT_EQ(d.added, 1u);
  EXPECT_EQ(d.restored, 0u);
  EXPECT_EQ(d.at_threshold, 1u);
  al::DecisionOptions o = plain;
  o.restore = al::Restore::kOn;
  const auto r = al::ApplyDecision(R, prob, p, o);
  EXPECT_EQ(r.refined, (std::vector<bool>{true, false, true, false, false, false}));
  EXPECT_EQ(r.restored, 2u);
}

TEST(Decision, SegmentRuleAddsOnlyToSegmentsMostlyRemoved) {
  // Segment A = nodes 0-4 (chain), 4 of 5 in R; segment B = nodes 5-7 (chain), 1 of 3 in R;
  // segment C = nodes 8-10, 2 of 3 in R (exactly the default share). The solver says "remove"
  // everywhere.
  const std::vector<bool> R{true, true, true, true, false, true, false, false, true, true, false};
  auto prob = Nodes({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10});
  SetEdges(prob, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {5, 6}, {6, 7}, {8, 9}, {9, 10}}, R);
  const std::vector<double> p(11, 1.0);
  al::DecisionOptions rule;
  rule.min_segment_share = 2.0 / 3.0;
  const auto d = al::ApplyDecision(R, prob, p, rule);
  EXPECT_TRUE(d.refined[4]);    // A: share 0.8
  EXPECT_FALSE(d.refined[6]);   // B: share 1/3, left as the method left it
  EXPECT_FALSE(d.refined[7]);
  EXPECT_TRUE(d.refined[10]);   // C: share 2/3 >= 2/3
  EXPECT_EQ(d.added, 2u);
  EXPECT_EQ(d.held_back, 2u);
  EXPECT_EQ(d.segments_held_back, 1u);
  EXPECT_EQ(d.selected, 11u);
  EXPECT_EQ(d.ToJson().at("held_back"), 2);
  // Off (the default): SPEC §5's plain rule adds all four.
  al::DecisionOptions off;
  const auto e = al::ApplyDecision(R, prob, p, off);
  EXPECT_EQ(e.refined, std::vector<bool>(11, true));
  EXPECT_EQ(e.added, 4u);
  EXPECT_EQ(e.held_back, 0u);
  // Shares are weighted by the node weights: node 4 weighing 4 makes A's share 4/8.
  prob.node_weights[4] = 4.0;
  const auto f = al::ApplyDecision(R, prob, p, rule);
  EXPECT_FALSE(f.refined[4]);
  EXPECT_EQ(f.segments_held_back, 2u);
  // Shares come from the mask, not from soft observations (the feature prior's y).
  for (double& y : prob.y_remove) y = 0.5;
  EXPECT_EQ(al::ApplyDecision(R, prob, p, rule).refined, f.refined);
  // Restore is independent of the segment rule; bad shares are usage errors.
  al::DecisionOptions restore = rule;
  restore.restore = al::Restore::kOn;
  std::vector<double> q(11, 1.0);
  q[5] = 0.0;  // an R node of B the solver returns
  EXPECT_EQ(al::ApplyDecision(R, prob, q, restore).restored, 1u);
  al::DecisionOptions bad;
  bad.min_segment_share = 1.5;
  EXPECT_THROW(al::ApplyDecision(R, prob, p, bad), al::Error);
}

TEST(Decision, NearestRankPercentileWithPlateau) {
  // 10,000 distinct values: P95 keeps n - k + 1 = 501 nodes.
  const std::size_t n = 10000;
  std::vector<std::int64_t> ids(n);
  std::vector<double> p(n);
  for (std::size_t i = 0; i < n; ++i) {
    ids[i] = static_cast<std::int64_t>(i);
    p[i] = static_cast<double>((i * 7919) % n) / n;
  }
  al::DecisionOptions o;
  o.rule = al::ParseDecisionRule("percentile:95");
  o.min_segment_share = 0.0;  // the rank rule alone (no edges, nothing in R here)
  const auto d = al::ApplyDecision(std::vector<bool>(n, false), Nodes(ids), p, o);
  EXPECT_EQ(d.added, 501u);
  EXPECT_DOUBLE_EQ(d.threshold, 9499.0 / n);
  // A plateau on the percentile: everything tied goes.
  std::vector<double> q(n, 0.0);
  for (std::size_t i = 9000; i < n; ++i) q[i] = 0.7;
  const auto e = al::ApplyDecision(std::vector<bool>(n, false), Nodes(ids), q, o);
  EXPECT_EQ(e.threshold, 0.7);
  EXPECT_EQ(e.added, 1000u);
  EXPECT_EQ(e.at_threshold, 1000u);
  // All equal: all removed.
  const auto f = al::ApplyDecision(std::vector<bool>(n, false), Nodes(ids), std::vector<double>(n, 0.0), o);
  EXPECT_EQ(f.added, n);
}

TEST(Decision, EmptyCandidateSetAndParsing) {
  al::DecisionOptions o;
  o.rule = al::ParseDecisionRule("percentile:95");
  std::vector<bool> R{true, false};
  const auto d = al::ApplyDecision(R, Nodes({}), {}, o);
  EXPECT_EQ(d.refined, R);
  EXPECT_TRUE(std::isnan(d.threshold));
  EXPECT_EQ(al::ParseDecisionRule("0.25").threshold, 0.25);
  EXPECT_EQ(al::ParseDecisionRule("percentile:90").ToString(), "percentile:90");
  EXPECT_THROW(al::ParseDecisionRule("percentile:101"), al::Error);
  EXPECT_THROW(al::ParseDecisionRule("abc"), al::Error);
  EXPECT_THROW(al::ParseDecisionRule("0.5x"), al::Error);
  EXPECT_THROW(al::ApplyDecision(R, Nodes({0}), {0.1, 0.2}, {}), al::Error);
}

}  // namespace
