// Subset matching (FORMATS.md §2.4): in-order pass, hash pass with exact clones, tolerance pass,
// bitwise keys, and LoadRemovalSet on subset PLY files written with al::WritePly.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>

#include "al/core/error.hpp"
#include "al/io/masks.hpp"
#include "al/io/ply.hpp"
#include "test_data.hpp"

namespace {

al::Scene RandomScene(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.f, 1.f);
  al::Scene s;
  const auto rows = static_cast<Eigen::Index>(n);
  s.means.resize(rows, 3);
  s.log_scales.resize(rows, 3);
  s.rotations.resize(rows, 4);
  s.opacity_logits.resize(rows);
  s.sh.resize(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (int c = 0; c < 3; ++c) s.means(i, c) = g(rng), s.log_scales(i, c) = g(rng) - 3, s.sh(i, c) = g(rng);
    for (int c = 0; c < 4; ++c) s.rotations(i, c) = g(rng);
    s.opacity_logits(i) = g(rng);
  }
  s.has_opacity = s.has_scales = s.has_rotations = s.has_f_dc = true;
  return s;
}

void CopyRow(const al::Scene& from, std::size_t i, al::Scene& to, std::size_t j) {
  const auto a = static_cast<Eigen::Index>(i), b = static_cast<Eigen::Index>(j);
  to.means.row(b) = from.means.row(a);
  to.log_scales.row(b) = from.log_scales.row(a);
  to.rotations.row(b) = from.rotations.row(a);
  to.opacity_logits(b) = from.opacity_logits(a);
  to.sh.row(b) = from.sh.row(a);
}

al::Scene Rows(const al::Scene& s, const std::vector<std::size_t>& rows) {
  al::Scene out = RandomScene(rows.size(), 0);
  for (std::size_t j = 0; j < rows.size(); ++j) CopyRow(s, rows[j], out, j);
  return out;
}

bool SameKey(const al::Scene& a, std::int64_t i, const al::Scene& b, std::size_t j) {
  auto eq = [](float x, float y) { return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); };
  for (int c = 0; c < 3; ++c)
    if (!eq(a.means(i, c), b.means(j, c)) || !eq(a.log_scales(i, c), b.log_scales(j, c)) || !eq(a.sh(i, c), b.sh(j, c)))
      return false;
  for (int c = 0; c < 4; ++c)
    if (!eq(a.rotations(i, c), b.rotations(j, c))) return false;
  return eq(a.opacity_logits(i), b.opacity_logits(j));
}

TEST(MasksSubset, InOrderWithExactClones) {
  al::Scene scene = RandomScene(200, 1);
  CopyRow(scene, 10, scene, 11);  // clones: rows 10, 11, 50
  CopyRow(scene, 10, scene, 50);
  const al::Scene sub = Rows(scene, {5, 10, 11, 50, 120});
  const auto m = al::MatchSubset(scene, sub);
  EXPECT_EQ(m.scene_index, (std::vector<std::int64_t>{5, 10, 11, 50, 120}));
  EXPECT_EQ(m.matched_in_order, 5u);
  EXPECT_EQ(m.matched_by_hash, 0u);
  EXPECT_EQ(m.unmatched, 0u);
  EXPECT_EQ(m.ambiguous, 3u);
}

TEST(MasksSubset, ShuffledFallsBackToHashSmallestUnusedIndex) {
  al::Scene scene = RandomScene(200, 2);
  CopyRow(scene, 10, scene, 50);
  const al::Scene sub = Rows(scene, {120, 5, 50, 10});
  const auto m = al::MatchSubset(scene, sub);
  // Pass 1 matches row 120, then cannot find row 5 after it; pass 2 takes the smallest unused
  // index of each key, so the two clones map to 10 and 50 in subset order.
  EXPECT_EQ(m.matched_in_order, 1u);
  EXPECT_EQ(m.matched_by_hash, 3u);
  EXPECT_EQ(m.scene_index, (std::vector<std::int64_t>{120, 5, 10, 50}));
  EXPECT_EQ(m.ambiguous, 2u);
}

