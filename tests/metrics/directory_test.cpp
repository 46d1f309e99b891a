// End-to-end directory metrics on a generated scene in the released layout (PNG masks 8- and
// 16-bit, GroundedSAM JSON, depth pairs, SAM lists, missing and unreadable files).
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/io/image.hpp"
#include "al/metrics/directory.hpp"
#include "test_data.hpp"

namespace al::metrics {
namespace {

namespace fs = std::filesystem;
constexpr int kW = 8, kH = 6;

// 0/255 image with the rectangle [x0,x1)×[y0,y1) set.
Image8 Rect(int x0, int y0, int x1, int y1, std::uint8_t on = 255, std::uint8_t off = 0) {
  Image8 img{kW, kH, 1, std::vector<std::uint8_t>(kW * kH, off)};
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) img.pixels[y * kW + x] = on;
  return img;
}

void Write(const fs::path& p, const Image8& img) {
  fs::create_directories(p.parent_path());
  WritePng8(p.string(), img);
}

void WriteText(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

nlohmann::json DenseSegment(int x0, int y0, int x1, int y1) {
  nlohmann::json rows = nlohmann::json::array();
  for (int y = 0; y < kH; ++y) {
    nlohmann::json row = nlohmann::json::array();
    for (int x = 0; x < kW; ++x) row.push_back(x >= x0 && x < x1 && y >= y0 && y < y1);
    rows.push_back(row);
  }
  return {{"segmentation", rows}};
}

fs::path MakeScene() {
  const fs::path d = test::TempDir() / "scene";
  // a: detected before, gone after; 60-level depth change on the object.
  Write(d / "masks/a.png", Rect(2, 1, 6, 4));
  Write(d / "gsam2/before/mask/a.png", Rect(2, 1, 6, 4));
  Write(d / "gsam2/after/mask/a.png", Rect(0, 0, 0, 0));
  Write(d / "depth/before/a.png", Rect(2, 1, 6, 4, 40, 100));
  Write(d / "depth/after/a.png", Rect(0, 0, 0, 0, 0, 100));
  // b: object mask stored as 16-bit (0/65535); no after-detection file (empty mask); the
  // before-detection is GroundedSAM JSON with two instances of the class and one other.
  Image16 b16{kW, kH, std::vector<std::uint16_t>(kW * kH, 0)};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) b16.pixels[y * kW + x] = 65535;
  fs::create_directories(d / "masks");
  WritePng16((d / "masks/b.png").string(), b16);
  // Column-major runs on 6 rows: column 0 rows 0-1, then column 1 rows 0-1 (instance 1) and
  // columns 2-3 rows 0-1 (instance 2), a "chair" elsewhere.
  const std::string gsam = R"({"img_width": 8, "img_height": 6, "annotations": [
      {"class_name": "bear", "segmentation": {"size": [6, 8], "counts": [0, 2, 4, 2, 40]}},
      {"class_name": "bear.", "segmentation": {"size": [6, 8], "counts": [12, 2, 4, 2, 28]}},
      {"class_name": "chair", "segmentation": {"size": [6, 8], "counts": [47, 1]}}]})";
  WriteText(d / "gsam2/before/mask/b.json", gsam);
  Write(d / "depth/before/b.png", Rect(0, 0, 0, 0, 0, 100));  // no after: counted, skipped
  // An unreadable object mask: the semantic metrics skip it and count it.
  WriteText(d / "masks/broken.png", "not a png");
  // SAM lists: a has both sides; b has no side B.
  nlohmann::json side_a = {DenseSegment(2, 1, 6, 4), DenseSegment(0, 0, 1, 1)};
  nlohmann::json side_b = {DenseSegment(2, 1, 4, 4)};
  WriteText(d / "masks/a.json", side_a.dump());
  WriteText(d / "masks/b.json", side_a.dump());
  WriteText(d / "sam/after/a.json", side_b.dump());
  return d;
}

