// acc_Δdepth: LUT, GHT ties, 8-bit pipeline, float mode, 8-bit conversion, collateral damage
// (METRICS.md §4–§7, §10).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/metrics/collateral.hpp"
#include "al/metrics/depth.hpp"

namespace al::metrics {
namespace {

TEST(DepthLut, ThirtyEightExceptionalIndices) {
  const int exceptional[] = {43,  59,  75,  91,  107, 123, 133, 140, 141, 149, 156, 157, 165,
                             172, 173, 181, 188, 189, 197, 198, 204, 205, 206, 213, 214, 220,
                             221, 222, 229, 230, 236, 237, 238, 245, 246, 252, 253, 254};
  std::vector<bool> is_exc(256, false);
  for (int i : exceptional) is_exc[i] = true;
  const auto& lut = GrayReversedLut();
  int count = 0;
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(int(lut[i]), is_exc[i] ? 254 - i : 255 - i) << i;
    count += is_exc[i];
  }
  EXPECT_EQ(count, 38);
}

TEST(Ght, SpikesAtBothEndsTieOnEverySplit) {
  Histogram256 h{};
  h[0] = 500;
  h[255] = 300;
  EXPECT_DOUBLE_EQ(GhtThreshold(h), 127.0);
}

TEST(Ght, EqualSpikesTieOutsideTheGap) {
  Histogram256 h{};
  h[70] = 1000;
  h[215] = 1000;
  const double t = GhtThreshold(h);
  EXPECT_EQ(t, 107.22727272727273);
  // Independent: mean of 0..69 and 215..254.
  double sum = 0;
  int n = 0;
  for (int i = 0; i < 70; ++i) sum += i, ++n;
  for (int i = 215; i < 255; ++i) sum += i, ++n;
  EXPECT_DOUBLE_EQ(t, sum / n);
}

TEST(Ght, SeparatesTwoWellSpreadClusters) {
  Histogram256 h{};
  for (int j = 20; j < 40; ++j) h[j] = 50;
  for (int j = 200; j < 220; ++j) h[j] = 50;
  const double t = GhtThreshold(h);
  EXPECT_GE(t, 39.0);
  EXPECT_LT(t, 200.0);
}

Gray8 Filled(int w, int h, std::uint8_t v) { return {w, h, std::vector<std::uint8_t>(std::size_t(w) * h, v)}; }

TEST(Depth8Bit, ObjectSixtyLevelsCloserGivesFullScore) {
  const int w = 16, h = 12;
  Gray8 before = Filled(w, h, 100), after = Filled(w, h, 100);
  Mask object = EmptyMask(w, h);
  for (int y = 3; y < 7; ++y)
    for (int x = 4; x < 10; ++x) before.pixels[y * w + x] = 40, object.bits[y * w + x] = 1;
  const DepthChange c = DepthChange8Bit(before, after);
  EXPECT_FALSE(c.constant);
  EXPECT_DOUBLE_EQ(c.threshold, 127.0);  // bytes only 0 (object) and 255 (rest)
  EXPECT_EQ(c.image.pixels[3 * w + 4], 0);
  EXPECT_EQ(c.image.pixels[0], 255);
  const DepthScore s = ScoreDepthChange(&object, c.changed);
  EXPECT_DOUBLE_EQ(s.acc_delta_depth, 1.0);
  EXPECT_DOUBLE_EQ(s.iou, 1.0);
  EXPECT_DOUBLE_EQ(s.collateral_depth, 0.0);
}

TEST(Depth8Bit, ConstantDifferenceMeansNoChange) {
  const Gray8 before = Filled(5, 4, 10), after = Filled(5, 4, 30);  // |Δ| = 20 everywhere
  const DepthChange c = DepthChange8Bit(before, after);
  for (auto b : c.image.pixels) EXPECT_EQ(b, 255);
  EXPECT_EQ(c.changed.Count(), 0u);
  Mask object = EmptyMask(5, 4);
  object.bits[0] = 1;
  EXPECT_EQ(ScoreDepthChange(&object, c.changed).acc_delta_depth, 0.0);
}

TEST(Depth8Bit, ZeroDepthIsExcludedFromTheDifference) {
  Gray8 before = Filled(4, 1, 50), after = Filled(4, 1, 50);
  before.pixels[0] = 0;   // no depth before: Δ forced to 0 despite after = 50
  after.pixels[1] = 200;  // a real change
  const DepthChange c = DepthChange8Bit(before, after);
  EXPECT_EQ(c.valid_pixels, 3u);
  EXPECT_EQ(c.changed.bits, (std::vector<std::uint8_t>{0, 1, 0, 0}));
}

TEST(Depth8Bit, PixelExactlyAtIntegralThresholdIsUnchanged) {
  // Bytes 255 (unchanged) and a byte equal to t would not count; with spikes at 0 and 255 t = 127,
  // a pixel of byte exactly 127 cannot occur, so check the strictness on the rule itself.
  Gray8 before = Filled(2, 1, 10), after = Filled(2, 1, 10);
  after.pixels[0] = 70;
  const DepthChange c = DepthChange8Bit(before, after);
  for (std::size_t i = 0; i < c.changed.bits.size(); ++i)
    EXPECT_EQ(c.changed.bits[i] != 0, double(c.image.pixels[i]) < c.threshold);
  EXPECT_THROW(DepthChange8Bit(Filled(2, 1, 1), Filled(1, 2, 1)), Error);
}

TEST(DepthScore, MissingObjectCountsWithZeroAndSizesUseTheExactRule) {
  Mask changed = EmptyMask(4, 1);
  changed.bits = {0, 0, 1, 1};
  const DepthScore missing = ScoreDepthChange(nullptr, changed);
  EXPECT_TRUE(missing.missing_object);
  EXPECT_EQ(missing.acc_delta_depth, 0.0);
  EXPECT_EQ(missing.iou, 0.0);
  // Object at a third of the width: exact rule picks source pixels floor((d+.5)·4/3) = 0, 2, 3.
  Mask object = EmptyMask(3, 1);
  object.bits = {0, 1, 0};
  const DepthScore s = ScoreDepthChange(&object, changed);
  EXPECT_DOUBLE_EQ(s.acc_delta_depth, 1.0);  // with the floor rule (src 0,1,2) it would be 0
  EXPECT_DOUBLE_EQ(s.iou, 0.5);
  EXPECT_DOUBLE_EQ(s.collateral_depth, 0.5);  // one of the two non-object pixels changed
}

DepthRender Plane(int w, int h, float z) {
  return {w, h, std::vector<float>(std::size_t(w) * h, z), std::vector<float>(std::size_t(w) * h, 1.0f)};
}

TEST(DepthFloat, ObjectInFrontIsFoundWithMaxdiff) {
  const int w = 20, h = 10;
  DepthRender before = Plane(w, h, 5.0f), after = Plane(w, h, 5.0f);
  Mask object = EmptyMask(w, h);
  for (int y = 2; y < 5; ++y)
    for (int x = 3; x < 8; ++x) before.depth[y * w + x] = 4.8f, object.bits[y * w + x] = 1;
  const DepthChange c = DepthChangeFloat(before, after);
  EXPECT_EQ(c.image.pixels[2 * w + 3], 255);  // the largest change maps to bin 255
  EXPECT_EQ(c.image.pixels[0], 0);
  const DepthScore s = ScoreDepthChange(&object, c.changed);
  EXPECT_DOUBLE_EQ(s.acc_delta_depth, 1.0);
  EXPECT_DOUBLE_EQ(s.iou, 1.0);
}

TEST(DepthFloat, RangeNormaliserMissesSmallChangesAndNoHitMeansNoChange) {
  const int w = 20, h = 10;
  DepthRender before = Plane(w, h, 5.0f), after = Plane(w, h, 5.0f);
  before.depth[0] = 1.0f;  // stretches the joint range to [1, 5]
  after.depth[0] = 1.0f;
  before.depth[5] = 4.9f;  // a change of 2.5 % of the range: below GHT's reach (METRICS.md §5)
  FloatDepthOptions range;
  range.depth_norm = DepthNorm::kRange;
  EXPECT_EQ(DepthChangeFloat(before, after, range).changed.Count(), 0u);
  EXPECT_EQ(DepthChangeFloat(before, after).changed.bits[5], 1);  // maxdiff puts it at bin 255
  DepthRender empty = Plane(w, h, 5.0f);
  for (auto& a : empty.alpha) a = 0.0f;  // no hit anywhere
  const DepthChange none = DepthChangeFloat(empty, empty);
  EXPECT_TRUE(none.constant);
  EXPECT_EQ(none.changed.Count(), 0u);
}

TEST(DepthTo8Bit, JointScaleAndZeroForMisses) {
  DepthRender before{3, 1, {2.0f, 4.0f, 3.0f}, {1, 1, 0}};  // pixel 2 is not a hit
  DepthRender after{3, 1, {6.0f, std::numeric_limits<float>::quiet_NaN(), 2.0f}, {1, 1, 1}};
  const Depth8Pair p = DepthTo8Bit(before, after);
  EXPECT_DOUBLE_EQ(p.zmin, 2.0);
  EXPECT_DOUBLE_EQ(p.zmax, 6.0);
  // 1 + floor(254·(z − 2)/4 + 0.5): z = 2 → 1, 4 → 128, 6 → 255.
  EXPECT_EQ(p.before.pixels, (std::vector<std::uint8_t>{1, 128, 0}));
  EXPECT_EQ(p.after.pixels, (std::vector<std::uint8_t>{255, 0, 1}));
  EXPECT_EQ(p.hits_before, 2u);
  EXPECT_EQ(p.hits_after, 2u);
  const Depth8Pair flat = DepthTo8Bit(Plane(2, 1, 3.0f), Plane(2, 1, 3.0f));
  EXPECT_EQ(flat.before.pixels, (std::vector<std::uint8_t>{1, 1}));
}

TEST(Collateral, PsnrOverTheNonObjectRegionOnly) {
  RgbImage before{2, 1, {0.5f, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f}};
  RgbImage after{2, 1, {0.6f, 0.6f, 0.6f, 0.9f, 0.9f, 0.9f}};
  Mask object = EmptyMask(2, 1);
  object.bits[1] = 1;  // the big change is inside the object: ignored
  const CollateralPsnr p = ComputeCollateralPsnr(before, after, &object);
  ASSERT_TRUE(p.psnr.has_value());
  EXPECT_EQ(p.pixels, 1u);
  const double mse = std::pow(double(0.6f) - double(0.5f), 2);
  EXPECT_NEAR(*p.psnr, 10 * std::log10(1 / mse), 1e-9);
  const CollateralPsnr same = ComputeCollateralPsnr(before, before, nullptr);
  EXPECT_TRUE(same.identical);
  EXPECT_FALSE(same.psnr.has_value());
  RgbImage clipped{1, 1, {1.5f, 2.0f, -1.0f}}, at_bounds{1, 1, {1.0f, 1.0f, 0.0f}};
  EXPECT_TRUE(ComputeCollateralPsnr(clipped, at_bounds, nullptr).identical);  // clamped to [0, 1]
}

}  // namespace
}  // namespace al::metrics
