// ObjectColourChange: hand-computed values, the PNG clamp, empty masks and size checks.
#include <gtest/gtest.h>

#include <vector>

#include "al/core/error.hpp"
#include "al/metrics/object_colour_change.hpp"

namespace al::metrics {
namespace {

std::vector<float> Uniform(int w, int h, float r, float g, float b) {
  std::vector<float> rgb;
  for (int p = 0; p < w * h; ++p) rgb.insert(rgb.end(), {r, g, b});
  return rgb;
}

Mask FirstPixels(int w, int h, int n) {
  Mask m{w, h, std::vector<std::uint8_t>(std::size_t(w) * h, 0)};
  for (int p = 0; p < n; ++p) m.bits[p] = 1;
  return m;
}

TEST(ObjectColourChange, MeanAbsoluteDifferenceOverTheObjectOnly) {
  std::vector<float> before = Uniform(4, 2, 0.2f, 0.4f, 0.6f), after = before;
  // Object pixel 0: changes by (0.3, 0.3, 0.0) -> 0.2; pixel 1 unchanged -> 0; a non-object pixel
  // changes completely and must not count.
  after[0] = 0.5f;
  after[1] = 0.1f;
  for (int c = 0; c < 3; ++c) after[3 * 7 + c] = 1.0f - before[3 * 7 + c];
  const auto v = ObjectColourChange(before, after, FirstPixels(4, 2, 2));
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(*v, (0.2 + 0.0) / 2.0, 1e-6);
}

TEST(ObjectColourChange, ValuesAreClampedAsAPngHoldsThem) {
  const std::vector<float> before = Uniform(1, 1, 1.8f, -0.5f, 0.5f), after = Uniform(1, 1, 1.0f, 0.0f, 0.5f);
  EXPECT_NEAR(*ObjectColourChange(before, after, FirstPixels(1, 1, 1)), 0.0, 1e-12);
}

TEST(ObjectColourChange, EmptyMaskIsUndefinedAndSizesMustAgree) {
  const std::vector<float> img = Uniform(3, 3, 0.1f, 0.2f, 0.3f);
  EXPECT_FALSE(ObjectColourChange(img, img, FirstPixels(3, 3, 0)).has_value());
  EXPECT_THROW(ObjectColourChange(img, Uniform(2, 3, 0, 0, 0), FirstPixels(3, 3, 1)), Error);
}

}  // namespace
}  // namespace al::metrics
