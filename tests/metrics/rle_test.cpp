// COCO RLE decoding (compressed strings and count lists), SAM lists and GroundedSAM JSON.
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/core/memory_limit.hpp"
#include "al/metrics/mask_io.hpp"

namespace al::metrics {
namespace {

// Independent encoder written from the format description: runs after the second are stored as
// differences to the run two before; each value in 5-bit groups, low first, 0x20 = more follows,
// the last group's 0x10 bit carries the sign; characters offset by '0'.
std::string EncodeCounts(const std::vector<std::int64_t>& counts) {
  std::string s;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    std::int64_t x = counts[i];
    if (i > 2) x -= counts[i - 2];
    bool more = true;
    while (more) {
      int c = int(x & 0x1f);
      x >>= 5;  // arithmetic shift (C++20)
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      s += char(c + 48);
    }
  }
  return s;
}

// Column-major runs of a row-major mask, zeros first.
std::vector<std::int64_t> RunsOf(const Mask& m) {
  std::vector<std::int64_t> runs;
  int current = 0;
  std::int64_t run = 0;
  for (int x = 0; x < m.width; ++x)
    for (int y = 0; y < m.height; ++y) {
      const int v = m.bits[std::size_t(y) * m.width + x];
      if (v != current) runs.push_back(run), run = 0, current = v;
      ++run;
    }
  runs.push_back(run);
  return runs;
}

TEST(Rle, LiteralStringDerivedByHand) {
  // counts 5, 40, 3, 2: "5"; 40 = 8 + 1·32 → 'X' (48+8+32), '1'; "3"; 2 − 40 = −38 → groups 26 with
  // continuation (48+26+32 = 'j') and 30 with the sign bit (48+30 = 'N').
  EXPECT_EQ(DecodeCocoRleString("5X13jN"), (std::vector<std::int64_t>{5, 40, 3, 2}));
  EXPECT_EQ(EncodeCounts({5, 40, 3, 2}), "5X13jN");
  const Mask m = MaskFromRleCounts({5, 40, 3, 2}, 5, 10);  // h = 5, w = 10
  // Column-major positions 5..44 (columns 1..8 entirely) and 48..49 (column 9, rows 3 and 4).
  EXPECT_EQ(m.Count(), 42u);
  EXPECT_EQ(m.bits[0 * 10 + 0], 0);
  EXPECT_EQ(m.bits[0 * 10 + 1], 1);
  EXPECT_EQ(m.bits[4 * 10 + 8], 1);
  EXPECT_EQ(m.bits[3 * 10 + 9], 1);
  EXPECT_EQ(m.bits[4 * 10 + 9], 1);
  EXPECT_EQ(m.bits[2 * 10 + 9], 0);  // position 47
}

TEST(Rle, RandomMasksRoundTripThroughTheEncoder) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + int(rng() % 40), h = 1 + int(rng() % 40);
    Mask m = EmptyMask(w, h);
    const int density = int(rng() % 100);
    // Blocky masks give long runs (multi-character values and negative differences).
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) m.bits[std::size_t(y) * w + x] = int((x / 3 + y / 5 + rng() % 7) % 100) < density;
    const auto runs = RunsOf(m);
    const std::string s = EncodeCounts(runs);
    ASSERT_EQ(DecodeCocoRleString(s), runs) << s;
    const nlohmann::json rle = {{"size", {h, w}}, {"counts", s}};
    EXPECT_EQ(MaskFromCocoRle(rle).bits, m.bits);
    const nlohmann::json raw = {{"size", {h, w}}, {"counts", runs}};
    EXPECT_EQ(MaskFromCocoRle(raw).bits, m.bits);
  }
}

TEST(Rle, MalformedInputsAreErrors) {
  EXPECT_THROW(DecodeCocoRleString("5X"), Error);              // continuation without end... 'X' has 0x20
  EXPECT_THROW(DecodeCocoRleString(" "), Error);               // below '0'
  EXPECT_THROW(DecodeCocoRleString(std::string(20, 'o')), Error);  // never-ending value
  EXPECT_THROW(MaskFromRleCounts({3, 2}, 2, 2), Error);        // covers 5 of 4 pixels
  EXPECT_THROW(MaskFromRleCounts({1, 2}, 2, 2), Error);        // covers 3 of 4
  EXPECT_THROW(MaskFromRleCounts({-1, 5}, 2, 2), Error);
  EXPECT_THROW(MaskFromCocoRle(nlohmann::json{{"size", {2}}, {"counts", "0"}}), Error);
  EXPECT_THROW(MaskFromCocoRle(nlohmann::json{{"size", {2, 2}}, {"counts", 4}}), Error);
}

