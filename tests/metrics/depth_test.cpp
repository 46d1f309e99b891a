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

// ---- Depth holes (METRICS.md §4 step 1, issue 16). Hand-worked on an 8×4 image: background
// D1 = D2 = 100, the object the 2×2 block of pixels 10, 11, 18, 19. Released rule: Δ = D2 − D1 in
// float32, zeroed where Δ == D2 (D1 = 0) or Δ == −D1 computed in uint8 (256 − D1: never equal);
// "both" zeroes Δ == −D1 in signed arithmetic (D2 = 0). With |Δ| taking only the values 0 and M,
// the stretch gives index 255 → byte LUT[255] = 0 on the changed pixels and 255 elsewhere; two
// spikes at 0 and 255 tie on all 255 GHT splits, t = 127, changed = the byte-0 pixels.
constexpr int kHw = 8, kHh = 4;
const std::vector<std::size_t> kHoleObject = {10, 11, 18, 19};

struct HolePair {
  Gray8 before = Filled(kHw, kHh, 100), after = Filled(kHw, kHh, 100);
  Mask object = EmptyMask(kHw, kHh);
  HolePair() {
    for (std::size_t i : kHoleObject) object.bits[i] = 1;
  }
  void Set(std::initializer_list<std::size_t> pixels, std::uint8_t d1, std::uint8_t d2) {
    for (std::size_t i : pixels) before.pixels[i] = d1, after.pixels[i] = d2;
  }
  DepthScore Score(DepthHoles holes, DepthChange* out = nullptr) const {
    DepthChange c = DepthChange8Bit(before, after, {}, holes);
    if (out) *out = c;
    return ScoreDepthChange(&object, c.changed);
  }
};

TEST(DepthHoles, NamesRoundTrip) {
  EXPECT_EQ(DepthHolesFromName("before"), DepthHoles::kBefore);
  EXPECT_EQ(DepthHolesFromName("both"), DepthHoles::kBoth);
  EXPECT_FALSE(DepthHolesFromName("after").has_value());
  EXPECT_STREQ(DepthHolesName(DepthHoles::kBefore), "before");
}

TEST(DepthHoles, HolesBeforeOnlyAreZeroedByBothRules) {
  // Object 40 → 100 (|Δ| = 60); pixels 0-2 have no depth before and 180 after: Δ = 180 = D2, zeroed.
  // |Δ| ∈ {0, 60}: changed = the object. acc = 4/4, IoU = 4/4, collateral = 0/28.
  HolePair p;
  p.Set({10, 11, 18, 19}, 40, 100);
  p.Set({0, 1, 2}, 0, 180);
  for (DepthHoles h : {DepthHoles::kBefore, DepthHoles::kBoth}) {
    DepthChange c;
    const DepthScore s = p.Score(h, &c);
    EXPECT_EQ(c.threshold, 127.0);
    EXPECT_EQ(c.holes_before, 3u);
    EXPECT_EQ(c.holes_after, 0u);
    EXPECT_EQ(s.acc_delta_depth, 1.0);
    EXPECT_EQ(s.iou, 1.0);
    EXPECT_EQ(s.collateral_depth, 0.0);
  }
}

