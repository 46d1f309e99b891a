// LoadRemovalSet for .npy masks/indices and .txt indices: polarity, range checks, duplicates,
// the 0/1 ambiguity, GC float polarity, and the index-text writer.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "al/core/error.hpp"
#include "al/io/masks.hpp"
#include "al/io/npy.hpp"
#include "test_data.hpp"

namespace {

al::Scene SceneOfSize(std::size_t n) {
  al::Scene s;
  s.means = al::MatX3f::Zero(static_cast<Eigen::Index>(n), 3);
  return s;
}

std::string WriteText(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const std::string p = (dir / name).string();
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// Version 1.0 header (magic .. '\n') for a hand-written dtype, data appended by the caller.
std::string RawNpy(std::string dict) {
  const std::size_t total = 10 + dict.size() + 1;
  dict.append((total + 63) / 64 * 64 - total, ' ');
  dict += '\n';
  return std::string("\x93NUMPY\x01\x00", 8) + char(dict.size()) + '\0' + dict;
}

// Expects al::Error naming the file and containing `needle`.
template <typename F>
void ExpectError(const std::string& path, F f, const std::string& needle) {
  try {
    f();
    FAIL() << "no error (" << needle << ")";
  } catch (const al::Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  }
}

TEST(MasksLoad, BoolAndUint8Masks) {
  const auto dir = al::test::TempDir();
  const auto scene = SceneOfSize(6);
  const std::vector<bool> mask = {true, false, false, true, false, true};
  const std::string p = (dir / "m.npy").string();
  al::WriteNpyBool(p, mask);
  const auto r = al::LoadRemovalSet(p, scene);
  EXPECT_EQ(r.removed, mask);
  EXPECT_EQ(r.num_removed, 3u);
  EXPECT_EQ(r.stats["kind"], "mask");
  EXPECT_EQ(r.stats["num_input_rows"], 6);

  // uint8: any non-zero value means removed (written by hand: the library has no u1 writer).
  std::string bytes = RawNpy("{'descr': '|u1', 'fortran_order': False, 'shape': (6,), }");
  bytes += std::string("\x00\x07\xff\x00\x01\x00", 6);
  const std::string pu = WriteText(dir, "u.npy", bytes);
  EXPECT_EQ(al::LoadRemovalSet(pu, scene).removed, (std::vector<bool>{false, true, true, false, true, false}));

  ExpectError(p, [&] { al::LoadRemovalSet(p, SceneOfSize(7)); }, "does not match");
  // Remaining polarity complements.
  al::RemovalLoadOptions opt;
  opt.removed_is = al::RemovedIs::kRemaining;
  const auto c = al::LoadRemovalSet(p, scene, opt);
  EXPECT_EQ(c.removed, (std::vector<bool>{false, true, true, false, true, false}));
  EXPECT_EQ(c.num_removed, 3u);
  EXPECT_EQ(c.stats["removed_is"], "remaining");
}

TEST(MasksLoad, IntegerIndicesDuplicatesRangeAndAmbiguity) {
  const auto dir = al::test::TempDir();
  const auto scene = SceneOfSize(10);
  const std::string p = (dir / "i.npy").string();
  al::WriteNpy(p, std::vector<std::int64_t>{7, 2, 7, 9, 2, 2}, {6});
  const auto r = al::LoadRemovalSet(p, scene);
  EXPECT_EQ(al::MaskToIndices(r.removed), (std::vector<std::int64_t>{2, 7, 9}));
  EXPECT_EQ(r.stats["kind"], "indices");
  EXPECT_EQ(r.stats["duplicates"], 3);
  EXPECT_EQ(r.warnings.size(), 1u);

  al::WriteNpy(p, std::vector<std::int32_t>{0, 10}, {2});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "index 10 out of range [0, 10)");
  al::WriteNpy(p, std::vector<std::int32_t>{-1}, {1});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "out of range");

  // Length N, only 0 and 1: probably a mask saved with an integer dtype.
  al::WriteNpy(p, std::vector<std::int32_t>{0, 1, 1, 0, 0, 0, 1, 0, 0, 0}, {10});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "ambiguous");
  // The same values with another length are plain indices.
  al::WriteNpy(p, std::vector<std::int32_t>{0, 1, 1, 0}, {4});
  const auto ok = al::LoadRemovalSet(p, scene);
  EXPECT_EQ(al::MaskToIndices(ok.removed), (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(ok.stats["duplicates"], 2);

  // Length N with repeats: per-Gaussian labels passed as --removed, never read as indices.
  al::WriteNpy(p, std::vector<std::int32_t>{0, 0, 3, 3, 3, 5, 5, 0, 2, 2}, {10});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "not an index list");
  // A permutation of all N indices is a valid (full) removal.
  al::WriteNpy(p, std::vector<std::int32_t>{9, 8, 7, 6, 5, 4, 3, 2, 1, 0}, {10});
  EXPECT_EQ(al::LoadRemovalSet(p, scene).num_removed, 10u);

  al::WriteNpy(p, std::vector<std::int32_t>{1, 2, 3, 4}, {2, 2});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "1-D");
}

