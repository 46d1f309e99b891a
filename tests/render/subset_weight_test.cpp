// RenderOptions::weight_subset: the per-pixel subset share computed in the compositing pass.
// Its agreement with the independent fixtures::SubsetWeight is checked in
// tests/fixtures/subset_weight_render_test.cpp (this suite links al_render only).
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/render/render.hpp"
#include "render/expect_identical.hpp"

namespace al {
namespace {

// Random SH1 scene in front of an identity-ish camera; overlapping splats so T really drops.
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

std::vector<bool> EveryThird(std::size_t n) {
  std::vector<bool> s(n);
  for (std::size_t i = 0; i < n; ++i) s[i] = i % 3 == 0;
  return s;
}

// Asking for the subset weight changes no other output, bit for bit, nor the work done.
TEST(RenderSubsetWeight, OtherOutputsUnchanged) {
  const Scene s = RandomScene(3000, 11);
  const Camera cam = TestCamera();
  const std::vector<bool> subset = EveryThird(s.size());
  RenderOptions with;
  with.weight_subset = &subset;
  const RenderOutput plain = Render(s, cam);
  const RenderOutput sw = Render(s, cam, with);
  test::ExpectIdenticalRenders(plain, sw);
  EXPECT_EQ(plain.pixel_evaluations, sw.pixel_evaluations);
  EXPECT_TRUE(plain.subset_weight.empty());
  ASSERT_EQ(sw.subset_weight.size(), std::size_t(cam.width) * cam.height);
}

// Empty subset: exactly 0. Whole scene: the composite's alpha (1 - T, summed differently, so up to
// float rounding). A subset and its complement add up to the whole.
TEST(RenderSubsetWeight, SharesOfTheComposite) {
  const Scene s = RandomScene(3000, 12);
  const Camera cam = TestCamera();
  const std::size_t n = s.size();
  const std::vector<bool> none(n, false), all(n, true), third = EveryThird(n);
  std::vector<bool> rest(n);
  for (std::size_t i = 0; i < n; ++i) rest[i] = !third[i];
  auto weight = [&](const std::vector<bool>& subset) {
    RenderOptions o;
    o.weight_subset = &subset;
    return Render(s, cam, o);
  };
  const RenderOutput wn = weight(none), wa = weight(all), wt = weight(third), wr = weight(rest);
  std::size_t covered = 0, mixed = 0;
  for (std::size_t p = 0; p < wa.subset_weight.size(); ++p) {
    ASSERT_EQ(wn.subset_weight[p], 0.0f);
    ASSERT_NEAR(wa.subset_weight[p], wa.alpha[p], 2e-6) << p;
    ASSERT_NEAR(wt.subset_weight[p] + wr.subset_weight[p], wa.subset_weight[p], 2e-6) << p;
    ASSERT_GE(wt.subset_weight[p], 0.0f);
    covered += wa.alpha[p] > 0.5f;
    mixed += wt.subset_weight[p] > 0.05f && wr.subset_weight[p] > 0.05f;
  }
  // The scene really covers the image and the subsets really overlap (else the test is vacuous).
  EXPECT_GT(covered, wa.subset_weight.size() / 4);
  EXPECT_GT(mixed, wa.subset_weight.size() / 10);
}

// Two Gaussians on the axis at the centre pixel: front alpha a1, back alpha a2 * (1 - a1).
TEST(RenderSubsetWeight, TwoGaussiansAnalytic) {
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
  const std::vector<bool> back = {true, false}, front = {false, true};
  RenderOptions o;
  o.weight_subset = &back;
  const int c = 32 * 65 + 32;
  EXPECT_FLOAT_EQ(Render(s, cam, o).subset_weight[c], 0.25f);
  o.weight_subset = &front;
  EXPECT_FLOAT_EQ(Render(s, cam, o).subset_weight[c], 0.5f);
}

TEST(RenderSubsetWeight, ThreadCountDoesNotChangeIt) {
  const Scene s = RandomScene(3000, 13);
  const Camera cam = TestCamera();
  const std::vector<bool> subset = EveryThird(s.size());
  RenderOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  one.weight_subset = two.weight_subset = &subset;
  EXPECT_EQ(Render(s, cam, one).subset_weight, Render(s, cam, two).subset_weight);
}

// The incremental renderer's "before" carries it; After() does not (and is still the full render).
TEST(RenderSubsetWeight, IncrementalBeforeOnly) {
  const Scene s = RandomScene(3000, 14);
  const Camera cam = TestCamera();
  std::vector<bool> subset = EveryThird(s.size());
  RenderOptions o;
  o.weight_subset = &subset;
  const RenderOutput full = Render(s, cam, o);
  const IncrementalRenderer inc(s, cam, o);
  subset.assign(s.size(), false);  // the renderer must not keep the caller's vector
  EXPECT_EQ(inc.before().subset_weight, full.subset_weight);
  std::vector<bool> removed(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) removed[i] = i % 5 == 1;
  const RenderOutput after = inc.After(removed);
  EXPECT_TRUE(after.subset_weight.empty());
  test::ExpectIdenticalRenders(after, Render(s, cam, {}, removed));
}

TEST(RenderSubsetWeight, WrongSizeThrows) {
  const Scene s = RandomScene(10, 15);
  const std::vector<bool> subset(9, true);
  RenderOptions o;
  o.weight_subset = &subset;
  EXPECT_THROW(Render(s, TestCamera(), o), Error);
  EXPECT_THROW(IncrementalRenderer(s, TestCamera(), o), Error);
}

}  // namespace
}  // namespace al
