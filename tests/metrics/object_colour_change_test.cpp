// ObjectColourChange: hand-computed values, the PNG clamp, empty masks and size checks.
#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/metrics/object_colour_change.hpp"

namespace al::metrics {
namespace {

RgbImage Uniform(int w, int h, float r, float g, float b) {
  RgbImage img{w, h, {}};
  for (int p = 0; p < w * h; ++p) img.rgb.insert(img.rgb.end(), {r, g, b});
  return img;
}

Mask FirstPixels(int w, int h, int n) {
  Mask m{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 0)};
  for (int p = 0; p < n; ++p) m.bits[p] = 1;
  return m;
}

TEST(ObjectColourChange, MeanAbsoluteDifferenceOverTheObjectOnly) {
  RgbImage before = Uniform(4, 2, 0.2f, 0.4f, 0.6f), after = before;
  // Object pixel 0: changes by (0.3, 0.3, 0.0) -> 0.2; pixel 1 unchanged -> 0; a non-object pixel
  // changes completely and must not count.
  after.rgb[0] = 0.5f;
  after.rgb[1] = 0.1f;
  for (int c = 0; c < 3; ++c) after.rgb[3 * 7 + c] = 1.0f - before.rgb[3 * 7 + c];
  const auto v = ObjectColourChange(before, after, FirstPixels(4, 2, 2));
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(*v, (0.2 + 0.0) / 2.0, 1e-6);
}

TEST(ObjectColourChange, ValuesAreClampedAsAPngHoldsThem) {
  const RgbImage before = Uniform(1, 1, 1.8f, -0.5f, 0.5f), after = Uniform(1, 1, 1.0f, 0.0f, 0.5f);
  EXPECT_NEAR(*ObjectColourChange(before, after, FirstPixels(1, 1, 1)), 0.0, 1e-12);
}

TEST(ObjectColourChange, EmptyMaskIsUndefinedAndSizesMustAgree) {
  const RgbImage img = Uniform(3, 3, 0.1f, 0.2f, 0.3f);
  EXPECT_FALSE(ObjectColourChange(img, img, FirstPixels(3, 3, 0)).has_value());
  EXPECT_THROW(ObjectColourChange(img, Uniform(2, 3, 0, 0, 0), FirstPixels(3, 3, 1)), Error);
}

}  // namespace
}  // namespace al::metrics
