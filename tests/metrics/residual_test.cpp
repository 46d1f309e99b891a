// Residuals on hand-made images (al/metrics/residual.hpp): the definition's known answers
// (perfect removal 0, none 1, half the footprint left 0.5), its edges (threshold, min(1, ·),
// |O| < 64, clamping, NaN) and residual_px's per-pixel tolerances, holes and empty/full masks.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/metrics/residual.hpp"

namespace al::metrics {
namespace {

constexpr int kW = 16, kH = 8;  // 128 pixels
constexpr std::size_t kN = std::size_t(kW) * kH;

std::vector<float> Fill(float r, float g, float b) {
  std::vector<float> img(3 * kN);
  for (std::size_t p = 0; p < kN; ++p) {
    img[3 * p] = r;
    img[3 * p + 1] = g;
    img[3 * p + 2] = b;
  }
  return img;
}

void SetPixel(std::vector<float>& img, std::size_t p, float r, float g, float b) {
  img[3 * p] = r;
  img[3 * p + 1] = g;
  img[3 * p + 2] = b;
}

// The object (red) covers the left 8 columns (64 pixels) in front of a grey wall.
struct Scene {
  std::vector<float> before = Fill(0.5f, 0.5f, 0.5f), ideal = Fill(0.5f, 0.5f, 0.5f);
  Scene() {
    for (std::size_t p = 0; p < kN; ++p)
      if (p % kW < 8) SetPixel(before, p, 1.0f, 0.0f, 0.0f);
  }
};

ViewResidual Score(const Scene& s, const std::vector<float>& after, const ResidualOptions& o = {},
                   std::vector<float>* share = nullptr) {
  return ComputeResidual({kW, kH, s.before, after, s.ideal}, o, share);
}

TEST(Residual, PerfectRemovalIsZeroNoRemovalIsOneHalfIsHalf) {
  const Scene s;
  const ViewResidual perfect = Score(s, s.ideal), none = Score(s, s.before);
  ASSERT_TRUE(perfect.value && none.value);
  EXPECT_EQ(perfect.pixels, 64u);
  EXPECT_EQ(*perfect.value, 0.0);
  EXPECT_EQ(*none.value, 1.0);
  std::vector<float> half = s.ideal;  // the object's top half (rows 0-3) still there
  for (std::size_t p = 0; p < kN / 2; ++p)
    if (p % kW < 8) SetPixel(half, p, 1.0f, 0.0f, 0.0f);
  EXPECT_DOUBLE_EQ(*Score(s, half).value, 0.5);
  // A faded object (a quarter of the way from the wall's colour to red) leaves a quarter.
  std::vector<float> faded = s.ideal;
  for (std::size_t p = 0; p < kN; ++p)
    if (p % kW < 8) SetPixel(faded, p, 0.625f, 0.375f, 0.375f);
  EXPECT_NEAR(*Score(s, faded).value, 0.25, 1e-6);
}

TEST(Residual, FootprintThresholdRatioClipAndShare) {
  Scene s;
  SetPixel(s.before, 8, 0.55f, 0.5f, 0.5f);  // outside the object: 0.05 from the ideal, not in O
  SetPixel(s.before, 9, 0.7f, 0.5f, 0.5f);   // 0.2 from the ideal: in O
  std::vector<float> after = s.ideal;
  SetPixel(after, 9, 0.0f, 0.0f, 0.0f);  // farther from the ideal than before was: clipped to 1
  std::vector<float> share;
  const ViewResidual r = Score(s, after, {}, &share);
  EXPECT_EQ(r.pixels, 65u);
  EXPECT_NEAR(*r.value, 1.0 / 65.0, 1e-12);
  ASSERT_EQ(share.size(), kN);
  EXPECT_EQ(share[8], -1.0f);
  EXPECT_EQ(share[9], 1.0f);
  EXPECT_EQ(share[0], 0.0f);
  ResidualOptions wide;
  wide.footprint = 0.6;  // only pixels farther than 0.6 from the ideal (red vs grey: 0.866)
  EXPECT_EQ(Score(s, after, wide).pixels, 64u);
}

TEST(Residual, SmallFootprintsAreNotScored) {
  const Scene s;
  ResidualOptions o;
  o.min_pixels = 65;  // the footprint has 64
  const ViewResidual small = Score(s, s.before, o);
  EXPECT_FALSE(small.value.has_value());
  EXPECT_EQ(small.pixels, 64u);
  o.min_pixels = 64;  // at the limit it counts
  EXPECT_TRUE(Score(s, s.before, o).value.has_value());
  // Nothing of the object in view: no footprint, no value.
  const std::vector<float> grey = Fill(0.5f, 0.5f, 0.5f);
  const ViewResidual empty = ComputeResidual({kW, kH, grey, grey, grey}, {});
  EXPECT_EQ(empty.pixels, 0u);
  EXPECT_FALSE(empty.value.has_value());
  EXPECT_FALSE(ComputeResidual({0, 0, {}, {}, {}}, {}).value.has_value());
}

TEST(Residual, ColoursAreClampedAndNonFiniteReadAsZero) {
  Scene s;
  std::vector<float> after = s.ideal;
  SetPixel(s.before, 0, 5.0f, -3.0f, 0.0f);  // reads as (1, 0, 0): same as the other object pixels
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  SetPixel(after, 1, nan, nan, nan);  // reads as black: 0.866 from the ideal, before 0.866 -> 1
  SetPixel(after, 2, inf, 0.0f, 0.0f);  // reads as black too
  const ViewResidual r = Score(s, after);
  ASSERT_TRUE(r.value);
  EXPECT_TRUE(std::isfinite(*r.value));
  EXPECT_EQ(r.pixels, 64u);
  EXPECT_NEAR(*r.value, 2.0 / 64.0, 1e-12);  // pixels 1 and 2 read as fully left
  const std::vector<float> wrong(5);
  EXPECT_THROW(ComputeResidual({kW, kH, s.before, wrong, s.ideal}, {}), Error);
}

struct Depths {
  std::vector<float> rgb, depth, alpha;
  PixelRender View() const { return {rgb, depth, alpha}; }
};

Depths Flat(float r, float z, float a = 1.0f) {
  return {Fill(r, 0.2f, 0.2f), std::vector<float>(kN, z), std::vector<float>(kN, a)};
}

Mask Left(int columns) {
  Mask m = EmptyMask(kW, kH);
  for (std::size_t p = 0; p < kN; ++p) m.bits[p] = p % kW < std::size_t(columns) ? 1 : 0;
  return m;
}

ResidualOptions Tolerances(double colour, double depth) {
  ResidualOptions o;
  o.colour_tol = colour;
  o.depth_tol = depth;
  return o;
}

TEST(PixelResidual, ColourAndDepthMustBothStay) {
  const Depths before = Flat(0.9f, 2.0f);
  const Mask object = Left(8);
  const ResidualOptions o = Tolerances(0.1, 0.02);
  EXPECT_EQ(*ComputePixelResidual(before.View(), before.View(), object, o).value, 1.0);  // untouched
  const Depths gone = Flat(0.3f, 5.0f);
  EXPECT_EQ(*ComputePixelResidual(before.View(), gone.View(), object, o).value, 0.0);
  // Same colour, depth 1 % further (within 2 %): still there; 3 % further: changed.
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.9f, 2.02f).View(), object, o).value, 1.0);
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.9f, 2.06f).View(), object, o).value, 0.0);
  // Same depth, colour 0.2 away: changed (a look-alike surface exactly where the object was is not)
  // -- unless the colour tolerance takes it.
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.7f, 2.0f).View(), object, o).value, 0.0);
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.7f, 2.0f).View(), object, Tolerances(0.25, 0.02)).value, 1.0);
  // The defaults (bench/residual's tuning half): 0.2 in colour, 15 % in depth.
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.9f, 2.2f).View(), object, {}).value, 1.0);
  EXPECT_EQ(*ComputePixelResidual(before.View(), Flat(0.9f, 2.4f).View(), object, {}).value, 0.0);
  // Half the mask still matches.
  Depths half = gone;
  for (std::size_t p = 0; p < kN; ++p)
    if (p % kW < 4) {
      SetPixel(half.rgb, p, 0.9f, 0.2f, 0.2f);
      half.depth[p] = 2.0f;
    }
  Mask still;
  EXPECT_DOUBLE_EQ(*ComputePixelResidual(before.View(), half.View(), object, o, &still).value, 0.5);
  EXPECT_EQ(still.Count(), 32u);
}

