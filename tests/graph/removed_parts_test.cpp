// FindSecondObject (al/graph/removed_parts.hpp) on hand-made layouts whose answer is known: two
// separate removed blobs with different features are two objects; the same features, a small
// fragment, a touching blob or featureless rows are not. FindWholeObjectGroup (same header) on
// the touching case: an object removed whole beside a neighbour removed in part.
#include <gtest/gtest.h>

#include <random>

#include "al/graph/graph.hpp"
#include "al/graph/prior.hpp"
#include "al/graph/removed_parts.hpp"

namespace {

constexpr int kDim = 4;

struct Layout {
  std::vector<float> xyz;
  std::vector<double> removed;
  al::RowMatXf f = al::RowMatXf(0, kDim);
  std::vector<std::int64_t> ids;
};

// n points uniformly in a unit cube at x offset `x0`, features near `axis` (zero rows if axis < 0),
// leaning by `lean` toward axis `lean_axis`.
void AddBlob(Layout& l, std::mt19937& rng, int n, float x0, int axis, bool removed, int lean_axis = 0,
             float lean = 0.0f) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.1f);
  for (int i = 0; i < n; ++i) {
    l.xyz.insert(l.xyz.end(), {x0 + u(rng), u(rng), u(rng)});
    l.removed.push_back(removed ? 1.0 : 0.0);
    Eigen::RowVectorXf v = Eigen::RowVectorXf::Zero(kDim);
    if (axis >= 0) {
      for (int d = 0; d < kDim; ++d) v[d] = noise(rng) + (d == axis ? 1.0f : 0.0f) + (d == lean_axis ? lean : 0.0f);
      v *= 3.0f;  // raw features need not be unit rows
    }
    l.f.conservativeResize(l.f.rows() + 1, kDim);
    l.f.row(l.f.rows() - 1) = v;
    l.ids.push_back(std::int64_t(l.ids.size()));
  }
}

// Two parts' scene rows when the layout's first blob (rows 0..599) and second (600..999) are
// the parts: `first` and `second` are exactly those rows, ascending.
void ExpectBlobRows(const std::vector<std::int64_t>& first, const std::vector<std::int64_t>& second) {
  ASSERT_EQ(first.size(), 600u);
  ASSERT_EQ(second.size(), 400u);
  EXPECT_EQ(first.front(), 0);
  EXPECT_EQ(first.back(), 599);
  EXPECT_EQ(second.front(), 600);
  EXPECT_EQ(second.back(), 999);
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
  ExpectBlobRows(so.largest_scene_rows, so.second_scene_rows);  // the first blob, the look-alike
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

// The prior's groups of a layout, and the parts FindWholeObjectGroup finds in them.
al::FeatureGroupParts GroupsOf(const Layout& l, al::PriorSwitch prototype_credit, al::KeptCredit credit,
                               al::PriorStats* stats) {
  al::RowMatXf unit = l.f;
  unit.rowwise().normalize();
  al::PriorOptions o;
  o.prototype_credit = prototype_credit;
  std::vector<double> upper;
  al::FeaturePrior(unit, l.removed, o, stats, credit, &upper);
  return al::FindWholeObjectGroup(*stats, upper, l.removed, l.ids);
}

// SAGS's touching neighbour: object A (rows 0..599) removed whole, neighbour B's near side (rows
// 600..999) removed and its far side (1000..1299) kept, background kept; B's features lean toward
// the background's (a neighbour's toward the table it stands on). near_side_axis < 0: B's removed
// rows are featureless.
Layout TouchingNeighbour(unsigned seed, int near_side_axis = 1) {
  std::mt19937 rng(seed);
  Layout l;
  AddBlob(l, rng, 600, 0.0f, 0, true);
  AddBlob(l, rng, 400, 1.0f, near_side_axis, true, 2, 1.0f);
  AddBlob(l, rng, 300, 2.0f, 1, false, 2, 1.0f);
  AddBlob(l, rng, 600, 3.0f, 2, false);
  AddBlob(l, rng, 300, -1.0f, 3, false);
  return l;
}

// One spatial part, but the prior's upper group is A alone, removed whole, and B's group stands
// apart: two parts, by group.
TEST(WholeObjectGroup, AnObjectTakenWholeBesideANeighbourTakenInPart) {
  const Layout l = TouchingNeighbour(4);
  EXPECT_FALSE(Find(l).Found());  // touching: not a second object in space
  al::PriorStats st;
  const al::FeatureGroupParts g = GroupsOf(l, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st);
  EXPECT_GE(st.removal_rate_upper, al::kWholeGroupRate);
  EXPECT_GE(st.separation, al::kApartSeparation);
  ASSERT_TRUE(g.Found());
  ExpectBlobRows(g.object_rows, g.other_rows);  // object A, neighbour B's near side
  EXPECT_EQ(g.ToJson()["other_rows"], 400);
}

// Not when the object group still has misses (its completion is the job), nor when the prior gave
// no kept Gaussian credit (a second object in space, or the prototype credit off).
TEST(WholeObjectGroup, NotWithMissesOrWithoutKeptCredit) {
  const Layout l = TouchingNeighbour(5);
  std::mt19937 rng(5);
  al::PriorStats st;
  EXPECT_TRUE(GroupsOf(l, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st).Found());
  EXPECT_FALSE(GroupsOf(l, al::PriorSwitch::kOn, al::KeptCredit::kWithheld, &st).Found());
  EXPECT_FALSE(GroupsOf(l, al::PriorSwitch::kOff, al::KeptCredit::kAllowed, &st).Found());
  EXPECT_TRUE(GroupsOf(l, al::PriorSwitch::kOff, al::KeptCredit::kAllowed, &st).ToJson().is_null());
  Layout missed = l;  // A's far side kept: 60 misses of 660 (removal rate 0.91)
  AddBlob(missed, rng, 60, -0.4f, 0, false);
  EXPECT_FALSE(GroupsOf(missed, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st).Found());
  EXPECT_LT(st.removal_rate_upper, al::kWholeGroupRate);
}

// Degenerate inputs: nothing or everything removed (the prior learns nothing), and featureless
// rows (no evidence: they keep their mask value and never form the other group).
TEST(WholeObjectGroup, EmptyFullAndFeaturelessInputs) {
  std::mt19937 rng(6);
  al::PriorStats st;
  Layout none;
  AddBlob(none, rng, 300, 0.0f, 0, false);
  AddBlob(none, rng, 300, 2.0f, 1, false);
  EXPECT_FALSE(GroupsOf(none, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st).Found());
  Layout all;
  AddBlob(all, rng, 300, 0.0f, 0, true);
  AddBlob(all, rng, 300, 1.0f, 1, true);
  EXPECT_FALSE(GroupsOf(all, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st).Found());
  const Layout featureless = TouchingNeighbour(6, -1);
  const al::FeatureGroupParts g = GroupsOf(featureless, al::PriorSwitch::kOn, al::KeptCredit::kAllowed, &st);
  for (std::int64_t row : g.other_rows) EXPECT_TRUE(row < 600 || row >= 1000) << row;
}

}  // namespace
