// Analytic answers, invariants (fast == reference, incremental == full, threads) and stress
// cases for the CPU rasterizer, on scenes built in memory.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/render/render.hpp"
#include "render/expect_identical.hpp"

namespace al {
namespace {

constexpr float kC0 = 0.28209479177387814f;

Scene MakeScene(std::size_t n, int sh_degree) {
  Scene s;
  s.means = MatX3f::Zero(n, 3);
  s.log_scales = MatX3f::Constant(n, 3, std::log(0.1f));
  s.rotations = MatX4f::Zero(n, 4);
  s.rotations.col(0).setOnes();
  s.opacity_logits = Eigen::VectorXf::Zero(n);
  const int k = (sh_degree + 1) * (sh_degree + 1);
  s.sh = RowMatXf::Zero(n, 3 * k);
  s.sh_degree = sh_degree;
  return s;
}

void SetColour(Scene& s, std::size_t i, float r, float g, float b) {
  s.sh(i, 0) = (r - 0.5f) / kC0;
  s.sh(i, 1) = (g - 0.5f) / kC0;
  s.sh(i, 2) = (b - 0.5f) / kC0;
}

float Logit(float o) { return std::log(o / (1 - o)); }

Camera MakeCamera(int w, int h, double f) {
  Camera c;
  c.name = "test";
  c.width = w;
  c.height = h;
  c.fx = c.fy = f;
  c.cx = w / 2.0;
  c.cy = h / 2.0;
  return c;
}

// A random SH3 scene in front of an identity camera, including Gaussians behind the camera,
// off-screen and near the near plane, so that all code paths run.
Scene RandomScene(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> U(-1, 1);
  Scene s = MakeScene(n, 3);
  for (std::size_t i = 0; i < n; ++i) {
    s.means.row(i) << 3 * U(rng), 2 * U(rng), 3.0f + 2.5f * U(rng);
    s.log_scales.row(i) << -3 + U(rng), -3 + U(rng), -3.5f + U(rng);
    s.rotations.row(i) << U(rng), U(rng), U(rng), U(rng);
    s.opacity_logits[i] = 3 * U(rng);
    for (int k = 0; k < s.sh.cols(); ++k) s.sh(i, k) = (k < 3 ? 1.5f : 0.3f) * U(rng);
  }
  return s;
}

Camera OffsetCamera() {
  Camera c = MakeCamera(100, 75, 90);  // not a multiple of 16: partial edge tiles
  const double a = 0.2;
  c.R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  c.t << 0.3, -0.1, 0.4;
  return c;
}

using test::ExpectIdenticalRenders;

void ExpectAllFinite(const RenderOutput& o) {
  for (float v : o.rgb) ASSERT_TRUE(std::isfinite(v));
  for (float v : o.alpha) ASSERT_TRUE(std::isfinite(v) && v >= 0 && v <= 1);
  for (float v : o.depth) ASSERT_TRUE(std::isfinite(v));
  for (float v : o.invdepth) ASSERT_TRUE(std::isfinite(v));
}

// One isotropic Gaussian on the optical axis: centre value, Gaussian falloff, radius, depth.
TEST(RenderAnalytic, IsotropicGaussian) {
  Scene s = MakeScene(1, 0);
  const float z = 5, sigma = 0.1f, f = 64;
  s.means.row(0) << 0, 0, z;
  s.log_scales.row(0).setConstant(std::log(sigma));
  SetColour(s, 0, 0.8f, 0.4f, 0.2f);
  const Camera cam = MakeCamera(65, 65, f);  // principal point (W-1)/2 = 32: a pixel centre
  const RenderOutput out = Render(s, cam);
  const float var = (f * sigma / z) * (f * sigma / z) + 0.3f;  // projected variance + dilation
  const int c = 32 * 65 + 32;
  EXPECT_NEAR(out.alpha[c], 0.5f, 1e-6);  // opacity logit 0, power 0 at the centre
  EXPECT_NEAR(out.rgb[3 * c + 0], 0.4f, 1e-6);
  EXPECT_NEAR(out.rgb[3 * c + 1], 0.2f, 1e-6);
  EXPECT_NEAR(out.depth[c], z, 1e-5);
  EXPECT_NEAR(out.invdepth[c], 0.5f / z, 1e-7);
  EXPECT_EQ(out.front_id[c], 0);
  for (int k = 1; k <= 4; ++k) {
    const float expect = 0.5f * std::exp(-0.5f * k * k / var);
    EXPECT_NEAR(out.alpha[32 * 65 + 32 + k], expect, 1e-6) << k;
    EXPECT_NEAR(out.alpha[(32 + k) * 65 + 32], expect, 1e-6) << k;
  }
  // Isotropic: mid^2 - det = 0, so lambda = var + sqrt(0.1).
  EXPECT_EQ(out.radii[0], int(std::ceil(3 * std::sqrt(var + std::sqrt(0.1f)))));
  EXPECT_EQ(out.visible_gaussians, 1u);
  // Far from the centre alpha drops below 1/255: background, no id.
  EXPECT_EQ(out.alpha[0], 0.0f);
  EXPECT_EQ(out.front_id[0], -1);
  EXPECT_EQ(out.depth[0], 0.0f);
}

// Two overlapping Gaussians listed back-to-front: depth order, transmittance, depth average.
TEST(RenderAnalytic, TwoGaussiansOrderAndTransmittance) {
  Scene s = MakeScene(2, 0);
  s.means.row(0) << 0, 0, 6;  // back, green
  s.means.row(1) << 0, 0, 4;  // front, red
  SetColour(s, 0, 0, 1, 0);
  SetColour(s, 1, 1, 0, 0);
  s.opacity_logits << Logit(0.7f), Logit(0.4f);
  RenderOptions opt;
  opt.background = Eigen::Vector3f(0, 0, 1);
  const RenderOutput out = Render(s, MakeCamera(65, 65, 64), opt);
  const int c = 32 * 65 + 32;
  const float a1 = 0.4f, a2 = 0.7f, T = (1 - a1) * (1 - a2);
  EXPECT_NEAR(out.rgb[3 * c + 0], a1, 1e-6);
  EXPECT_NEAR(out.rgb[3 * c + 1], a2 * (1 - a1), 1e-6);
  EXPECT_NEAR(out.rgb[3 * c + 2], T, 1e-6);  // blue background through the remaining T
  EXPECT_NEAR(out.alpha[c], 1 - T, 1e-6);
  EXPECT_NEAR(out.depth[c], (a1 * 4 + a2 * (1 - a1) * 6) / (1 - T), 1e-5);
  EXPECT_NEAR(out.invdepth[c], a1 / 4 + a2 * (1 - a1) / 6, 1e-6);
  EXPECT_EQ(out.front_id[c], 1);
}

// Opaque stack: the Gaussian that would push T below 1e-4 and everything behind it add nothing.
TEST(RenderAnalytic, EarlyStopRule) {
  Scene s = MakeScene(5, 0);
  for (int i = 0; i < 5; ++i) {
    s.means.row(i) << 0, 0, 2.0f + i;
    s.opacity_logits[i] = Logit(0.95f);
    SetColour(s, i, i < 3 ? 1.0f : 0.0f, i >= 3 ? 1.0f : 0.0f, 0);
  }
  const RenderOutput out = Render(s, MakeCamera(65, 65, 64));
  const int c = 32 * 65 + 32;
  // T: 0.05, 0.0025, 1.25e-4, then 6.25e-6 < 1e-4: the 4th (green) is not blended.
  EXPECT_NEAR(out.alpha[c], 1 - 1.25e-4f, 1e-6);
  EXPECT_NEAR(out.rgb[3 * c + 0], 1 - 1.25e-4f, 1e-6);
  EXPECT_EQ(out.rgb[3 * c + 1], 0.0f);
  // Alpha is capped at 0.99.
  Scene one = MakeScene(1, 0);
  one.means.row(0) << 0, 0, 3;
  one.opacity_logits[0] = 1e4f;
  EXPECT_NEAR(Render(one, MakeCamera(65, 65, 64)).alpha[c], 0.99f, 1e-7);
}

TEST(RenderAnalytic, ShDegreeOneDirection) {
  // A Gaussian straight ahead (d = +z) picks up +C1 * sh2; degree limited to 0 ignores it.
  Scene s = MakeScene(1, 1);
  s.means.row(0) << 0, 0, 4;
  s.opacity_logits[0] = 1e4f;
  s.sh(0, 2 * 3 + 0) = 0.5f;  // coefficient 2 (z), red
  const int c = 32 * 65 + 32;
  const RenderOutput out = Render(s, MakeCamera(65, 65, 64));
  EXPECT_NEAR(out.rgb[3 * c], 0.99f * (0.5f + 0.4886025f * 0.5f), 1e-6);
  RenderOptions deg0;
  deg0.max_sh_degree = 0;
  EXPECT_NEAR(Render(s, MakeCamera(65, 65, 64), deg0).rgb[3 * c], 0.99f * 0.5f, 1e-6);
}

TEST(RenderInvariants, FastPathEqualsReference) {
  const Scene s = RandomScene(600, 1);
  const Camera cam = OffsetCamera();
  for (float bg : {0.0f, 1.0f}) {
    RenderOptions opt;
    opt.background.setConstant(bg);
    const RenderOutput fast = Render(s, cam, opt);
    const RenderOutput ref = ReferenceRender(s, cam, opt);
    ExpectIdenticalRenders(fast, ref);
    EXPECT_GT(fast.visible_gaussians, 300u);
    EXPECT_LT(fast.visible_gaussians, 600u);  // some behind / off-screen
  }
}

TEST(RenderInvariants, RemovingNothingIsFullRender) {
  const Scene s = RandomScene(400, 2);
  const Camera cam = OffsetCamera();
  const RenderOutput full = Render(s, cam);
  ExpectIdenticalRenders(full, Render(s, cam, {}, std::vector<bool>(s.size(), false)));
  IncrementalRenderer inc(s, cam);
  const RenderOutput after = inc.After(std::vector<bool>(s.size(), false));
  ExpectIdenticalRenders(full, after);
  EXPECT_EQ(after.tiles_rendered, 0u);
  EXPECT_EQ(after.tiles_copied, after.tiles_total);
}

TEST(RenderInvariants, IncrementalAfterEqualsFullRender) {
  const Scene s = RandomScene(800, 3);
  const Camera cam = OffsetCamera();
  std::vector<bool> base(s.size(), false);
  for (std::size_t i = 0; i < s.size(); i += 17) base[i] = true;
  IncrementalRenderer inc(s, cam, {}, base);
  ExpectIdenticalRenders(inc.before(), Render(s, cam, {}, base));
  // A compact removed object: Gaussians near one point.
  std::vector<bool> removed(s.size(), false), both = base;
  std::size_t count = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if ((s.means.row(i) - Eigen::RowVector3f(1, 0.5f, 3)).norm() < 0.8f) {
      removed[i] = true;
      both[i] = true;
      ++count;
    }
  ASSERT_GT(count, 5u);
  const RenderOutput after = inc.After(removed);
  const RenderOutput full = Render(s, cam, {}, both);
  ExpectIdenticalRenders(after, full);
  EXPECT_GT(after.tiles_rendered, 0u);
  EXPECT_GT(after.tiles_copied, 0u);
  EXPECT_EQ(after.tiles_rendered + after.tiles_copied, after.tiles_total);
  EXPECT_EQ(after.tile_entries, full.tile_entries);
  // Removing everything gives the background everywhere.
  const RenderOutput empty = inc.After(std::vector<bool>(s.size(), true));
  for (float a : empty.alpha) ASSERT_EQ(a, 0.0f);
  EXPECT_EQ(empty.visible_gaussians, 0u);
  EXPECT_THROW(inc.After(std::vector<bool>(3, true)), Error);
}

TEST(RenderInvariants, ThreadCountDoesNotChangeResults) {
  const Scene s = RandomScene(700, 4);
  const Camera cam = OffsetCamera();
  RenderOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  ExpectIdenticalRenders(Render(s, cam, one), Render(s, cam, two));
  std::vector<bool> removed(s.size(), false);
  for (std::size_t i = 0; i < s.size(); i += 5) removed[i] = true;
  ExpectIdenticalRenders(IncrementalRenderer(s, cam, one).After(removed), IncrementalRenderer(s, cam, two).After(removed));
}

// Enough Gaussians that binning splits its work into several chunks (src/render/binning.cpp),
// with many exactly equal depths, so the stable (tz, index) order across chunk boundaries is
// what decides the result: every thread count must give the reference's pixels and lists.
TEST(RenderInvariants, ChunkedBinningKeepsDepthTiesInIndexOrder) {
  Scene s = RandomScene(20000, 8);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (i % 3 != 0) s.means(i, 2) = 2.0f + 0.5f * static_cast<float>(i % 4);  // 4 shared depths
  const Camera cam = MakeCamera(96, 64, 60);
  RenderOptions one, three;
  one.num_threads = 1;
  three.num_threads = 3;
  const RenderOutput a = Render(s, cam, one), b = Render(s, cam, three);
  ASSERT_GT(a.visible_gaussians, 9000u);  // > 2 chunks of 4096
  ExpectIdenticalRenders(a, b);
  EXPECT_EQ(a.tile_entries, b.tile_entries);
  EXPECT_EQ(a.pixel_evaluations, b.pixel_evaluations);
  ExpectIdenticalRenders(b, ReferenceRender(s, cam, three));
}

// The compositing work counter: positive, bounded by the list entries times the tile size, and
// smaller for an incremental render that re-composites a few tiles.
TEST(RenderInvariants, PixelEvaluationCount) {
  const Scene s = RandomScene(800, 9);
  const Camera cam = OffsetCamera();
  IncrementalRenderer inc(s, cam);
  const RenderOutput& full = inc.before();
  EXPECT_GT(full.pixel_evaluations, 0u);
  EXPECT_LE(full.pixel_evaluations, full.tile_entries * 256);
  std::vector<bool> removed(s.size(), false);
  removed[0] = true;
  const RenderOutput after = inc.After(removed);
  EXPECT_LT(after.pixel_evaluations, full.pixel_evaluations);
  EXPECT_EQ(inc.After(std::vector<bool>(s.size(), false)).pixel_evaluations, 0u);
}

TEST(RenderInvariants, ExcludedGaussiansHaveZeroRadius) {
  const Scene s = RandomScene(300, 5);
  const Camera cam = OffsetCamera();
  std::vector<bool> ex(s.size(), false);
  for (std::size_t i = 0; i < s.size(); i += 2) ex[i] = true;
  const RenderOutput out = Render(s, cam, {}, ex);
  for (std::size_t i = 0; i < s.size(); i += 2) EXPECT_EQ(out.radii[i], 0);
  for (std::int32_t id : out.front_id)
    if (id >= 0) {
      EXPECT_FALSE(ex[id]);
    }
  EXPECT_THROW(Render(s, cam, {}, std::vector<bool>(5, false)), Error);
}

// Stress: degenerate parameters never crash and never produce NaN pixels.
TEST(RenderStress, DegenerateParameters) {
  Scene s = RandomScene(200, 6);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  s.log_scales.row(0).setConstant(-100);  // zero scale
  s.log_scales.row(1).setConstant(60);    // scale overflows float when squared
  s.log_scales.row(2) << 80, -80, 0;
  s.rotations.row(3).setZero();           // zero quaternion
  s.rotations.row(4) << 1e6f, 3e6f, -2e5f, 7;  // unnormalised
  s.opacity_logits[5] = 1e4f;
  s.opacity_logits[6] = -1e4f;
  s.means(7, 0) = nan;
  s.log_scales(8, 1) = inf;
  s.rotations(9, 2) = -inf;
  s.opacity_logits[10] = nan;
  s.sh(11, 17) = inf;
  const Camera cam = OffsetCamera();
  const RenderOutput out = Render(s, cam);
  ExpectAllFinite(out);
  EXPECT_EQ(out.excluded_nonfinite, 5u);
  for (int i = 7; i <= 11; ++i) EXPECT_EQ(out.radii[i], 0);
  ExpectIdenticalRenders(out, ReferenceRender(s, cam));
}

TEST(RenderStress, AllBehindCamera) {
  Scene s = RandomScene(100, 7);
  s.means.col(2).array() = -s.means.col(2).array().abs() - 0.1f;
  const RenderOutput out = Render(s, OffsetCamera());
  EXPECT_EQ(out.visible_gaussians, 0u);
  for (float a : out.alpha) EXPECT_EQ(a, 0.0f);
  // Exactly on the near plane (z = 0.2) is culled, just beyond is kept.
  Scene near = MakeScene(2, 0);
  near.means.row(0) << 0, 0, 0.2f;
  near.means.row(1) << 0, 0, 0.2001f;
  const RenderOutput n = Render(near, MakeCamera(64, 48, 50));
  EXPECT_EQ(n.radii[0], 0);
  EXPECT_GT(n.radii[1], 0);
}

TEST(RenderStress, GaussianCoveringWholeImage) {
  Scene s = MakeScene(1, 0);
  s.means.row(0) << 0.1f, 0, 0.25f;
  s.log_scales.row(0).setConstant(1.0f);
  s.opacity_logits[0] = 2;
  const Camera cam = MakeCamera(100, 75, 90);
  const RenderOutput out = Render(s, cam);
  ExpectAllFinite(out);
  EXPECT_GT(out.radii[0], 1000);
  EXPECT_EQ(out.tile_entries, out.tiles_total);
  for (std::int32_t id : out.front_id) EXPECT_EQ(id, 0);
}

// The image is invariant to a global similarity of scene + camera (scale 1e-6 .. 1e6), up to
// float rounding, as long as the near plane (absolute 0.2) does not cut differently.
TEST(RenderStress, SceneScaleInvariance) {
  const Scene base = RandomScene(300, 8);
  Camera cam = MakeCamera(64, 48, 60);
  cam.t << 0, 0, 10;  // everything at depth >= 10.5
  const RenderOutput ref = Render(base, cam);
  for (double k : {1e-6, 1e6}) {
    Scene s = base;
    s.means *= float(k);
    s.log_scales.array() += float(std::log(k));
    Camera c = cam;
    c.t *= k;
    const RenderOutput out = Render(s, c);
    ExpectAllFinite(out);
    if (k > 1) {  // at 1e-6 everything is inside the near plane
      double max_diff = 0;
      for (std::size_t i = 0; i < ref.rgb.size(); ++i) max_diff = std::max(max_diff, double(std::abs(out.rgb[i] - ref.rgb[i])));
      EXPECT_LT(max_diff, 1e-2);
    } else {
      EXPECT_EQ(out.visible_gaussians, 0u);
    }
  }
}

TEST(RenderStress, BadCameraThrows) {
  const Scene s = RandomScene(10, 9);
  EXPECT_THROW(Render(s, MakeCamera(0, 10, 10)), Error);
  EXPECT_THROW(Render(s, MakeCamera(10, 10, 0)), Error);
  Camera c = MakeCamera(10, 10, 10);
  c.t[0] = std::nan("");
  EXPECT_THROW(Render(s, c), Error);
}

}  // namespace
}  // namespace al