TEST(PixelResidual, HolesEmptyAndFullMasks) {
  const Depths before = Flat(0.0f, 2.0f);
  Depths hole = Flat(0.0f, 0.0f, 0.0f);  // nothing behind: same (black) colour, no depth
  EXPECT_EQ(*ComputePixelResidual(before.View(), hole.View(), Left(8), {}).value, 0.0);
  const Depths sky = Flat(0.0f, 0.0f, 0.0f);  // empty before and after: unchanged
  EXPECT_EQ(*ComputePixelResidual(sky.View(), sky.View(), Left(8), {}).value, 1.0);
  const ViewResidual empty = ComputePixelResidual(before.View(), before.View(), Left(0), {});
  EXPECT_FALSE(empty.value.has_value());
  EXPECT_EQ(empty.pixels, 0u);
  const ViewResidual full = ComputePixelResidual(before.View(), before.View(), Left(kW), {});
  EXPECT_EQ(full.pixels, kN);
  EXPECT_EQ(*full.value, 1.0);
  Depths nan = before;
  nan.depth[0] = std::numeric_limits<float>::quiet_NaN();  // no depth there after: a change
  EXPECT_DOUBLE_EQ(*ComputePixelResidual(before.View(), nan.View(), Left(kW), {}).value, 127.0 / 128.0);
  EXPECT_THROW(ComputePixelResidual(before.View(), before.View(), EmptyMask(3, 3), {}), Error);
}

TEST(Residual, SummaryAndOptions) {
  const ResidualSummary s = SummarizeResidual({{0.2, 100}, {std::nullopt, 10}, {0.4, 80}});
  EXPECT_EQ(s.stats.count, 2u);
  EXPECT_NEAR(s.stats.mean, 0.3, 1e-12);
  EXPECT_EQ(s.small_views, 1u);
  EXPECT_EQ(SummarizeResidual({}).stats.count, 0u);
  ResidualOptions o;
  EXPECT_NO_THROW(o.Check());
  o.footprint = 0;
  EXPECT_THROW(o.Check(), Error);
  o = {};
  o.min_pixels = 0;
  EXPECT_THROW(o.Check(), Error);
  o = {};
  o.depth_tol = std::nan("");
  EXPECT_THROW(o.Check(), Error);
  EXPECT_EQ(ResidualOptions::Table().ToJson(ResidualOptions{})["residual_min_pixels"], 64);
}

}  // namespace
}  // namespace al::metrics
