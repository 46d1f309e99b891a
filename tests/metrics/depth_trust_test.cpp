// acc_Δdepth trust flags (depth_trust.hpp): each flag on a case built to raise it alone, none on a
// clean removal, and the summary's trusted mean and flag lists.
#include <gtest/gtest.h>

#include "al/metrics/depth.hpp"

namespace al::metrics {
namespace {

constexpr int kW = 40, kH = 30;  // 1200 px; the object is the 20×15 block at (10, 5): 300 px

Gray8 Filled(std::uint8_t v) { return {kW, kH, std::vector<std::uint8_t>(kW * kH, v)}; }

bool InObject(int x, int y) { return x >= 10 && x < 30 && y >= 5 && y < 20; }

Mask ObjectMask() {
  Mask m = EmptyMask(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) m.bits[y * kW + x] = InObject(x, y);
  return m;
}

// Before: background 200, the object at `object_before`; after: background 200 everywhere, then
// `extra` pixels outside the object changed to 200 - `extra_change`.
DepthTrust Assess(std::uint8_t object_before, int extra, std::uint8_t extra_change, DepthTrustOptions o = {}) {
  Gray8 before = Filled(200), after = Filled(200);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (InObject(x, y)) before.pixels[y * kW + x] = object_before;
  for (int i = 1; i <= extra; ++i) after.pixels[kW * kH - i] = std::uint8_t(200 - extra_change);  // rows 20-29
  const Mask object = ObjectMask();
  return AssessDepthTrust(&object, DepthChange8Bit(before, after), o);
}

TEST(DepthTrust, CleanRemovalRaisesNothing) {
  const DepthTrust t = Assess(100, 0, 0);  // the object (|Δ| = 100) is the only change
  EXPECT_TRUE(t.Trusted()) << t.ToJson().dump();
  EXPECT_EQ(t.object_pixels, 300);
  EXPECT_EQ(t.outside_share, 0.0);
  EXPECT_EQ(t.object_peak, 1.0);
  EXPECT_EQ(t.object_median, 1.0);
}

TEST(DepthTrust, SmallObject) {
  DepthTrustOptions o;
  o.min_object_pixels = 301;
  const DepthTrust t = Assess(100, 0, 0, o);
  EXPECT_EQ(t.Flags(), std::vector<std::string>{"small_object"});
  const DepthTrust missing = AssessDepthTrust(nullptr, DepthChange8Bit(Filled(9), Filled(9)));
  EXPECT_TRUE(missing.small_object);  // a missing object mask is an empty object
  EXPECT_EQ(missing.object_pixels, 0);
}

TEST(DepthTrust, ChangeOutsideTheObject) {
  // 320 outside pixels change as much as the object (300 px): 320 / 620 of the change is outside.
  const DepthTrust t = Assess(100, 320, 100);
  EXPECT_EQ(t.Flags(), std::vector<std::string>{"change_outside_object"});
  EXPECT_DOUBLE_EQ(t.outside_share, 320.0 / 620.0);
  EXPECT_TRUE(Assess(100, 280, 100).Trusted());  // 280 / 580 < 1/2
}

TEST(DepthTrust, StretchSetOutsideTheObject) {
  // 10 outside pixels change by 160, the object by 100: the object's peak is 100/160 = 0.625 of the
  // stretch (< 3/4); its median the same (not compressed, >= 1/4).
  const DepthTrust t = Assess(100, 10, 160);
  EXPECT_TRUE(t.stretch_outside_object) << t.ToJson().dump();
  EXPECT_FALSE(t.object_change_compressed);
  EXPECT_NEAR(t.object_peak, 100.0 / 160.0, 1e-6);
  // At 100/130 = 0.77 the stretch flag stays down, yet GHT splits the 10 pixels off alone (the
  // object's bytes ~58 fall on the "unchanged" side): acc 0, caught as change outside the object.
  const DepthTrust near = Assess(100, 10, 130);
  EXPECT_EQ(near.Flags(), std::vector<std::string>{"change_outside_object"}) << near.ToJson().dump();
}

TEST(DepthTrust, CompressedObjectChange) {
  // The object moves by 10, except one of its pixels by 190: peak 1, median 10/190 < 1/4.
  Gray8 before = Filled(200), after = Filled(200);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (InObject(x, y)) before.pixels[y * kW + x] = 190;
  before.pixels[5 * kW + 10] = 10;
  const Mask object = ObjectMask();
  const DepthTrust t = AssessDepthTrust(&object, DepthChange8Bit(before, after));
  EXPECT_EQ(t.Flags(), std::vector<std::string>{"object_change_compressed"});
  EXPECT_EQ(t.object_peak, 1.0);
  EXPECT_NEAR(t.object_median, 10.0 / 190.0, 1e-6);
}

TEST(DepthTrust, UnchangedObjectIsNotFlaggedForTheStretch) {
  // Only outside pixels change: acc = 0 is right whatever the stretch (no stretch/compress flags),
  // but every changed pixel is outside.
  const DepthTrust t = Assess(200, 50, 100);
  EXPECT_EQ(t.Flags(), std::vector<std::string>{"change_outside_object"});
  EXPECT_EQ(t.object_peak, 0.0);
}

TEST(DepthTrust, OptionsCheckAndSummary) {
  DepthTrustOptions bad;
  bad.max_outside_share = 1.5;
  EXPECT_FALSE(bad.Check().empty());
  EXPECT_TRUE(DepthTrustOptions{}.Check().empty());
  std::vector<DepthRecord> records(3);
  records[0].image = "a", records[0].score.acc_delta_depth = 0.8;
  records[1].image = "b", records[1].score.acc_delta_depth = 0.1, records[1].trust.small_object = true;
  records[2].image = "c", records[2].score.acc_delta_depth = 0.6;
  const DepthSummary s = SummarizeDepth(records);
  EXPECT_DOUBLE_EQ(s.acc_delta_depth.mean, 0.5);
  EXPECT_DOUBLE_EQ(s.acc_delta_depth_trusted.mean, 0.7);
  ASSERT_EQ(s.flagged.size(), 1u);
  EXPECT_EQ(s.flagged[0].first, "b");
  const auto j = s.ToJson("view");
  EXPECT_EQ(j["trust"]["flagged_views"], 1);
  EXPECT_EQ(j["trust"]["flag_counts"]["small_object"], 1);
  EXPECT_EQ(j["trust"]["flagged"][0]["view"], "b");
}

}  // namespace
}  // namespace al::metrics
