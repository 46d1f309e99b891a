// TrimOneSidedAdditions (al/graph/either_object.hpp) on hand-made layouts: two removed parts A and B
// and additions beside them. The two readings' F1 are recomputed here from the sets themselves
// (not from the counts the implementation uses): after trimming neither reading loses more than
// the tolerance, one addition fewer taken back would break that, and what is taken back is the
// farthest from its part.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "al/graph/either_object.hpp"

namespace {

struct Layout {
  std::vector<float> xyz;
  std::vector<bool> removed, refined;
  std::vector<std::int64_t> part_a, part_b;
  std::vector<int> owner;  // per row: 0 = A (or beside A), 1 = B (or beside B), -1 = elsewhere
};

// n rows uniformly in [x0, x1] × [0, 1]²; removed rows join part `owner`'s list, added rows are
// refined but not removed.
void AddRows(Layout& l, std::mt19937& rng, int n, float x0, float x1, int owner, bool removed, bool refined) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < n; ++i) {
    const auto row = std::int64_t(l.removed.size());
    l.xyz.insert(l.xyz.end(), {x0 + (x1 - x0) * u(rng), u(rng), u(rng)});
    l.removed.push_back(removed);
    l.refined.push_back(refined);
    l.owner.push_back(owner);
    if (removed) (owner == 0 ? l.part_a : l.part_b).push_back(row);
  }
}

// Part A (600 rows) at x ∈ [0, 1], part B (400) at [5, 6], kept background between them, and
// `beside_a` / `beside_b` additions just outside each part.
Layout TwoParts(int beside_a, int beside_b) {
  std::mt19937 rng(7);
  Layout l;
  AddRows(l, rng, 600, 0.0f, 1.0f, 0, true, true);
  AddRows(l, rng, 400, 5.0f, 6.0f, 1, true, true);
  AddRows(l, rng, 500, 2.0f, 4.0f, -1, false, false);
  AddRows(l, rng, beside_a, 1.0f, 1.6f, 0, false, true);
  AddRows(l, rng, beside_b, 4.4f, 5.0f, 1, false, true);
  return l;
}

double F1(const std::vector<bool>& set, const std::vector<bool>& object) {
  std::size_t tp = 0, n_set = 0, n_object = 0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    tp += set[i] && object[i];
    n_set += set[i];
    n_object += object[i];
  }
  return 2.0 * double(tp) / double(n_set + n_object);
}

// ΔF1 of `after` under the reading "the object is part h and what the refinement added beside it".
double ReadingDelta(const Layout& l, const std::vector<bool>& after, int h) {
  std::vector<bool> object(l.removed.size());
  for (std::size_t i = 0; i < object.size(); ++i) object[i] = l.owner[i] == h;
  return F1(after, object) - F1(l.removed, object);
}

std::vector<bool> Apply(const Layout& l, const std::vector<std::int64_t>& back) {
  std::vector<bool> after = l.refined;
  for (std::int64_t row : back) after[std::size_t(row)] = false;
  return after;
}