TEST(DepthHoles, HolesAfterOnlyCountAsChangeInTheReleasedRule) {
  // The object (40) and pixels 30, 31 (40) have no depth after. Released: Δ = −40, −D1 in uint8 is
  // 216, not zeroed: |Δ| = 40 on 6 pixels → changed = 6, acc = 4/4, IoU = 4/6, collateral = 2/28.
  // Both: every |Δ| is 0 → all bytes 255 → t = 127 → nothing below it → constant, no change.
  HolePair p;
  p.Set({10, 11, 18, 19, 30, 31}, 40, 0);
  DepthChange c;
  const DepthScore released = p.Score(DepthHoles::kBefore, &c);
  EXPECT_EQ(c.holes_after, 6u);
  EXPECT_EQ(c.changed.Count(), 6u);
  EXPECT_EQ(released.acc_delta_depth, 1.0);
  EXPECT_DOUBLE_EQ(released.iou, 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(released.collateral_depth, 2.0 / 28.0);
  const DepthScore both = p.Score(DepthHoles::kBoth, &c);
  EXPECT_TRUE(c.constant);
  EXPECT_EQ(both.acc_delta_depth, 0.0);
  EXPECT_EQ(both.iou, 0.0);
}

TEST(DepthHoles, HolesOnBothSides) {
  // Object pixels 10, 11: 90 → no depth (released |Δ| = 90); 18, 19: 30 → 120 (|Δ| = 90). Pixels
  // 0-2: no depth either side (Δ = 0). Pixels 5, 6: no depth before, 200 after (zeroed).
  // Released: |Δ| = 90 on the object only → acc 1, IoU 1. Both: only 18, 19 → acc 2/4, IoU 2/4.
  HolePair p;
  p.Set({10, 11}, 90, 0);
  p.Set({18, 19}, 30, 120);
  p.Set({0, 1, 2}, 0, 0);
  p.Set({5, 6}, 0, 200);
  DepthChange c;
  const DepthScore released = p.Score(DepthHoles::kBefore, &c);
  EXPECT_EQ(c.holes_before, 5u);
  EXPECT_EQ(c.holes_after, 2u);
  EXPECT_EQ(c.valid_pixels, 32u - 7u);
  EXPECT_EQ(released.acc_delta_depth, 1.0);
  EXPECT_EQ(released.iou, 1.0);
  const DepthScore both = p.Score(DepthHoles::kBoth);
  EXPECT_EQ(both.acc_delta_depth, 0.5);
  EXPECT_EQ(both.iou, 0.5);
  EXPECT_EQ(both.collateral_depth, 0.0);
}

TEST(DepthHoles, AVanishedObjectOutweighsASmallerRealChange) {
  // Object: 80 → no depth (released |Δ| = 80). Pixels 28-31: 60 → 100 (|Δ| = 40). Stretch: r = 1,
  // 0.5, 0 → index 255, 128, 0 → bytes 0, 127, 255 (128 is not one of the 38 exceptions), counts 4,
  // 4, 24. GHT by hand: splits 0..126 give {0} | {127, 255}: w0 = 4, d0 = 0, p0 = 1/8,
  // v0 = 125·300²/129, f0 = −4·ln v0 + 8·ln 4 = −34.41; w1 = 28, μ1 = 6628/28, d1 = 1625116 − 28·μ1²
  // = 56173.4, v1 = (875·300² + d1)/903, f1 = −d1/v1 − 28·ln v1 + 56·ln 28 = −132.59; sum −167.00.
  // Splits 127..254 give {0, 127} | {255}: −178.60. So t = mean(0..126) = 63, changed = the byte-0
  // object: acc 1, IoU 1, collateral 0. Both rule: only the real change is left (bytes 0 outside),
  // t = 127: acc 0, IoU 0, collateral 4/28.
  HolePair p;
  p.Set({10, 11, 18, 19}, 80, 0);
  p.Set({28, 29, 30, 31}, 60, 100);
  DepthChange c;
  const DepthScore released = p.Score(DepthHoles::kBefore, &c);
  EXPECT_EQ(c.image.pixels[10], 0);
  EXPECT_EQ(c.image.pixels[28], 127);
  EXPECT_EQ(c.image.pixels[0], 255);
  EXPECT_EQ(c.threshold, 63.0);
  EXPECT_EQ(released.acc_delta_depth, 1.0);
  EXPECT_EQ(released.iou, 1.0);
  EXPECT_EQ(released.collateral_depth, 0.0);
  const DepthScore both = p.Score(DepthHoles::kBoth, &c);
  EXPECT_EQ(c.threshold, 127.0);
  EXPECT_EQ(both.acc_delta_depth, 0.0);
  EXPECT_DOUBLE_EQ(both.collateral_depth, 4.0 / 28.0);
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

TEST(DepthFloat, AHitThatVanishesIsAChange) {
  // Object (15 px) at 4.8 before, no hit after; two pixels move 5 → 4 (Δ = 1 = R, bin 255).
  // kBefore: the object takes bin 255 too → spikes at 0 and 255, t = 127 → changed = 17 pixels.
  // kBoth: the object is ignored (bin 0) → only the two pixels change.
  const int w = 20, h = 10;
  DepthRender before = Plane(w, h, 5.0f), after = Plane(w, h, 5.0f);
  Mask object = EmptyMask(w, h);
  for (int y = 2; y < 5; ++y)
    for (int x = 3; x < 8; ++x) before.depth[y * w + x] = 4.8f, after.alpha[y * w + x] = 0.0f, object.bits[y * w + x] = 1;
  after.depth[0] = after.depth[1] = 4.0f;
  const DepthChange released = DepthChangeFloat(before, after);
  EXPECT_EQ(released.holes_after, 15u);
  EXPECT_EQ(released.image.pixels[2 * w + 3], 255);
  EXPECT_EQ(released.threshold, 127.0);
  const DepthScore s = ScoreDepthChange(&object, released.changed);
  EXPECT_EQ(s.acc_delta_depth, 1.0);
  EXPECT_DOUBLE_EQ(s.iou, 15.0 / 17.0);
  FloatDepthOptions both;
  both.holes = DepthHoles::kBoth;
  const DepthChange old = DepthChangeFloat(before, after, both);
  EXPECT_EQ(ScoreDepthChange(&object, old.changed).acc_delta_depth, 0.0);
  EXPECT_EQ(old.changed.Count(), 2u);
  // Nothing else changed: no scale from the hits (R = 0), the vanished object is still found.
  after.depth[0] = after.depth[1] = 5.0f;
  EXPECT_EQ(ScoreDepthChange(&object, DepthChangeFloat(before, after).changed).acc_delta_depth, 1.0);
  EXPECT_EQ(DepthChangeFloat(before, after, both).changed.Count(), 0u);
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
