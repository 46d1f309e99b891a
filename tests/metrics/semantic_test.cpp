// Semantic recognition metrics against hand-computed cases (METRICS.md §2, §10).
#include <gtest/gtest.h>

#include "al/metrics/semantic.hpp"

namespace al::metrics {
namespace {

Gray8 Row(std::vector<std::uint8_t> v) { return {int(v.size()), 1, std::move(v)}; }

TEST(Semantic, HandComputedRecord) {
  const Gray8 object = Row({255, 255, 255, 255, 0, 0});
  const Gray8 before = Row({1, 1, 1, 0, 0, 7});  // ∩ 3, ∪ 5
  const Gray8 after = Row({0, 0, 0, 9, 0, 0});   // ∩ 1, ∪ 4
  const SemanticRecord r = ComputeSemantic(object, &before, &after, "x.png");
  EXPECT_EQ(r.image_name, "x.png");
  EXPECT_DOUBLE_EQ(r.iou_before, 0.6);
  EXPECT_DOUBLE_EQ(r.iou_after, 0.25);
  EXPECT_DOUBLE_EQ(r.iou_drop, 0.6 - 0.25);
  EXPECT_DOUBLE_EQ(r.acc_before, 0.75);
  EXPECT_DOUBLE_EQ(r.acc_after, 0.75);  // 3 of 4 object pixels no longer detected
  EXPECT_DOUBLE_EQ(r.acc_diff, 0.0);
}

TEST(Semantic, MissingDetectionIsAnEmptyMask) {
  const Gray8 object = Row({255, 0});
  const SemanticRecord r = ComputeSemantic(object, nullptr, nullptr);
  EXPECT_TRUE(r.missing_before && r.missing_after);
  EXPECT_EQ(r.iou_before, 0.0);
  EXPECT_EQ(r.iou_after, 0.0);
  EXPECT_EQ(r.acc_before, 0.0);
  EXPECT_EQ(r.acc_after, 1.0);
}

TEST(Semantic, EmptyObjectGivesZeroAccuracies) {
  const Gray8 object = Row({0, 0}), det = Row({0, 0});
  const SemanticRecord r = ComputeSemantic(object, &det, &det);
  EXPECT_EQ(r.iou_before, 0.0);  // two empty masks: 0, not 1
  EXPECT_EQ(r.acc_before, 0.0);
  EXPECT_EQ(r.acc_after, 0.0);
}

TEST(Semantic, MasksAreResizedToTheLargestWithTheFloorRule) {
  const Gray8 object{2, 1, {255, 0}};
  const Gray8 before{4, 1, {255, 255, 0, 0}};  // same shape at double resolution
  const SemanticRecord r = ComputeSemantic(object, &before, nullptr);
  EXPECT_DOUBLE_EQ(r.iou_before, 1.0);
}

TEST(Semantic, AccSegIsStrictAndTablePercentToo) {
  std::vector<SemanticRecord> recs(4);
  const double post[] = {0.5, 0.2, 0.9, 0.7};
  const double pre[] = {1.0, 0.8, 0.95, 0.75};
  for (int i = 0; i < 4; ++i) recs[i].iou_after = post[i], recs[i].iou_before = pre[i];
  const SemanticSummary s = SummarizeSemantic(recs);
  ASSERT_EQ(s.acc_seg.size(), 4u);
  EXPECT_DOUBLE_EQ(s.acc_seg[0].value, 0.25);  // < 0.3: {0.2}
  EXPECT_DOUBLE_EQ(s.acc_seg[1].value, 0.25);  // < 0.5: 0.5 itself does not count
  EXPECT_DOUBLE_EQ(s.acc_seg[2].value, 0.5);   // < 0.7: {0.5, 0.2}
  EXPECT_DOUBLE_EQ(s.acc_seg[3].value, 0.75);  // < 0.9
  ASSERT_EQ(s.acc_iou_post_above.size(), 3u);
  EXPECT_DOUBLE_EQ(s.acc_iou_post_above[0].value, 50.0);  // > 0.5: {0.9, 0.7}
  EXPECT_DOUBLE_EQ(s.acc_iou_post_above[1].value, 25.0);  // > 0.7: {0.9}
  EXPECT_DOUBLE_EQ(s.acc_iou_post_above[2].value, 0.0);   // > 0.9: none (0.9 is not counted)
  EXPECT_EQ(s.iou_drop, s.iou_before - s.iou_after);      // exact identity
  EXPECT_DOUBLE_EQ(s.iou_before, (1.0 + 0.8 + 0.95 + 0.75) / 4);
}

TEST(Semantic, PooledMeanIsOverImagesNotSceneMeans) {
  std::vector<SemanticRecord> scene1(1), scene2(3);
  scene1[0].iou_before = 1.0;
  for (auto& r : scene2) r.iou_before = 0.0;
  std::vector<SemanticRecord> all = scene1;
  all.insert(all.end(), scene2.begin(), scene2.end());
  EXPECT_DOUBLE_EQ(SummarizeSemantic(all).iou_before, 0.25);  // not (1 + 0)/2
}

}  // namespace
}  // namespace al::metrics
