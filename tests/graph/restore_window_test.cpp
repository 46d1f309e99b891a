// InRestoreWindow (al/graph/restore_window.hpp) on hand-made feature sets whose answer is known:
// the removed set is an object (one feature direction with noise) plus a slab of background (another
// direction); restores of object rows fall inside the window, restores of the slab do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "al/graph/restore_window.hpp"

namespace {

constexpr int kDim = 8;

struct Rows {
  al::RowMatXf f = al::RowMatXf(0, kDim);
  std::vector<bool> removed;
  std::vector<std::uint8_t> active;
};

// n rows along `axis` with noise σ (zero rows if axis < 0); removed or not. Returns the first row.
std::int64_t Add(Rows& r, std::mt19937& rng, int n, int axis, float sigma, bool removed) {
  std::normal_distribution<float> noise(0.0f, sigma);
  const Eigen::Index first = r.f.rows();
  r.f.conservativeResize(first + n, kDim);
  for (int i = 0; i < n; ++i) {
    Eigen::RowVectorXf v = Eigen::RowVectorXf::Zero(kDim);
    if (axis >= 0)
      for (int d = 0; d < kDim; ++d) v[d] = noise(rng) + (d == axis ? 1.0f : 0.0f);
    r.f.row(first + i) = v;
    r.removed.push_back(removed);
    r.active.push_back(1);
  }
  return first;
}

std::vector<std::int64_t> Range(std::int64_t first, int n) {
  std::vector<std::int64_t> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[std::size_t(i)] = first + i;
  return v;
}

std::vector<std::uint8_t> Window(const Rows& r, const std::vector<std::int64_t>& rows, double mads,
                                 al::RestoreWindowStats* st) {
  const al::SceneFeatureMap map{r.f, true, false, Eigen::VectorXd::Zero(kDim)};
  return al::InRestoreWindow(map, r.removed, r.active, rows, mads, st);
}

int Count(const std::vector<std::uint8_t>& v) { return int(std::count(v.begin(), v.end(), 1)); }

struct Layout {
  Rows r;
  std::int64_t object, slab;
};
Layout MakeLayout() {
  std::mt19937 rng(11);
  Layout l;
  l.object = Add(l.r, rng, 2000, 0, 0.15f, true);
  l.slab = Add(l.r, rng, 200, 1, 0.15f, true);  // background the method swallowed
  Add(l.r, rng, 3000, 2, 0.15f, false);          // kept background
  return l;
}

TEST(RestoreWindow, ObjectRowsStayRemovedBackgroundGoesBack) {
  const Layout l = MakeLayout();
  al::RestoreWindowStats st;
  const auto object = Window(l.r, Range(l.object, 200), al::kRestoreWindowMads, &st);
  EXPECT_GE(Count(object), 180);  // ~98 % of a normal spread lies above median − 2σ
  const auto slab = Window(l.r, Range(l.slab, 200), al::kRestoreWindowMads, nullptr);
  EXPECT_EQ(Count(slab), 0);
  EXPECT_EQ(st.prototype_rows, 2200u);
  EXPECT_NEAR(st.floor, st.median - al::kRestoreWindowMads * st.sigma, 1e-12);
  EXPECT_GT(st.sigma, 0.0);
  EXPECT_EQ(st.kept, std::size_t(Count(object)));
}

TEST(RestoreWindow, DepthZeroKeepsTheUpperHalf) {
  const Layout l = MakeLayout();
  const auto object = Window(l.r, Range(l.object, 2000), 0.0, nullptr);
  EXPECT_GT(Count(object), 900);
  EXPECT_LT(Count(object), 1200);  // the median of the removed set: the object's upper half or so
}

TEST(RestoreWindow, InactiveRowsDoNotShapeThePrototype) {
  Layout l = MakeLayout();
  // The object inactive (e.g. non-finite): the prototype is the slab's, and the slab's rows are inside.
  for (int i = 0; i < 2000; ++i) l.r.active[std::size_t(l.object + i)] = 0;
  al::RestoreWindowStats st;
  const auto slab = Window(l.r, Range(l.slab, 200), al::kRestoreWindowMads, &st);
  EXPECT_EQ(st.prototype_rows, 200u);
  EXPECT_GE(Count(slab), 180);
}

TEST(RestoreWindow, FeatureScaleAndNonFiniteRowsDoNotMatter) {
  // Rows are normalised: features scaled by 1e-6 or 1e6 give the same window; a NaN row neither
  // shapes the prototype nor is kept.
  Layout l = MakeLayout();
  const auto rows = Range(l.object, 200);
  const auto ref = Window(l.r, rows, al::kRestoreWindowMads, nullptr);
  for (float scale : {1e-6f, 1e6f}) {
    Layout scaled = l;
    scaled.r.f *= scale;
    EXPECT_EQ(Window(scaled.r, rows, al::kRestoreWindowMads, nullptr), ref) << scale;
  }
  l.r.f(l.object, 0) = std::numeric_limits<float>::quiet_NaN();
  al::RestoreWindowStats st;
  const auto in = Window(l.r, rows, al::kRestoreWindowMads, &st);
  EXPECT_EQ(in[0], 0);
  EXPECT_EQ(st.prototype_rows, 2199u);
}

TEST(RestoreWindow, NoUsablePrototypeKeepsNothing) {
  std::mt19937 rng(5);
  Rows r;
  const std::int64_t first = Add(r, rng, 100, -1, 0.1f, true);  // zero-norm features
  al::RestoreWindowStats st;
  const auto in = Window(r, Range(first, 100), al::kRestoreWindowMads, &st);
  EXPECT_EQ(Count(in), 0);
  EXPECT_EQ(st.prototype_rows, 0u);
  EXPECT_EQ(st.kept, 0u);
  EXPECT_TRUE(Window(r, {}, al::kRestoreWindowMads, nullptr).empty());
}

}  // namespace