TEST(MasksLoad, UnsignedIndicesAboveInt64AreOutOfRange) {
  const auto dir = al::test::TempDir();
  const std::uint64_t v = std::numeric_limits<std::uint64_t>::max();
  std::string bytes = RawNpy("{'descr': '<u8', 'fortran_order': False, 'shape': (1,), }");
  bytes.append(reinterpret_cast<const char*>(&v), 8);
  const std::string p = WriteText(dir, "u8.npy", bytes);
  ExpectError(p, [&] { al::LoadRemovalSet(p, SceneOfSize(4)); }, "out of range");
}

TEST(MasksLoad, FloatArraysNeedGcPolarity) {
  const auto dir = al::test::TempDir();
  const auto scene = SceneOfSize(5);
  const std::string p = (dir / "f.npy").string();
  al::WriteNpy(p, std::vector<double>{0.0, 1.0, -0.0, 1e-300, std::nan("")}, {5});
  ExpectError(p, [&] { al::LoadRemovalSet(p, scene); }, "polarity");
  al::RemovalLoadOptions gc;
  gc.gc_polarity = true;
  const auto r = al::LoadRemovalSet(p, scene, gc);
  EXPECT_EQ(r.removed, (std::vector<bool>{true, false, true, false, false}));  // exactly 0 only
  EXPECT_EQ(r.stats["kind"], "gc_float");
  ExpectError(p, [&] { al::LoadRemovalSet(p, SceneOfSize(4), gc); }, "does not match");
}

TEST(MasksLoad, TextIndicesCommentsBlankLinesAndErrors) {
  const auto dir = al::test::TempDir();
  const auto scene = SceneOfSize(20);
  const std::string p = WriteText(dir, "r.txt",
                                  "# removed rows\n"
                                  "3\n"
                                  "\n"
                                  "   17   # trailing comment\r\n"
                                  "+5\n"
                                  "\t3\n"
                                  "# 99 commented out\n"
                                  "0");
  const auto r = al::LoadRemovalSet(p, scene);
  EXPECT_EQ(al::MaskToIndices(r.removed), (std::vector<std::int64_t>{0, 3, 5, 17}));
  EXPECT_EQ(r.stats["kind"], "txt");
  EXPECT_EQ(r.stats["num_input_rows"], 5);
  EXPECT_EQ(r.stats["duplicates"], 1);

  const std::string bad = WriteText(dir, "bad.txt", "1\n2\n\n3.5\n");
  ExpectError(bad, [&] { al::LoadRemovalSet(bad, scene); }, "line 4: '3.5' is not an integer");
  const std::string two = WriteText(dir, "two.txt", "1 2\n");
  ExpectError(two, [&] { al::LoadRemovalSet(two, scene); }, "line 1");
  const std::string range = WriteText(dir, "range.txt", "1\n# x\n20\n");
  ExpectError(range, [&] { al::LoadRemovalSet(range, scene); }, "out of range [0, 20) at line 3");
  const std::string neg = WriteText(dir, "neg.txt", "-1\n");
  ExpectError(neg, [&] { al::LoadRemovalSet(neg, scene); }, "out of range");
  const std::string huge = WriteText(dir, "huge.txt", "99999999999999999999999\n");
  ExpectError(huge, [&] { al::LoadRemovalSet(huge, scene); }, "line 1");
  // Ambiguity is a property of typed arrays; a text list is always indices.
  const std::string empty = WriteText(dir, "empty.txt", "# nothing removed\n\n");
  EXPECT_EQ(al::LoadRemovalSet(empty, scene).num_removed, 0u);

  const std::string other = WriteText(dir, "r.csv", "1\n");
  ExpectError(other, [&] { al::LoadRemovalSet(other, scene); }, "format");
  ExpectError((dir / "absent.txt").string(), [&] { al::LoadRemovalSet((dir / "absent.txt").string(), scene); },
              "cannot open");
}

TEST(MasksLoad, WriteIndexTextRoundTrip) {
  const auto dir = al::test::TempDir();
  const auto scene = SceneOfSize(1000);
  std::vector<bool> mask(1000, false);
  for (std::size_t i = 0; i < mask.size(); i += 7) mask[i] = true;
  const auto idx = al::MaskToIndices(mask);
  EXPECT_EQ(idx.size(), 143u);
  const std::string p = (dir / "refined.txt").string();
  al::WriteIndexText(p, idx, "refined removed set\nk=10 delta=0.8");
  std::ifstream in(p);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "# refined removed set");
  const auto r = al::LoadRemovalSet(p, scene);
  EXPECT_EQ(r.removed, mask);
  EXPECT_EQ(r.stats["duplicates"], 0);
  al::WriteIndexText(p, {});
  EXPECT_EQ(std::filesystem::file_size(p), 0u);
}

}  // namespace