TEST(MasksSubset, RandomisedAgainstBruteForce) {
  for (std::uint32_t seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(seed);
    const std::size_t n = 300;
    al::Scene pool = RandomScene(40, seed + 100);
    al::Scene scene = RandomScene(n, seed);
    for (std::size_t i = 0; i < n; ++i) CopyRow(pool, rng() % 40, scene, i);  // many exact clones
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < n; ++i)
      if (rng() % 3 == 0) rows.push_back(i);
    const bool shuffle = seed % 2 == 1;
    if (shuffle) std::shuffle(rows.begin(), rows.end(), rng);
    al::Scene sub = Rows(scene, rows);
    const std::size_t foreign = seed % 4;  // rows absent from the scene
    if (foreign) {
      al::Scene extra = RandomScene(foreign, seed + 999);
      al::Scene both = RandomScene(rows.size() + foreign, 0);
      for (std::size_t j = 0; j < rows.size(); ++j) CopyRow(sub, j, both, j);
      for (std::size_t j = 0; j < foreign; ++j) CopyRow(extra, j, both, rows.size() + j);
      sub = both;
    }
    const auto m = al::MatchSubset(scene, sub);
    ASSERT_EQ(m.scene_index.size(), sub.size());
    std::set<std::int64_t> used;
    std::size_t matched = 0;
    for (std::size_t j = 0; j < sub.size(); ++j) {
      const std::int64_t i = m.scene_index[j];
      if (i < 0) continue;
      ++matched;
      EXPECT_TRUE(used.insert(i).second) << "index used twice";
      EXPECT_TRUE(SameKey(scene, i, sub, j));
    }
    EXPECT_EQ(matched, rows.size()) << seed;
    EXPECT_EQ(m.unmatched, foreign);
    EXPECT_EQ(m.matched_in_order + m.matched_by_hash, rows.size());
    if (!shuffle && foreign == 0) {
      EXPECT_EQ(m.matched_in_order, rows.size());
      EXPECT_EQ(m.matched_by_hash, 0u);
    }
    // Ambiguity: subset rows whose key occurs more than once in the scene (brute force).
    std::size_t ambiguous = 0;
    for (std::size_t j = 0; j < sub.size(); ++j) {
      std::size_t count = 0;
      for (std::size_t i = 0; i < n; ++i) count += SameKey(scene, static_cast<std::int64_t>(i), sub, j);
      ambiguous += count > 1;
    }
    EXPECT_EQ(m.ambiguous, ambiguous) << seed;
  }
}

TEST(MasksSubset, BitwiseKeysAndMissingColumns) {
  al::Scene scene = RandomScene(4, 3);
  scene.means(1, 0) = 0.0f;
  scene.means(2, 0) = std::nanf("");
  al::Scene sub = Rows(scene, {1, 2});
  sub.means(0, 0) = -0.0f;  // +0 and -0 differ bitwise
  auto m = al::MatchSubset(scene, sub);
  EXPECT_EQ(m.scene_index, (std::vector<std::int64_t>{-1, 2}));  // NaN matches by bits
  EXPECT_EQ(m.unmatched, 1u);

  // A subset with only x y z: the key uses the columns both files have.
  al::Scene xyz;
  xyz.means = scene.means.topRows(3);
  m = al::MatchSubset(scene, xyz);
  EXPECT_EQ(m.scene_index, (std::vector<std::int64_t>{0, 1, 2}));
  // With all columns, a changed opacity breaks the match.
  al::Scene changed = Rows(scene, {3});
  changed.opacity_logits(0) += 1.0f;
  EXPECT_EQ(al::MatchSubset(scene, changed).unmatched, 1u);
  changed.has_opacity = false;
  EXPECT_EQ(al::MatchSubset(scene, changed).unmatched, 0u);
}

TEST(MasksSubset, TolerancePassTakesNearestUnusedCentre) {
  al::Scene scene = RandomScene(100, 4);
  al::Scene sub = Rows(scene, {7, 30});
  sub.means(0, 0) += 1e-4f;  // modified positions (e.g. SAGS _gd.ply)
  auto m = al::MatchSubset(scene, sub);
  EXPECT_EQ(m.unmatched, 1u);
  m = al::MatchSubset(scene, sub, 1e-3);
  EXPECT_EQ(m.scene_index, (std::vector<std::int64_t>{7, 30}));
  EXPECT_EQ(m.matched_by_tolerance, 1u);
  EXPECT_EQ(m.unmatched, 0u);
  m = al::MatchSubset(scene, sub, 1e-5);
  EXPECT_EQ(m.unmatched, 1u);
}

class SubsetPlyFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = al::test::TempDir();
    scene_ = RandomScene(500, 5);
    CopyRow(scene_, 3, scene_, 4);  // exact clone pair
    keep_.assign(500, false);
    for (std::size_t i = 0; i < 500; ++i) keep_[i] = (i * 7919) % 5 == 0 || i == 3 || i == 4;
  }
  std::filesystem::path dir_;
  al::Scene scene_;
  std::vector<bool> keep_;
};

TEST_F(SubsetPlyFiles, RemovedAndRemainingSubsets) {
  const std::string removed = (dir_ / "seg.ply").string(), remaining = (dir_ / "rest.ply").string();
  al::WritePly(removed, scene_, keep_);
  std::vector<bool> rest(keep_.size());
  for (std::size_t i = 0; i < rest.size(); ++i) rest[i] = !keep_[i];
  al::WritePly(remaining, scene_, rest);

  const auto r = al::LoadRemovalSet(removed, scene_);
  EXPECT_EQ(r.removed, keep_);
  EXPECT_EQ(r.stats["kind"], "subset_ply");
  EXPECT_EQ(r.stats["matched_in_order"], r.num_removed);
  EXPECT_EQ(r.stats["unmatched"], 0);
  EXPECT_EQ(r.stats["ambiguous"], 2);

  al::RemovalLoadOptions opt;
  opt.removed_is = al::RemovedIs::kRemaining;
  const auto c = al::LoadRemovalSet(remaining, scene_, opt);
  EXPECT_EQ(c.removed, keep_);
  EXPECT_EQ(c.stats["num_input_rows"], 500 - static_cast<int>(r.num_removed));
}

TEST_F(SubsetPlyFiles, ShuffledSubsetUsesHashPass) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < 500; ++i)
    if (keep_[i]) rows.push_back(i);
  std::reverse(rows.begin(), rows.end());
  const std::string p = (dir_ / "shuffled.ply").string();
  al::WritePly(p, Rows(scene_, rows));
  const auto r = al::LoadRemovalSet(p, scene_);
  EXPECT_EQ(r.removed, keep_);
  EXPECT_EQ(r.stats["matched_in_order"], 1);
  EXPECT_EQ(r.stats["matched_by_hash"], rows.size() - 1);
}

TEST_F(SubsetPlyFiles, UnmatchedRowsAboveTheLimitFail) {
  std::vector<std::size_t> rows = {1, 2, 10, 20};
  al::Scene sub = Rows(scene_, rows);
  sub.means(1, 2) += 0.5f;
  sub.means(3, 1) += 0.5f;
  const std::string p = (dir_ / "moved.ply").string();
  al::WritePly(p, sub);
  try {
    al::LoadRemovalSet(p, scene_);
    FAIL() << "unmatched rows accepted";
  } catch (const al::Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(p + ": 2 of 4 subset rows", 0), 0u) << msg;
    EXPECT_NE(msg.find("row 1 "), std::string::npos) << msg;
    EXPECT_NE(msg.find("row 3 "), std::string::npos) << msg;
  }
  al::RemovalLoadOptions opt;
  opt.max_unmatched = 2;
  const auto r = al::LoadRemovalSet(p, scene_, opt);
  EXPECT_EQ(al::MaskToIndices(r.removed), (std::vector<std::int64_t>{1, 10}));
  EXPECT_EQ(r.stats["unmatched"], 2);
  EXPECT_FALSE(r.warnings.empty());
}

TEST(MasksSubsetReal, EverySeventhRowOfScene9k) {
  AL_REQUIRE_SHARED_DATA(data);
  const std::string path = (data / "real_ply" / "scene_9k.ply").string();
  const al::Scene scene = al::ReadPly(path);
  std::vector<bool> keep(scene.size(), false);
  for (std::size_t i = 0; i < keep.size(); i += 7) keep[i] = true;
  const auto dir = al::test::TempDir();
  const std::string sub = (dir / "sub.ply").string();
  al::WritePly(sub, scene, keep);  // byte-exact copy of the kept records
  const auto r = al::LoadRemovalSet(sub, scene);
  EXPECT_EQ(r.removed, keep);
  EXPECT_EQ(r.stats["matched_in_order"], r.num_removed);
  EXPECT_EQ(r.num_removed, (scene.size() + 6) / 7);
}

}  // namespace
