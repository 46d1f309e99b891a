// RenderOptions::features: a per-Gaussian feature composited with the RGB blend weights alpha*T in
// the same pass. Bit-identical to the per-pixel reference, independent of the thread count, exact
// in the incremental "after" render, and invisible to every other output.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/render/render.hpp"
#include "render/expect_identical.hpp"

namespace al {
namespace {

// Random SH1 scene with overlapping splats (T really drops), as in subset_weight_test.cpp.
Scene RandomScene(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> U(-1, 1);
  Scene s;
  s.sh_degree = 1;
  s.means = MatX3f::Zero(n, 3);
  s.log_scales = MatX3f::Zero(n, 3);
  s.rotations = MatX4f::Zero(n, 4);
  s.opacity_logits = Eigen::VectorXf::Zero(n);
  s.sh = RowMatXf::Zero(n, 12);
  for (std::size_t i = 0; i < n; ++i) {
    s.means.row(i) << 3 * U(rng), 2 * U(rng), 3.0f + 2.5f * U(rng);
    s.log_scales.row(i) << -3 + U(rng), -3 + U(rng), -3.5f + U(rng);
    s.rotations.row(i) << U(rng), U(rng), U(rng), U(rng);
    s.opacity_logits[i] = 3 * U(rng);
    for (int k = 0; k < s.sh.cols(); ++k) s.sh(i, k) = (k < 3 ? 1.5f : 0.3f) * U(rng);
  }
  return s;
}

RowMatXf RandomFeatures(std::size_t n, int dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> N(0, 1);
  RowMatXf f(static_cast<Eigen::Index>(n), dim);
  for (Eigen::Index i = 0; i < f.size(); ++i) f.data()[i] = N(rng);
  return f;
}

Camera TestCamera() {
  Camera c;
  c.name = "test";
  c.width = 100;  // not a multiple of 16: partial edge tiles
  c.height = 75;
  c.fx = c.fy = 90;
  c.cx = 50;
  c.cy = 37.5;
  const double a = 0.2;
  c.R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  c.t << 0.3, -0.1, 0.4;
  return c;
}

std::vector<bool> EveryFifth(std::size_t n) {
  std::vector<bool> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = i % 5 == 1;
  return r;
}

// The fast path equals the per-pixel reference bit for bit, for channel counts that are and are
// not multiples of the 4-wide SIMD blocks, up to the maximum.
TEST(RenderFeatures, BitIdenticalToReference) {
  const Scene s = RandomScene(2000, 21);
  const Camera cam = TestCamera();
  for (int dim : {1, 3, 4, 13, 16, kMaxFeatureChannels}) {
    const RowMatXf f = RandomFeatures(s.size(), dim, 100 + dim);
    RenderOptions o;
    o.features = &f;
    const RenderOutput fast = Render(s, cam, o), ref = ReferenceRender(s, cam, o);
    ASSERT_EQ(fast.feature_dim, dim);
    ASSERT_EQ(fast.feature.size(), std::size_t(cam.width) * cam.height * dim);
    EXPECT_EQ(fast.feature, ref.feature) << "dim " << dim;
    test::ExpectIdenticalRenders(fast, ref);
  }
}

// Asking for features changes no other output, bit for bit, nor the work done; together with the
// subset weight both extras are the same as alone.
TEST(RenderFeatures, OtherOutputsUnchanged) {
  const Scene s = RandomScene(3000, 22);
  const Camera cam = TestCamera();
  const RowMatXf f = RandomFeatures(s.size(), 16, 1);
  std::vector<bool> subset(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) subset[i] = i % 3 == 0;
  RenderOptions with_f, with_sw, with_both;
  with_f.features = with_both.features = &f;
  with_sw.weight_subset = with_both.weight_subset = &subset;
  const RenderOutput plain = Render(s, cam), rf = Render(s, cam, with_f);
  const RenderOutput rsw = Render(s, cam, with_sw), both = Render(s, cam, with_both);
  test::ExpectIdenticalRenders(plain, rf);
  test::ExpectIdenticalRenders(plain, both);
  EXPECT_EQ(plain.pixel_evaluations, rf.pixel_evaluations);
  EXPECT_TRUE(plain.feature.empty());
  EXPECT_EQ(plain.feature_dim, 0);
  EXPECT_EQ(both.feature, rf.feature);
  EXPECT_EQ(both.subset_weight, rsw.subset_weight);
}

TEST(RenderFeatures, ThreadCountDoesNotChangeIt) {
  const Scene s = RandomScene(3000, 23);
  const Camera cam = TestCamera();
  const RowMatXf f = RandomFeatures(s.size(), 24, 2);
  RenderOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  one.features = two.features = &f;
  EXPECT_EQ(Render(s, cam, one).feature, Render(s, cam, two).feature);
  const std::vector<bool> removed = EveryFifth(s.size());
  EXPECT_EQ(IncrementalRenderer(s, cam, one).After(removed).feature,
            IncrementalRenderer(s, cam, two).After(removed).feature);
}

// The incremental "after" feature image is the full render of the remaining Gaussians.
TEST(RenderFeatures, IncrementalAfterEqualsFullRender) {
  const Scene s = RandomScene(3000, 24);
  const Camera cam = TestCamera();
  const RowMatXf f = RandomFeatures(s.size(), 7, 3);
  RenderOptions o;
  o.features = &f;
  const IncrementalRenderer inc(s, cam, o);
  EXPECT_EQ(inc.before().feature, Render(s, cam, o).feature);
  std::vector<bool> removed(s.size());  // a compact group near the image centre: some tiles change
  for (Eigen::Index i = 0; i < s.means.rows(); ++i)
    removed[std::size_t(i)] = std::abs(s.means(i, 0)) < 0.5f && std::abs(s.means(i, 1)) < 0.5f;
  const RenderOutput after = inc.After(removed), full = Render(s, cam, o, removed);
  EXPECT_EQ(after.feature_dim, 7);
  EXPECT_EQ(after.feature, full.feature);
  test::ExpectIdenticalRenders(after, full);
  EXPECT_LT(after.tiles_rendered, after.tiles_total);  // really incremental
  EXPECT_NE(after.feature, inc.before().feature);      // and really changed
}

// One feature for every Gaussian renders as that feature wherever something blended (the weights
// are normalised per pixel), and as 0 where nothing did.
TEST(RenderFeatures, ConstantFeatureIsReproduced) {
  const Scene s = RandomScene(3000, 25);
  const Camera cam = TestCamera();
  RowMatXf f(static_cast<Eigen::Index>(s.size()), 5);
  for (Eigen::Index i = 0; i < f.rows(); ++i) f.row(i) << 1.0f, -2.0f, 0.5f, 0.0f, 3.0f;
  RenderOptions o;
  o.features = &f;
  const RenderOutput r = Render(s, cam, o);
  std::size_t covered = 0;
  for (std::size_t p = 0; p < r.alpha.size(); ++p) {
    if (r.alpha[p] == 0.0f) {
      for (int ch = 0; ch < 5; ++ch) ASSERT_EQ(r.feature[p * 5 + ch], 0.0f);
      continue;
    }
    // alpha = 1 - T and the weight sum agree up to float rounding, relative to alpha.
    const float tol = 2e-6f / r.alpha[p] + 1e-5f;
    for (int ch = 0; ch < 5; ++ch) ASSERT_NEAR(r.feature[p * 5 + ch], f(0, ch), tol * (1 + std::abs(f(0, ch)))) << p;
    ++covered;
  }
  EXPECT_GT(covered, r.alpha.size() / 4);
}

// Two Gaussians on the axis at the centre pixel: weights 0.5 (front) and 0.25 (back), normalised by
// alpha 0.75.
TEST(RenderFeatures, TwoGaussiansAnalytic) {
  Scene s = RandomScene(2, 1);
  s.means.row(0) << 0, 0, 6;  // back
  s.means.row(1) << 0, 0, 4;  // front
  s.log_scales.setConstant(std::log(0.2f));
  s.rotations.setZero();
  s.rotations.col(0).setOnes();
  s.opacity_logits.setZero();  // opacity 0.5, alpha 0.5 at the centre (power 0)
  Camera cam = TestCamera();
  cam.width = cam.height = 65;  // principal point (W-1)/2 = 32: a pixel centre
  cam.R.setIdentity();
  cam.t.setZero();
  RowMatXf f(2, 2);
  f << 0.0f, 1.0f,   // back
      1.0f, 0.0f;    // front
  RenderOptions o;
  o.features = &f;
  const RenderOutput r = Render(s, cam, o);
  const int c = 32 * 65 + 32;
  EXPECT_FLOAT_EQ(r.alpha[c], 0.75f);
  EXPECT_FLOAT_EQ(r.feature[c * 2 + 0], 0.5f / 0.75f);
  EXPECT_FLOAT_EQ(r.feature[c * 2 + 1], 0.25f / 0.75f);
}

TEST(RenderFeatures, BadShapesThrow) {
  const Scene s = RandomScene(10, 26);
  const RowMatXf rows9 = RandomFeatures(9, 4, 1), wide = RandomFeatures(10, kMaxFeatureChannels + 1, 1);
  const RowMatXf none(10, 0);
  for (const RowMatXf* f : {&rows9, &wide, &none}) {
    RenderOptions o;
    o.features = f;
    EXPECT_THROW(Render(s, TestCamera(), o), Error);
    EXPECT_THROW(IncrementalRenderer(s, TestCamera(), o), Error);
    EXPECT_THROW(ReferenceRender(s, TestCamera(), o), Error);
  }
}

}  // namespace
}  // namespace al
