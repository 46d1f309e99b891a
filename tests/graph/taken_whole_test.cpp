// FindTakenWhole (al/graph/taken_whole.hpp) on hand-made layouts whose answer is known: blobs of
// points in space, each with its own feature direction, so a blob is one feature region. Queried
// rows in a small region the method took nearly whole stay removed; rows of the main region, of a
// large region the method took a slab of, of a region holding too little of the removed set, or of
// featureless rows do not.
#include <gtest/gtest.h>

#include <random>

#include "al/graph/taken_whole.hpp"

namespace {

constexpr int kDim = 6;

struct Layout {
  std::vector<float> xyz;
  std::vector<std::uint8_t> active;
  std::vector<bool> removed;
  al::RowMatXf f = al::RowMatXf(0, kDim);
};

// n points in a cube of side `side` at x offset x0, features along `axis` (zero rows if axis < 0);
// the first `removed` of them are removed. Returns the index of the first point.
std::int64_t AddBlob(Layout& l, std::mt19937& rng, int n, float x0, float side, int axis, int removed) {
  std::uniform_real_distribution<float> u(0.0f, side);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  const auto first = static_cast<std::int64_t>(l.removed.size());
  l.f.conservativeResize(l.f.rows() + n, kDim);
  for (int i = 0; i < n; ++i) {
    l.xyz.insert(l.xyz.end(), {x0 + u(rng), u(rng), u(rng)});
    l.active.push_back(1);
    l.removed.push_back(i < removed);
    Eigen::RowVectorXf v = Eigen::RowVectorXf::Zero(kDim);
    if (axis >= 0)
      for (int d = 0; d < kDim; ++d) v[d] = 2.0f * (noise(rng) + (d == axis ? 1.0f : 0.0f));
    l.f.row(first + i) = v;
  }
  return first;
}

std::vector<std::uint8_t> Find(const Layout& l, const std::vector<std::int64_t>& rows, al::TakenWholeStats* st) {
  const al::SceneFeatureMap map{l.f, true, false, Eigen::VectorXd::Zero(kDim)};
  return al::FindTakenWhole({l.xyz, l.active, l.removed, map, 0.8, 10}, rows, st);
}

// The blobs sit 5 apart: no kNN edge links two of them through the gate (different axes anyway).
struct Scene {
  Layout l;
  std::int64_t object, part, table, floaters, featureless;
};
Scene MakeScene() {
  std::mt19937 rng(7);
  Scene s;
  s.object = AddBlob(s.l, rng, 3000, 0, 1.0f, 0, 2950);      // the target: the main region
  s.part = AddBlob(s.l, rng, 400, 5, 0.5f, 1, 330);          // an off part, taken whole (82 %)
  s.table = AddBlob(s.l, rng, 4000, 10, 1.5f, 2, 500);       // a table GG took a slab of (12 %)
  s.floaters = AddBlob(s.l, rng, 6, 15, 0.1f, 3, 6);         // six floaters, all removed (0.2 % of R)
  s.featureless = AddBlob(s.l, rng, 200, 20, 0.5f, -1, 150); // zero feature rows
  return s;
}

TEST(TakenWhole, KeepsOnlyASmallRegionTheMethodTookWhole) {
  const Scene s = MakeScene();
  const std::vector<std::int64_t> rows = {s.object, s.object + 1, s.part, s.part + 100, s.table + 3,
                                          s.floaters, s.featureless + 1};
  al::TakenWholeStats st;
  const auto keep = Find(s.l, rows, &st);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 0, 1, 1, 0, 0, 0}));
  EXPECT_EQ(st.kept, 2u);
  EXPECT_EQ(st.regions, 1u);
  EXPECT_EQ(st.rows, 330u);
}

TEST(TakenWhole, ARegionBelowTheRatioOrWithHalfOfTheRemovedSetIsNotTakenWhole) {
  std::mt19937 rng(3);
  Layout l;
  const std::int64_t object = AddBlob(l, rng, 2000, 0, 1.0f, 0, 1900);   // 90 % of R: the main region
  const std::int64_t third = AddBlob(l, rng, 600, 5, 0.6f, 1, 200);      // 33 % < 40 % removed
  EXPECT_EQ(Find(l, {object, third, object + 5}, nullptr), (std::vector<std::uint8_t>{0, 0, 0}));
}

// The search from a row stops once its region cannot qualify: a huge feature region (a floor) is
// never walked whole, whatever the scene's size.
TEST(TakenWhole, TheSearchStopsEarlyInALargeRegion) {
  std::mt19937 rng(11);
  Layout l;
  AddBlob(l, rng, 1000, 0, 0.7f, 0, 1000);
  const std::int64_t floor = AddBlob(l, rng, 50000, 5, 4.0f, 1, 20);
  al::TakenWholeStats st;
  const auto keep = Find(l, {floor}, &st);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0}));
  EXPECT_LE(st.visited, 1020u / (2 * al::kTakenWholeRatio) + 20);
}

TEST(TakenWhole, NoRowsOrNoFeaturesOrInactiveNeighbours) {
  Scene s = MakeScene();
  EXPECT_TRUE(Find(s.l, {}, nullptr).empty());
  // Colour-like raw rows (no normalisation) work the same way.
  const al::SceneFeatureMap raw{s.l.f, false, false, Eigen::VectorXd::Zero(kDim)};
  EXPECT_EQ(al::FindTakenWhole({s.l.xyz, s.l.active, s.l.removed, raw, 0.8, 10}, {s.part}, nullptr),
            (std::vector<std::uint8_t>{1}));
  // Inactive Gaussians are never visited: with the part's kept rows inactive the part is all
  // removed, and still taken whole.
  for (std::int64_t i = s.part + 330; i < s.part + 400; ++i) s.l.active[std::size_t(i)] = 0;
  al::TakenWholeStats st;
  EXPECT_EQ(Find(s.l, {s.part}, &st), (std::vector<std::uint8_t>{1}));
  EXPECT_EQ(st.visited, 330u);
}

TEST(SceneFeatureMap, CentredUnitRowsAndZeroRows) {
  al::RowMatXf f(3, 2);
  f << 3, 4, 0, 0, 1, 0;
  Eigen::VectorXd mean(2);
  mean << 0.5, 0;
  const al::SceneFeatureMap map{f, true, true, mean};
  float out[2];
  ASSERT_TRUE(map.Row(0, out));  // (0.6, 0.8) − (0.5, 0) = (0.1, 0.8), normalised
  EXPECT_NEAR(out[0], 0.1 / std::sqrt(0.65), 1e-6);
  EXPECT_NEAR(out[1], 0.8 / std::sqrt(0.65), 1e-6);
  EXPECT_FALSE(map.Row(1, out));
  EXPECT_EQ(out[0], 0.0f);
  // Huge and tiny rows keep their direction (their squared norms leave float's range).
  al::RowMatXf scaled(2, 2);
  scaled << 3e30f, 4e30f, 3e-30f, 4e-30f;
  const al::SceneFeatureMap unit{scaled, true, false, Eigen::VectorXd::Zero(2)};
  for (int r = 0; r < 2; ++r) {
    ASSERT_TRUE(unit.Row(r, out)) << r;
    EXPECT_NEAR(out[0], 0.6f, 1e-6) << r;
    EXPECT_NEAR(out[1], 0.8f, 1e-6) << r;
  }
  const al::SceneFeatureMap plain{f, false, false, Eigen::VectorXd::Zero(2)};
  ASSERT_TRUE(plain.Row(0, out));
  EXPECT_EQ(out[1], 4.0f);
}

}  // namespace