TEST(EitherObject, OneSidedAdditionsAreTrimmedJustEnough) {
  const Layout l = TwoParts(200, 0);
  const double tol = 0.005;
  ASSERT_LT(ReadingDelta(l, l.refined, 1), -0.05);  // all 200 are wrong if B is the target
  al::EitherObjectStats st;
  const auto back = al::TrimOneSidedAdditions({l.xyz, l.removed, l.part_a, l.part_b, tol}, l.refined, &st);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(st.trimmed, back.size());
  EXPECT_EQ(st.trimmed_part, 0);
  EXPECT_EQ(st.added[0], 200u);
  EXPECT_EQ(st.added[1], 0u);
  EXPECT_TRUE(std::is_sorted(back.begin(), back.end()));
  const std::vector<bool> after = Apply(l, back);
  EXPECT_GE(ReadingDelta(l, after, 1), -tol);
  EXPECT_GE(ReadingDelta(l, after, 0), -tol);
  EXPECT_NEAR(st.worst_after, std::min(ReadingDelta(l, after, 0), ReadingDelta(l, after, 1)), 1e-12);
  // Minimal: giving back one of them again breaks the B reading.
  std::vector<bool> one_more = after;
  one_more[std::size_t(back.front())] = true;
  EXPECT_LT(ReadingDelta(l, one_more, 1), -tol);
  // Farthest first (brute force): every addition taken back lies at least as far from part A as
  // every kept one.
  double nearest_back = 1e30, farthest_kept = 0.0;
  for (std::size_t i = 1500; i < l.removed.size(); ++i) {
    double d = 1e30;
    for (std::int64_t a : l.part_a) {
      double s = 0;
      for (int c = 0; c < 3; ++c) s += std::pow(double(l.xyz[3 * i + c]) - l.xyz[3 * std::size_t(a) + c], 2);
      d = std::min(d, s);
    }
    if (after[i]) farthest_kept = std::max(farthest_kept, d);
    else nearest_back = std::min(nearest_back, d);
  }
  EXPECT_GE(nearest_back, farthest_kept * (1 - 1e-5));  // float vs double distances
}

TEST(EitherObject, BalancedAdditionsStay) {
  const Layout l = TwoParts(120, 80);  // in proportion to the parts: both readings gain
  ASSERT_GT(ReadingDelta(l, l.refined, 0), 0.0);
  ASSERT_GT(ReadingDelta(l, l.refined, 1), 0.0);
  al::EitherObjectStats st;
  EXPECT_TRUE(al::TrimOneSidedAdditions({l.xyz, l.removed, l.part_a, l.part_b, 0.0}, l.refined, &st).empty());
  EXPECT_EQ(st.trimmed_part, -1);
  EXPECT_EQ(st.added[0], 120u);
  EXPECT_EQ(st.added[1], 80u);
  EXPECT_GT(st.worst_before, 0.0);
}

TEST(EitherObject, ToleranceOneNeverTrims) {
  const Layout l = TwoParts(200, 0);
  EXPECT_TRUE(al::TrimOneSidedAdditions({l.xyz, l.removed, l.part_a, l.part_b, 1.0}, l.refined).empty());
}

TEST(EitherObject, NothingToDoWithoutAdditionsOrParts) {
  const Layout none = TwoParts(0, 0);
  al::EitherObjectStats st;
  EXPECT_TRUE(al::TrimOneSidedAdditions({none.xyz, none.removed, none.part_a, none.part_b, 0.0}, none.refined, &st).empty());
  EXPECT_EQ(st.trimmed, 0u);
  const Layout l = TwoParts(200, 0);
  const std::vector<std::int64_t> empty;
  EXPECT_TRUE(al::TrimOneSidedAdditions({l.xyz, l.removed, l.part_a, empty, 0.0}, l.refined).empty());
}

// Restores count in both readings: with the B part's rows given back, the B reading is already
// below the tolerance and stays there however many additions are taken back; trimming then keeps
// the additions that lift the worse reading highest, here none of them.
TEST(EitherObject, RestoresThatNoTrimCanMendTakeNothingBack) {
  Layout l = TwoParts(0, 30);
  for (std::size_t t = 0; t < 200; ++t) l.refined[std::size_t(l.part_b[t])] = false;
  ASSERT_LT(ReadingDelta(l, l.refined, 1), -0.01);
  al::EitherObjectStats st;
  const auto back = al::TrimOneSidedAdditions({l.xyz, l.removed, l.part_a, l.part_b, 0.005}, l.refined, &st);
  EXPECT_EQ(st.restored[1], 200u);
  EXPECT_TRUE(back.empty());  // only part A's additions could lift the B reading, and there are none
  EXPECT_NEAR(st.worst_after, ReadingDelta(l, l.refined, 1), 1e-12);
}

}  // namespace
