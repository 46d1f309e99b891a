// Hungarian assignment vs brute-force enumeration, and sim_SAM hand cases (METRICS.md §3, §10).
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "al/metrics/hungarian.hpp"
#include "al/metrics/sim_sam.hpp"

namespace al::metrics {
namespace {

TEST(Hungarian, MatchesBruteForceOnRandomRectangularMatrices) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> dim(1, 7), level(0, 10);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const int n = dim(rng), m = dim(rng);
    std::vector<double> w(std::size_t(n) * m);
    // Half the trials quantised to tenths (many ties and zeros), half continuous.
    for (double& v : w) v = trial % 2 ? level(rng) / 10.0 : uni(rng);
    const Assignment a = MaxWeightAssignment(w, n, m);
    const double brute = MaxWeightAssignmentBruteForce(w, n, m);
    ASSERT_NEAR(a.total, brute, 1e-12) << n << "x" << m << " trial " << trial;
    std::set<int> cols;
    int assigned = 0;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      if (a.row_to_col[i] < 0) continue;
      ++assigned;
      ASSERT_LT(a.row_to_col[i], m);
      cols.insert(a.row_to_col[i]);
      sum += w[std::size_t(i) * m + a.row_to_col[i]];
    }
    EXPECT_EQ(assigned, std::min(n, m));
    EXPECT_EQ(int(cols.size()), assigned);  // one-to-one
    EXPECT_DOUBLE_EQ(sum, a.total);
  }
}

TEST(Hungarian, KnownRectangularCase) {
  // Greedy would take 0.9 (row 0, col 0) and then 0.1; the optimum is 0.8 + 0.85.
  const std::vector<double> w = {0.9, 0.8, 0.0,  //
                                 0.85, 0.1, 0.0};
  const Assignment a = MaxWeightAssignment(w, 2, 3);
  EXPECT_DOUBLE_EQ(a.total, 1.65);
  EXPECT_EQ(a.row_to_col, (std::vector<int>{1, 0}));
  // The transpose gives the same optimum.
  const std::vector<double> t = {0.9, 0.85, 0.8, 0.1, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(MaxWeightAssignment(t, 3, 2).total, 1.65);
  EXPECT_TRUE(MaxWeightAssignment({}, 0, 4).row_to_col.empty());
}

Mask Span(int width, int begin, int end) {
  Mask m = EmptyMask(width, 1);
  for (int x = begin; x < end; ++x) m.bits[x] = 1;
  return m;
}

TEST(SimSam, HandCaseTwoByThree) {
  const Gray8 object{20, 1, std::vector<std::uint8_t>(20, 255)};
  // Side A: a tiny segment (IoU 0.05 with the object, filtered out), then [0,10) and [10,20).
  const std::vector<Mask> a = {Span(20, 0, 1), Span(20, 0, 10), Span(20, 10, 20)};
  // Side B: [0,10) (IoU 1 with a0), [10,14) (0.4 with a1), [14,16) (IoU exactly 0.1 with the
  // object: kept, the filter is inclusive; 0.2 with a1).
  const std::vector<Mask> b = {Span(20, 0, 10), Span(20, 10, 14), Span(20, 14, 16)};
  const SimSamResult r = ComputeSimSam(object, a, b);
  ASSERT_TRUE(r.scored);
  EXPECT_EQ(r.n_gt, 2);
  EXPECT_EQ(r.n_sam, 3);
  EXPECT_NEAR(r.sim_sam, 1.4 / 3.0, 1e-15);
  EXPECT_NEAR(r.sim_sam, 0.4667, 5e-5);
  ASSERT_EQ(r.matches.size(), 2u);
  EXPECT_EQ(r.matches[0].gt_idx, 0);  // indices into the filtered list
  EXPECT_EQ(r.matches[0].sam_idx, 0);
  EXPECT_DOUBLE_EQ(r.matches[0].iou, 1.0);
  EXPECT_EQ(r.matches[1].gt_idx, 1);
  EXPECT_EQ(r.matches[1].sam_idx, 1);
  EXPECT_DOUBLE_EQ(r.matches[1].iou, 0.4);
  // Symmetric in A and B.
  EXPECT_NEAR(ComputeSimSam(object, b, a).sim_sam, r.sim_sam, 1e-15);
}

TEST(SimSam, EmptyFilteredSideDropsTheImage) {
  const Gray8 object{20, 1, std::vector<std::uint8_t>(20, 255)};
  const SimSamResult r = ComputeSimSam(object, {Span(20, 0, 10)}, {Span(20, 0, 1)});
  EXPECT_FALSE(r.scored);
  EXPECT_EQ(r.n_gt, 1);
  EXPECT_EQ(r.n_sam, 0);
}

TEST(SimSam, ObjectMaskIsBinarisedAbove128AndSegmentsResizedWithFloorRule) {
  // Object value 128 is background for sim_SAM (strict > 128): only pixels 0..3 are object.
  Gray8 object{8, 1, {255, 255, 255, 255, 128, 128, 128, 128}};
  // A 4-wide segment [0,2) at half resolution covers [0,4) after the floor-rule upsampling.
  const Mask half = Span(4, 0, 2);
  // [4,8) has IoU 0 with the > 128 object (filtered); with a > 0 object it would be kept (M = 2).
  const SimSamResult r = ComputeSimSam(object, {half}, {Span(8, 0, 4), Span(8, 4, 8)});
  ASSERT_TRUE(r.scored);
  EXPECT_EQ(r.n_sam, 1);
  EXPECT_DOUBLE_EQ(r.sim_sam, 1.0);
}

TEST(SimSam, ZeroIoUPairsAddNothingAndAreNotListed) {
  const Gray8 object{20, 1, std::vector<std::uint8_t>(20, 255)};
  const SimSamResult r = ComputeSimSam(object, {Span(20, 0, 10)}, {Span(20, 10, 20)});
  ASSERT_TRUE(r.scored);
  EXPECT_EQ(r.sim_sam, 0.0);
  EXPECT_TRUE(r.matches.empty());
}

}  // namespace
}  // namespace al::metrics
