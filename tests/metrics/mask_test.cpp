// IoU/acc conventions, nearest-neighbour rules and PIL-like luma conversion (METRICS.md §1).
#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/metrics/mask.hpp"

namespace al::metrics {
namespace {

Mask FromBits(int w, int h, std::vector<std::uint8_t> bits) { return {w, h, std::move(bits)}; }

TEST(Mask, IoUOfTwoEmptyMasksIsZero) {
  const Mask a = EmptyMask(4, 3), b = EmptyMask(4, 3);
  EXPECT_EQ(IoU(a, b), 0.0);
  EXPECT_EQ(AccIn(a, b), 0.0);
}

TEST(Mask, IoUAndAccHandComputed) {
  // A = {0,1,2}, B = {2,3}: ∩ = 1, ∪ = 4.
  const Mask a = FromBits(5, 1, {1, 1, 1, 0, 0}), b = FromBits(5, 1, {0, 0, 1, 1, 0});
  EXPECT_DOUBLE_EQ(IoU(a, b), 0.25);
  EXPECT_DOUBLE_EQ(AccIn(a, b), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(AccIn(b, a), 0.5);
  EXPECT_THROW(IoU(a, EmptyMask(4, 1)), Error);
}

TEST(Mask, NearestRulesDifferAsSpecified) {
  // in = 3, out = 2: floor → {0, 1}; exact → floor(0.75)=0, floor(2.25)=2.
  EXPECT_EQ(NearestSourceIndex(3, 2, ResizeRule::kFloor), (std::vector<int>{0, 1}));
  EXPECT_EQ(NearestSourceIndex(3, 2, ResizeRule::kExact), (std::vector<int>{0, 2}));
  // Upsampling 2 → 5: floor → 0,0,0,1,1 (d·2/5); exact → floor((d+.5)·0.4) = 0,0,1,1,1.
  EXPECT_EQ(NearestSourceIndex(2, 5, ResizeRule::kFloor), (std::vector<int>{0, 0, 0, 1, 1}));
  EXPECT_EQ(NearestSourceIndex(2, 5, ResizeRule::kExact), (std::vector<int>{0, 0, 1, 1, 1}));
  // Identity for equal sizes.
  EXPECT_EQ(NearestSourceIndex(4, 4, ResizeRule::kExact), (std::vector<int>{0, 1, 2, 3}));
}

TEST(Mask, ResizeUsesRowAndColumnRules) {
  const Gray8 g{2, 1, {10, 20}};
  const Gray8 up = Resize(g, 4, 2, ResizeRule::kFloor);
  EXPECT_EQ(up.pixels, (std::vector<std::uint8_t>{10, 10, 20, 20, 10, 10, 20, 20}));
}

TEST(Mask, BinarizeIsStrict) {
  const Gray8 g{4, 1, {0, 1, 128, 129}};
  EXPECT_EQ(Binarize(g, 0).bits, (std::vector<std::uint8_t>{0, 1, 1, 1}));
  EXPECT_EQ(Binarize(g, 128).bits, (std::vector<std::uint8_t>{0, 0, 0, 1}));
}

TEST(Mask, LumaOf16BitGreyIsClippedAndColourUsesPilWeights) {
  PngData grey16{3, 1, 1, 16, {0, 200, 65535}};
  bool lossy = false;
  EXPECT_EQ(ToLuma8(grey16, &lossy).pixels, (std::vector<std::uint8_t>{0, 200, 255}));
  EXPECT_TRUE(lossy);
  // (R·19595 + G·38470 + B·7471 + 32768) >> 16: pure red 255 → 76, green → 150, blue → 29.
  PngData rgb{3, 1, 3, 8, {255, 0, 0, 0, 255, 0, 0, 0, 255}};
  EXPECT_EQ(ToLuma8(rgb).pixels, (std::vector<std::uint8_t>{76, 150, 29}));
  PngData bits1{2, 1, 1, 1, {0, 1}};
  EXPECT_EQ(ToLuma8(bits1).pixels, (std::vector<std::uint8_t>{0, 255}));
  PngData bad{2, 2, 1, 8, {0}};
  EXPECT_THROW(ToLuma8(bad), Error);
}

}  // namespace
}  // namespace al::metrics