TEST(DirectoryMetrics, PublishedLayoutEndToEnd) {
  const fs::path dir = MakeScene();
  DirectoryMetricsOptions o;
  o.dir = dir;
  o.seg_class = "bear";
  const DirectoryMetricsResult r = EvaluateDirectory(o);

  ASSERT_TRUE(r.ran_semantic);
  ASSERT_EQ(r.semantic.size(), 2u);  // broken.png skipped
  EXPECT_EQ(r.counts["semantic"]["unreadable_object_masks"], 1);
  EXPECT_EQ(r.semantic[0].image_name, "a.png");
  EXPECT_DOUBLE_EQ(r.semantic[0].iou_before, 1.0);
  EXPECT_DOUBLE_EQ(r.semantic[0].iou_after, 0.0);
  EXPECT_DOUBLE_EQ(r.semantic[0].acc_after, 1.0);
  // b: 16-bit object mask of 8 pixels; GroundedSAM union covers columns 0-3 rows 0-1 = the object.
  EXPECT_EQ(r.semantic[1].image_name, "b.png");
  EXPECT_DOUBLE_EQ(r.semantic[1].iou_before, 1.0);
  EXPECT_TRUE(r.semantic[1].missing_after);
  EXPECT_DOUBLE_EQ(r.semantic[1].acc_after, 1.0);
  EXPECT_EQ(r.semantic_summary.missing_after, 1u);
  EXPECT_DOUBLE_EQ(r.semantic_summary.iou_drop, 1.0);

  ASSERT_TRUE(r.ran_depth);
  ASSERT_EQ(r.depth.size(), 1u);
  EXPECT_EQ(r.depth[0].image, "a");
  EXPECT_DOUBLE_EQ(r.depth[0].score.acc_delta_depth, 1.0);
  EXPECT_DOUBLE_EQ(r.depth[0].score.iou, 1.0);
  EXPECT_EQ(r.counts["depth"]["missing_after"], 1);

  ASSERT_TRUE(r.ran_sam);
  ASSERT_EQ(r.sam.size(), 1u);  // b has no side B
  EXPECT_EQ(r.sam_summary.missing_side_b, 1u);
  // Side A keeps the object segment only (the 1-pixel one has IoU 1/12); side B's [2,4)×[1,4) has
  // IoU 6/12 = 0.5 with the object and with a's segment: sim = 0.5 / max(1, 1).
  EXPECT_EQ(r.sam[0].result.n_gt, 1);
  EXPECT_EQ(r.sam[0].result.n_sam, 1);
  EXPECT_DOUBLE_EQ(r.sam[0].result.sim_sam, 0.5);

  EXPECT_FALSE(r.ran_collateral);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].metric, "collateral_psnr");

  const fs::path out = test::TempDir() / "out";
  const auto written = WriteDirectoryMetrics(r, out);
  EXPECT_EQ(written.size(), 3u);
  std::ifstream sem(out / "semantic.json"), dep(out / "depth.json"), sam(out / "sam.json");
  const auto js = nlohmann::json::parse(sem), jd = nlohmann::json::parse(dep), jm = nlohmann::json::parse(sam);
  for (const char* key : {"image_name", "iou_before", "iou_after", "iou_drop", "acc_before", "acc_after", "acc_diff"})
    EXPECT_TRUE(js[0].contains(key)) << key;
  for (const char* key : {"image", "acc_delta_depth", "iou"}) EXPECT_TRUE(jd[0].contains(key)) << key;
  for (const char* key : {"matches", "sim_sam", "n_gt", "n_sam"}) EXPECT_TRUE(jm["a"].contains(key)) << key;
  EXPECT_EQ(jm["a"]["matches"][0]["gt_idx"], 0);
  const auto summary = SummaryJson(r);
  EXPECT_DOUBLE_EQ(summary["semantic"]["acc_seg"]["0.5"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(summary["semantic"]["acc_iou_post_above_percent"]["0.5"].get<double>(), 0.0);
}

TEST(DirectoryMetrics, SixteenBitAndEightBitMasksAgree) {
  const fs::path d8 = test::TempDir() / "s8", d16 = test::TempDir() / "s16";
  for (const fs::path& d : {d8, d16}) {
    Write(d / "gsam2/before/mask/v.png", Rect(1, 1, 5, 5));
    Write(d / "gsam2/after/mask/v.png", Rect(1, 1, 3, 3));
  }
  Write(d8 / "masks/v.png", Rect(2, 2, 6, 5));
  Image16 m16{kW, kH, std::vector<std::uint16_t>(kW * kH, 0)};
  for (int y = 2; y < 5; ++y)
    for (int x = 2; x < 6; ++x) m16.pixels[y * kW + x] = 65535;
  fs::create_directories(d16 / "masks");
  WritePng16((d16 / "masks/v.png").string(), m16);
  DirectoryMetricsOptions o;
  o.dir = d8;
  const auto r8 = EvaluateDirectory(o);
  o.dir = d16;
  const auto r16 = EvaluateDirectory(o);
  ASSERT_EQ(r8.semantic.size(), 1u);
  ASSERT_EQ(r16.semantic.size(), 1u);
  EXPECT_EQ(r8.semantic[0].iou_before, r16.semantic[0].iou_before);
  EXPECT_EQ(r8.semantic[0].iou_after, r16.semantic[0].iou_after);
  // ∩ = [2,5)×[2,5) = 9, ∪ = 16 + 12 − 9 = 19.
  EXPECT_DOUBLE_EQ(r8.semantic[0].iou_before, 9.0 / 19.0);
  // Nothing else present: depth and sim_SAM skipped, with reasons.
  EXPECT_FALSE(r8.ran_depth);
  EXPECT_FALSE(r8.ran_sam);
  EXPECT_EQ(r8.skipped.size(), 3u);
}

TEST(DirectoryMetrics, AbsentDetectorFoldersScoreEveryImage) {
  // Object masks but no gsam2/ at all: every image is scored with empty detections (the released
  // evaluator), one warning, semantic.json written. a: 12-pixel object → IoU 0 both sides,
  // acc_before 0, acc_after 1 (no object pixel detected after); e: empty object → all 0.
  const fs::path tmp = test::TempDir(), d = tmp / "nodet";
  Write(d / "masks/a.png", Rect(2, 1, 6, 4));
  Write(d / "masks/e.png", Rect(0, 0, 0, 0));
  DirectoryMetricsOptions o;
  o.dir = d;
  const DirectoryMetricsResult r = EvaluateDirectory(o);
  ASSERT_TRUE(r.ran_semantic);
  ASSERT_EQ(r.semantic.size(), 2u);
  for (const auto& rec : r.semantic) {
    EXPECT_EQ(rec.iou_before, 0.0);
    EXPECT_EQ(rec.iou_after, 0.0);
    EXPECT_EQ(rec.iou_drop, 0.0);
    EXPECT_TRUE(rec.missing_before && rec.missing_after);
  }
  EXPECT_EQ(r.semantic[0].acc_after, 1.0);
  EXPECT_EQ(r.semantic[0].acc_diff, 1.0);
  EXPECT_EQ(r.semantic[1].acc_after, 0.0);
  EXPECT_EQ(r.semantic_summary.acc_seg[1].value, 1.0);  // IoU_post 0 < 0.5 for both
  std::size_t warnings = 0;
  for (const auto& w : r.warnings) warnings += w.find("no detector mask folder") != std::string::npos;
  EXPECT_EQ(warnings, 1u);
  EXPECT_EQ(r.counts["semantic"]["absent_detector_folders"].size(), 2u);
  const fs::path out = tmp / "nodet_out";
  WriteDirectoryMetrics(r, out);
  ASSERT_TRUE(fs::exists(out / "semantic.json"));
  std::ifstream in(out / "semantic.json");
  EXPECT_EQ(nlohmann::json::parse(in).size(), 2u);

  // Only the after folder absent: the before detections count, the warning names that folder.
  Write(d / "gsam2/before/mask/a.png", Rect(2, 1, 6, 4));
  const DirectoryMetricsResult half = EvaluateDirectory(o);
  ASSERT_EQ(half.semantic.size(), 2u);
  EXPECT_EQ(half.semantic[0].iou_before, 1.0);
  EXPECT_EQ(half.semantic[0].iou_drop, 1.0);
  EXPECT_EQ(half.counts["semantic"]["absent_detector_folders"], nlohmann::json::array({(d / "gsam2/after/mask").string()}));
}

TEST(DirectoryMetrics, DepthHolesRuleAndTrustInTheOutputs) {
  // The object (4 px) has depth 40 before and none after: the released rule counts it as changed,
  // "both" ignores it. The record names the holes and the trust flags (4 px: small_object).
  const fs::path d = test::TempDir() / "holes";
  Write(d / "masks/a.png", Rect(2, 1, 4, 3));
  Write(d / "depth/before/a.png", Rect(2, 1, 4, 3, 40, 100));
  Write(d / "depth/after/a.png", Rect(2, 1, 4, 3, 0, 100));
  DirectoryMetricsOptions o;
  o.dir = d;
  const DirectoryMetricsResult released = EvaluateDirectory(o);
  ASSERT_EQ(released.depth.size(), 1u);
  EXPECT_EQ(released.depth[0].score.acc_delta_depth, 1.0);
  EXPECT_EQ(released.depth[0].holes_after, 4u);
  o.depth_holes = DepthHoles::kBoth;
  const DirectoryMetricsResult both = EvaluateDirectory(o);
  EXPECT_EQ(both.depth[0].score.acc_delta_depth, 0.0);
  const auto summary = SummaryJson(released), record = DepthJson(released.depth)[0];
  EXPECT_EQ(summary["depth"]["depth_holes"], "before");
  EXPECT_EQ(SummaryJson(both)["depth"]["depth_holes"], "both");
  EXPECT_EQ(o.ToJson()["depth_holes"], "both");
  EXPECT_EQ(record["hole_pixels"]["after_only"], 4);
  EXPECT_EQ(record["trust"]["flags"], nlohmann::json::array({"small_object"}));
  EXPECT_EQ(summary["depth"]["trust"]["flagged_images"], 1);
  EXPECT_TRUE(summary["depth"]["trust"]["mean_acc_delta_depth_trusted"].is_null());
}

TEST(DirectoryMetrics, BadInputsNameTheFile) {
  DirectoryMetricsOptions o;
  o.dir = test::TempDir() / "does_not_exist";
  EXPECT_THROW(EvaluateDirectory(o), Error);
  const fs::path d = test::TempDir() / "bad";
  Write(d / "masks/a.png", Rect(2, 1, 6, 4));
  WriteText(d / "masks/a.json", "[{\"segmentation\": ");
  WriteText(d / "sam/after/a.json", "[]");
  o.dir = d;
  try {
    EvaluateDirectory(o);
    FAIL() << "corrupt SAM JSON accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace al::metrics
