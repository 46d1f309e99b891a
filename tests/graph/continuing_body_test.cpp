// MeasureContinuingBody (al/graph/continuing_body.hpp) on hand-made layouts whose answer is known:
// boxes of points, each with its own feature direction. A layer of additions on a kept body of the
// same features continues; a part completed whole, with other features beyond it, does not.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "al/graph/continuing_body.hpp"

namespace {

constexpr int kDim = 6;

struct Layout {
  std::vector<float> xyz;
  std::vector<std::uint8_t> active;
  std::vector<bool> removed, refined;
  al::RowMatXf f = al::RowMatXf(0, kDim);
};

// n points in the box [x0, x0 + dx] × [0, 1]², features along `axis` (zero rows if axis < 0);
// a point is removed when its x < removed_below and refined when its x < refined_below.
void AddBox(Layout& l, std::mt19937& rng, int n, float x0, float dx, int axis, float removed_below,
            float refined_below) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  const Eigen::Index first = l.f.rows();
  l.f.conservativeResize(first + n, kDim);
  for (int i = 0; i < n; ++i) {
    const float x = x0 + dx * u(rng);
    l.xyz.insert(l.xyz.end(), {x, u(rng), u(rng)});
    l.active.push_back(1);
    l.removed.push_back(x < removed_below);
    l.refined.push_back(x < refined_below);
    Eigen::RowVectorXf v = Eigen::RowVectorXf::Zero(kDim);
    if (axis >= 0)
      for (int d = 0; d < kDim; ++d) v[d] = noise(rng) + (d == axis ? 1.0f : 0.0f);
    l.f.row(first + i) = v;
  }
}

al::ContinuingBody Measure(const Layout& l) {
  const al::SceneFeatureMap map{l.f, true, false, Eigen::VectorXd::Zero(kDim)};
  return al::MeasureContinuingBody({l.xyz, l.active, l.removed, l.refined, map, 10});
}

// The target (axis 0, removed whole) touches a neighbour (axis 1) whose near side was removed
// with it; the cut added a layer of the neighbour, the rest of it is kept.
Layout NeighbourLayer() {
  std::mt19937 rng(3);
  Layout l;
  AddBox(l, rng, 1000, -1.0f, 1.0f, 0, 1e9f, 1e9f);
  AddBox(l, rng, 4000, 0.0f, 4.0f, 1, 1.0f, 1.4f);
  return l;
}

// The neighbour's layer is still added, but nothing beyond it may count as its body.
void ExpectLayerWithoutBody(const Layout& l) {
  const al::ContinuingBody b = Measure(l);
  EXPECT_GT(b.added, 300u);
  EXPECT_EQ(b.body, 0u);
  EXPECT_FALSE(b.Continues());
}

TEST(ContinuingBody, ALayerOfANeighbourContinues) {
  const al::ContinuingBody b = Measure(NeighbourLayer());
  EXPECT_GT(b.added, 300u);
  EXPECT_LT(b.added, 500u);
  // About 2,600 kept Gaussians of the neighbour lie beyond the layer; the walk stops as soon as
  // it has twice the additions.
  EXPECT_EQ(b.body, static_cast<std::size_t>(std::ceil(al::kContinuingRatio * double(b.added))));
  EXPECT_TRUE(b.Continues());
  EXPECT_EQ(b.ToJson()["continues"], true);
}

TEST(ContinuingBody, APartCompletedWholeDoesNotContinue) {
  std::mt19937 rng(4);
  Layout l;
  AddBox(l, rng, 1000, -1.0f, 1.0f, 0, 1e9f, 1e9f);   // the target, removed whole
  AddBox(l, rng, 400, 0.0f, 0.4f, 1, 0.25f, 1e9f);    // its off part: partly removed, completed
  AddBox(l, rng, 3000, 0.4f, 3.0f, 2, -1e9f, -1e9f);  // the table beyond it, kept
  const al::ContinuingBody b = Measure(l);
  EXPECT_GT(b.added, 100u);
  EXPECT_LT(b.Ratio(), 0.2);
  EXPECT_FALSE(b.Continues());
}

TEST(ContinuingBody, InactiveRowsAreNeverReached) {
  Layout l = NeighbourLayer();
  for (std::size_t i = 0; i < l.active.size(); ++i)
    if (!l.refined[i]) l.active[i] = 0;  // e.g. non-finite Gaussians the graph excluded
  ExpectLayerWithoutBody(l);
}

TEST(ContinuingBody, NoAdditionsOrNoFeaturesMeasureNothing) {
  Layout l = NeighbourLayer();
  l.refined = l.removed;
  const al::ContinuingBody none = Measure(l);
  EXPECT_EQ(none.added, 0u);
  EXPECT_EQ(none.Ratio(), 0.0);
  EXPECT_FALSE(none.Continues());
  Layout featureless = NeighbourLayer();
  featureless.f.setZero();  // zero-norm rows: no direction to compare with
  ExpectLayerWithoutBody(featureless);
}

TEST(ContinuingBody, CoordinateScaleDoesNotMatter) {
  // kNN and cosines are scale-free: the same layout at 1e-6 and 1e6 gives the same body.
  const Layout base = NeighbourLayer();
  const al::ContinuingBody ref = Measure(base);
  for (float scale : {1e-6f, 1e6f}) {
    Layout l = base;
    for (float& x : l.xyz) x *= scale;
    const al::ContinuingBody b = Measure(l);
    EXPECT_EQ(b.added, ref.added) << scale;
    EXPECT_EQ(b.body, ref.body) << scale;
  }
}

TEST(ContinuingBody, NonFiniteFeaturesAreNeverPartOfTheBody) {
  Layout l = NeighbourLayer();
  for (Eigen::Index i = 0; i < l.f.rows(); ++i)
    if (!l.refined[std::size_t(i)]) l.f(i, 0) = std::numeric_limits<float>::quiet_NaN();
  ExpectLayerWithoutBody(l);
}

TEST(ContinuingBody, IsDeterministic) {
  const Layout l = NeighbourLayer();
  const al::ContinuingBody a = Measure(l), b = Measure(l);
  EXPECT_EQ(a.added, b.added);
  EXPECT_EQ(a.body, b.body);
}

}  // namespace