TEST(SamJson, DenseAndRleSegmentsAndLegacyMerged) {
  const std::string list = R"([
    {"segmentation": [[true, false], [false, true]], "area": 2},
    {"mask": [[0, 1], [1, 0]]},
    {"no_mask_here": 1},
    {"segmentation": {"size": [2, 2], "counts": [1, 2, 1]}},
    {"segmentation": {"size": [2, 2], "counts": "13"}}
  ])";
  const auto parsed = ParseSamJsonText(list, "x.json");
  ASSERT_EQ(parsed.count(""), 1u);
  const auto& segs = parsed.at("");
  ASSERT_EQ(segs.size(), 4u);  // the object without a mask is ignored
  EXPECT_EQ(segs[0].bits, (std::vector<std::uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(segs[1].bits, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  // Column-major runs 1,2,1 on 2×2: position 1 (row 1, col 0) and 2 (row 0, col 1) are on.
  EXPECT_EQ(segs[2].bits, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  EXPECT_EQ(segs[3].bits, (std::vector<std::uint8_t>{0, 1, 1, 1}));
  const auto merged = ParseSamJsonText(R"({"a.png": [{"mask": [[1]]}], "b": []})", "merged.json");
  EXPECT_EQ(merged.at("a").size(), 1u);
  EXPECT_EQ(merged.at("b").size(), 0u);
  EXPECT_THROW(ParseSamJsonText("[{\"segmentation\": [[1, 0], [1]]}]", "r.json"), Error);  // ragged
  EXPECT_THROW(ParseSamJsonText("{", "broken.json"), Error);
  EXPECT_THROW(ParseSamJsonText("3", "n.json"), Error);
  try {
    ParseSamJsonText("[{\"segmentation\": \"x\"}]", "dir/file.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("dir/file.json"), std::string::npos);  // names the file
  }
}

// A few bytes of COCO RLE can declare a 67-Mpixel mask: a file of many is refused from the declared
// sizes (exit 2, estimate and limit in the message) before a mask is allocated.
TEST(SamJson, MasksOverTheMemoryLimitAreRefusedBeforeDecoding) {
  nlohmann::json list = nlohmann::json::array();
  for (int i = 0; i < 100; ++i)  // 100 x 8192 x 8192 x 1 B = 6.25 GiB
    list.push_back({{"segmentation", {{"size", {8192, 8192}}, {"counts", {std::int64_t(8192) * 8192}}}}});
  SetMemoryLimitBytes(std::uint64_t(1) << 30);
  try {
    ParseSamJsonText(list.dump(), "huge.json");
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::kBadInput);
    EXPECT_NE(std::string(e.what()).find("100 SAM masks needs about 6.2 GiB"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("memory limit of 1.0 GiB"), std::string::npos) << e.what();
  }
  list.erase(list.begin() + 2, list.end());  // 2 masks: 128 MiB, under the limit
  EXPECT_EQ(ParseSamJsonText(list.dump(), "ok.json").at("").size(), 2u);
  SetMemoryLimitBytes(0);  // back to the default
}

TEST(GroundedSam, UnionOfThePromptsInstances) {
  const std::string text = R"({
    "annotations": [
      {"class_name": "Teddy Bear.", "segmentation": {"size": [2, 3], "counts": [0, 1, 5]}},
      {"class_name": "teddy bear", "segmentation": {"size": [2, 3], "counts": [5, 1]}},
      {"class_name": "chair", "segmentation": {"size": [2, 3], "counts": [2, 1, 3]}}
    ],
    "img_width": 3, "img_height": 2, "box_format": "xyxy"})";
  const GroundedSamMask bear = ParseGroundedSamText(text, "teddy bear", "g.json");
  EXPECT_EQ(bear.instances, 2u);
  EXPECT_EQ(bear.annotations, 3u);
  EXPECT_EQ(bear.mask.width, 3);
  EXPECT_EQ(bear.mask.height, 2);
  // Column-major position 0 → (0,0); position 5 → (row 1, col 2).
  EXPECT_EQ(bear.mask.pixels, (std::vector<std::uint8_t>{255, 0, 0, 0, 0, 255}));
  const GroundedSamMask all = ParseGroundedSamText(text, "", "g.json");
  EXPECT_EQ(all.instances, 3u);
  EXPECT_EQ(all.mask.pixels[1], 255);  // chair: position 2 → (row 0, col 1)
  const GroundedSamMask none = ParseGroundedSamText(text, "lamp", "g.json");
  EXPECT_EQ(none.instances, 0u);
  EXPECT_EQ(none.mask.pixels, std::vector<std::uint8_t>(6, 0));
  EXPECT_THROW(ParseGroundedSamText("{}", "", "g.json"), Error);
}

}  // namespace
}  // namespace al::metrics
