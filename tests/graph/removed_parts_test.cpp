// FindSecondObject (al/graph/removed_parts.hpp) on hand-made layouts whose answer is known: two
// separate removed blobs with different features are two objects; the same features, a small
// fragment, a touching blob or featureless rows are not.
#include <gtest/gtest.h>

#include <random>

#include "al/graph/graph.hpp"
#include "al/graph/removed_parts.hpp"

namespace {

constexpr int kDim = 4;

struct Layout {
  std::vector<float> xyz;
  std::vector<double> removed;
  al::RowMatXf f = al::RowMatXf(0, kDim);
  std::vector<std::int64_t> ids;
};

// n points uniformly in a unit cube at x offset `x0`, features near `axis` (zero rows if axis < 0).
void AddBlob(Layout& l, std::mt19937& rng, int n, float x0, int axis, bool removed) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  for (int i = 0; i < n; ++i) {
    l.xyz.insert(l.xyz.end(), {x0 + u(rng), u(rng), u(rng)});
    l.removed.push_back(removed ? 1.0 : 0.0);
    Eigen::RowVectorXf v = Eigen::RowVectorXf::Zero(kDim);
    if (axis >= 0) {
      for (int d = 0; d < kDim; ++d) v[d] = noise(rng) + (d == axis ? 1.0f : 0.0f);
      v *= 3.0f;  // raw features need not be unit rows
    }
    l.f.conservativeResize(l.f.rows() + 1, kDim);
    l.f.row(l.f.rows() - 1) = v;
    l.ids.push_back(std::int64_t(l.ids.size()));
  }
}

al::SecondObject Find(const Layout& l) {
  al::KnnOptions o;
  o.k = 10;
  const al::KnnResult knn = al::KnnAmongPoints(l.xyz, o);
  return al::FindSecondObject(knn, al::MedianKnnEdgeLength(knn, l.xyz), l.removed, l.f, l.ids);
}

TEST(SecondObject, TwoSeparateObjectsWithDifferentFeatures) {
  std::mt19937 rng(1);
  Layout l;
  AddBlob(l, rng, 600, 0.0f, 0, true);   // the larger part
  AddBlob(l, rng, 400, 5.0f, 1, true);   // a look-alike 5 units away
  AddBlob(l, rng, 500, 2.5f, 2, false);  // kept background between them
  const al::SecondObject so = Find(l);
  ASSERT_TRUE(so.Found());
  EXPECT_EQ(so.rows, 400u);
  EXPECT_EQ(so.largest_rows, 600u);
  EXPECT_NEAR(so.share, 0.4, 1e-12);
  EXPECT_LT(so.cosine, 0.2);
  EXPECT_TRUE(so.ToJson().is_object());
  // The parts' scene rows: the first blob is rows 0..599, the look-alike 600..999.
  ASSERT_EQ(so.largest_scene_rows.size(), 600u);
  ASSERT_EQ(so.second_scene_rows.size(), 400u);
  EXPECT_EQ(so.largest_scene_rows.front(), 0);
  EXPECT_EQ(so.largest_scene_rows.back(), 599);
  EXPECT_EQ(so.second_scene_rows.front(), 600);
  EXPECT_EQ(so.second_scene_rows.back(), 999);
}

TEST(SecondObject, NotForPartsOfOneObjectAFragmentOrATouchingBlob) {
  std::mt19937 rng(2);
  Layout same;  // one object split in two parts: same features
  AddBlob(same, rng, 600, 0.0f, 0, true);
  AddBlob(same, rng, 400, 5.0f, 0, true);
  EXPECT_FALSE(Find(same).Found());
  EXPECT_TRUE(Find(same).ToJson().is_null());
  Layout fragment;  // a different object, but only 10 % of the removed set
  AddBlob(fragment, rng, 900, 0.0f, 0, true);
  AddBlob(fragment, rng, 100, 5.0f, 1, true);
  EXPECT_FALSE(Find(fragment).Found());
  Layout touching;  // different features but one spatial part (SAGS's neighbour): not separable here
  AddBlob(touching, rng, 600, 0.0f, 0, true);
  AddBlob(touching, rng, 400, 0.9f, 1, true);
  EXPECT_FALSE(Find(touching).Found());
  Layout featureless;  // zero rows carry no direction: no evidence of a second object
  AddBlob(featureless, rng, 600, 0.0f, 0, true);
  AddBlob(featureless, rng, 400, 5.0f, -1, true);
  EXPECT_FALSE(Find(featureless).Found());
}

TEST(SecondObject, EmptyOrFullMasksAndScaleInvariance) {
  std::mt19937 rng(3);
  Layout none;
  AddBlob(none, rng, 300, 0.0f, 0, false);
  EXPECT_FALSE(Find(none).Found());
  Layout all;
  AddBlob(all, rng, 300, 0.0f, 0, true);
  EXPECT_FALSE(Find(all).Found());
  // The link length is relative to the kNN edges: the answer does not change with the units.
  for (float scale : {1e-6f, 1e6f}) {
    std::mt19937 r2(1);
    Layout l;
    AddBlob(l, r2, 600, 0.0f, 0, true);
    AddBlob(l, r2, 400, 5.0f, 1, true);
    for (float& c : l.xyz) c *= scale;
    const al::SecondObject so = Find(l);
    ASSERT_TRUE(so.Found()) << scale;
    EXPECT_EQ(so.rows, 400u) << scale;
  }
}

}  // namespace
