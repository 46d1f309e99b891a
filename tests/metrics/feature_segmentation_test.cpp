// Nearest-prototype segmentation of a feature image and the feature metrics on hand-made masks.
#include <vector>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/metrics/feature_segmentation.hpp"

namespace al::metrics {
namespace {

Prototypes ThreePrototypes() {
  Prototypes p;
  p.rows.resize(3, 3);
  p.rows << 1, 0, 0,  // other
      0, 1, 0,        // target
      -1, 0, 0;       // other
  p.target = 1;
  return p;
}

// One row of pixels, 3 channels: each pixel's feature and alpha chosen to hit one rule.
TEST(FeatureSegmentation, NearestPrototypeWithFloors) {
  const std::vector<float> feature = {
      0.0f, 2.0f, 0.0f,    // 0: the target's direction (any length)              -> target
      0.6f, 0.8f, 0.0f,    // 1: cos 0.8 to target, 0.6 to "other"                -> target
      0.8f, 0.6f, 0.0f,    // 2: closer to "other"                                -> not
      0.5f, 0.5f, 0.0f,    // 3: a tie with "other" (strict rule)                 -> not
      0.2f, 0.4f, 0.9f,    // 4: nearest is the target, but cos 0.40 < 0.5        -> not
      0.0f, 1.0f, 0.0f,    // 5: target, but alpha below 0.5                      -> not
      0.0f, 0.0f, 0.0f,    // 6: no feature                                       -> not
      -0.3f, 0.95f, 0.1f,  // 7: target (nearest, cos 0.95), alpha exactly 0.5    -> target
  };
  const std::vector<float> alpha = {1, 0.9f, 1, 1, 1, 0.4f, 1, 0.5f};
  const FeatureImage image{8, 1, 3, feature.data(), alpha.data()};
  const Mask m = SegmentTarget(image, ThreePrototypes(), {});
  EXPECT_EQ(m.bits, (std::vector<std::uint8_t>{1, 1, 0, 0, 0, 0, 0, 1}));
  FeatureSegOptions loose;
  loose.min_similarity = 0.35;
  loose.min_alpha = 0.3;
  EXPECT_EQ(SegmentTarget(image, ThreePrototypes(), loose).bits, (std::vector<std::uint8_t>{1, 1, 0, 0, 1, 1, 0, 1}));
}

TEST(FeatureSegmentation, BadInputThrows) {
  const std::vector<float> feature(6, 0.0f), alpha(3, 1.0f);
  Prototypes p = ThreePrototypes();
  EXPECT_THROW(SegmentTarget({3, 1, 2, feature.data(), alpha.data()}, p, {}), Error);  // dim mismatch
  p.target = 3;
  EXPECT_THROW(SegmentTarget({2, 1, 3, feature.data(), alpha.data()}, p, {}), Error);
  FeatureSegOptions o;
  o.min_similarity = 1.5;
  EXPECT_THROW(o.Check(), Error);
}

Mask FromBits(std::vector<std::uint8_t> bits) { return {int(bits.size()), 1, std::move(bits)}; }

TEST(FeatureSegmentation, ScoresAndResidual) {
  const Mask object = FromBits({1, 1, 1, 1, 0, 0});
  const Mask before = FromBits({1, 1, 1, 0, 1, 0});  // 3 object pixels segmented, 1 outside
  const Mask after = FromBits({0, 1, 0, 1, 1, 0});   // 1 of those 3 left; a new one; the outside one stays
  const FeatureRecord r = ScoreFeatureSegmentation(object, before, after, "v");
  EXPECT_EQ(r.before_pixels, 3u);
  EXPECT_EQ(r.residual_pixels, 1u);
  EXPECT_DOUBLE_EQ(r.residual, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(r.semantic.iou_before, 3.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.semantic.iou_after, 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.semantic.iou_drop, 0.2);
  EXPECT_DOUBLE_EQ(r.semantic.acc_before, 0.75);
  EXPECT_DOUBLE_EQ(r.semantic.acc_after, 0.5);
  // Nothing segmented before: residual undefined, reported as 0 and left out of the mean.
  const FeatureRecord none = ScoreFeatureSegmentation(object, FromBits({0, 0, 0, 0, 1, 1}), after);
  EXPECT_EQ(none.before_pixels, 0u);
  const FeatureSummary s = SummarizeFeature({r, none});
  EXPECT_EQ(s.semantic.images, 2u);
  EXPECT_EQ(s.residual.count, 1u);
  EXPECT_DOUBLE_EQ(s.residual.mean, 1.0 / 3.0);
  EXPECT_EQ(s.views_without_target, 1u);
  EXPECT_THROW(ScoreFeatureSegmentation(object, FromBits({1}), after), Error);
}

}  // namespace
}  // namespace al::metrics
