// Decision rules: fixed threshold, nearest-rank percentile with plateaus, restore, parsing.
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

TEST(Decision, FixedThresholdAddsOnlyUnlessRestore) {
  std::vector<bool> R{true, true, false, false, false, true};
  const auto prob = Nodes({0, 1, 2, 3, 5});
  const std::vector<double> p{1.0, 0.2, 0.5, 0.49, 0.0};
  const auto d = al::ApplyDecision(R, prob, p);
  EXPECT_EQ(d.refined, (std::vector<bool>{true, true, true, false, false, true}));
  EXPECT_EQ(d.added, 1u);
  EXPECT_EQ(d.restored, 0u);
  EXPECT_EQ(d.at_threshold, 1u);
  al::DecisionOptions o;
  o.restore = true;
  const auto r = al::ApplyDecision(R, prob, p, o);
  EXPECT_EQ(r.refined, (std::vector<bool>{true, false, true, false, false, false}));
  EXPECT_EQ(r.restored, 2u);
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
