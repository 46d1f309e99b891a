// report.html of eval (al/eval/report_html.hpp): it shows what report.json holds, including parts
// other evaluator work adds later (trust flags, feature metrics), sorts views by residual and keeps
// every image reference relative. The page in a real browser: ctest browser.report_html.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "al/core/html.hpp"
#include "al/eval/records.hpp"
#include "al/eval/report_html.hpp"

namespace al::eval {
namespace {

using json = nlohmann::json;

json Report() {
  return json::parse(R"({
    "params": {"row_name": "room-<mug>"},
    "counts": {"views": 3, "evaluated": 2},
    "warnings": ["a warning"],
    "metrics": {"skipped": [{"metric": "sim_sam", "column": "after", "reason": "no --sam-before"}],
      "residuals": {"headline": "residual_gt"},
      "columns": [
        {"name": "after", "label": "fgs", "num_removed": 10, "residual_gt": {"mean": 0.35},
         "depth": {"mean_acc_delta_depth": 0.25, "collateral_depth": {"mean": 0.02},
                   "flagged": [{"view": "v1", "flags": ["small_object"]}]},
         "feature": {"mean_residual": 0.7, "acc_seg": {"0.5": 0.25}}},
        {"name": "bk", "label": "fgs+bk", "num_removed": 12, "added": 2, "residual_gt": {"mean": 0.05},
         "depth": {"mean_acc_delta_depth": 0.75, "collateral_depth": {"mean": 0.01}, "flagged": []},
         "feature": {"mean_residual": 0.2, "acc_seg": {"0.5": 0.5}}, "iou_drop_feat": 0.4}]}})");
}

json Views() {
  return json::parse(R"([
    {"view": "v0", "evaluated": 1, "after_acc_delta_depth": 0.5, "bk_acc_delta_depth": 0.9, "bk_trust_flags": "",
     "bk_residual_feat": 0.05, "after_residual_gt": 0.5, "bk_residual_gt": 0.1},
    {"view": "v1", "evaluated": 1, "after_acc_delta_depth": 0.0, "bk_acc_delta_depth": 0.6, "bk_trust_flags": "dark",
     "after_residual_gt": 0.2, "bk_residual_gt": 0.0}])");
}

json Images(const std::string& view) {
  return {{"view", view},
          {"images", {{{"key", "before"}, {"label", "before"}, {"src", "images/" + view + " before.png"}},
                      {{"key", "bk"}, {"label", "fgs+bk"}, {"src", "images/" + view + "_bk.png"}}}}};
}

TEST(EvalReportHtml, ShowsEveryPartOfTheReport) {
  const std::string html = EvalReportHtml(Report(), Views(), json::array({Images("v0"), Images("v1")}));
  EXPECT_NE(html.find("room-&lt;mug&gt;"), std::string::npos);  // escaped
  EXPECT_NE(html.find("<b>0.750</b>"), std::string::npos);       // best acc_Δdepth bold
  EXPECT_NE(html.find("<b>0.0100</b>"), std::string::npos);      // best collateral depth (lower) bold
  EXPECT_NE(html.find("Feature metrics"), std::string::npos);
  // Feature metrics by their names, the best bold (residual_feat: lower; acc_seg_feat: higher), and
  // a feature number the page does not know by name listed as it is.
  EXPECT_NE(html.find("residual_feat ↓"), std::string::npos);
  EXPECT_NE(html.find("<b>0.200</b>"), std::string::npos);
  EXPECT_NE(html.find("acc_seg_feat ↑ (ξ = 0.5)"), std::string::npos);
  EXPECT_NE(html.find("<b>0.500</b>"), std::string::npos);
  EXPECT_EQ(html.find("feature.mean_residual"), std::string::npos);
  EXPECT_NE(html.find("iou_drop_feat"), std::string::npos);
  EXPECT_NE(html.find("residual_feat fgs+bk 0.05"), std::string::npos);  // per view
  EXPECT_NE(html.find("a warning"), std::string::npos);
  EXPECT_NE(html.find("no --sam-before"), std::string::npos);
  EXPECT_NE(html.find("src=\"images/v0%20before.png\""), std::string::npos);  // relative, encoded
  EXPECT_EQ(html.find("http"), std::string::npos);                            // no network reference
  // The headline residual leads the summary, the best (lowest) bold, and orders the views: v0 has
  // the larger residual_gt of the method's column (0.5 > 0.2), so it comes first (by 1 − acc_Δdepth
  // of the last column, the order before residuals, v1 would).
  EXPECT_LT(html.find("residual_gt ↓"), html.find("acc_Δdepth ↑"));
  EXPECT_NE(html.find("<b>0.050</b>"), std::string::npos);
  EXPECT_NE(html.find("residual_gt fgs 0.50 · fgs+bk 0.10"), std::string::npos);
  EXPECT_LT(html.find("id=\"view-v0\""), html.find("id=\"view-v1\""));
}

// Bold marks a best: a row where every method prints the same value has none; values that print
// the same as the best are bold too.
TEST(EvalReportHtml, TiesAreBoldOnlyWhenSomethingIsWorse) {
  json report = Report();
  auto& columns = report["metrics"]["columns"];
  columns[0]["depth"]["mean_acc_delta_depth"] = 0.625;
  columns[1]["depth"]["mean_acc_delta_depth"] = 0.625;  // a tie in every column
  columns[0]["depth"]["collateral_depth"]["mean"] = 0.0200004;  // prints as 0.0200, like the other
  columns[1]["depth"]["collateral_depth"]["mean"] = 0.02;
  columns[1]["feature"]["mean_residual"] = 0.7;
  columns[0]["feature"]["mean_residual"] = 0.2;
  const std::string html = EvalReportHtml(report, Views(), json::array());
  EXPECT_NE(html.find("0.625"), std::string::npos);
  EXPECT_EQ(html.find("<b>0.625</b>"), std::string::npos) << "a tie in every column is not bold";
  EXPECT_EQ(html.find("<b>0.0200</b>"), std::string::npos) << "equal when printed: a tie";
  EXPECT_NE(html.find("<b>0.200</b>"), std::string::npos);  // the lower residual stays bold
}

TEST(EvalReportHtml, FlagsComeFromTheReportAndTheRecords) {
  const auto flagged = FlaggedViews(Report(), Views());
  ASSERT_EQ(flagged.size(), 1u);
  const auto& flags = flagged.at("v1");
  EXPECT_EQ(flags, (std::vector<std::string>{"fgs, depth: small_object"}));
  // Without flags in report.json, the per-view records' flag cells count.
  json bare = Report();
  bare["metrics"]["columns"][0]["depth"].erase("flagged");
  EXPECT_EQ(FlaggedViews(bare, Views()).at("v1"), (std::vector<std::string>{"bk_trust_flags: dark"}));
  const std::string html = EvalReportHtml(Report(), Views(), json::array({Images("v0"), Images("v1")}));
  EXPECT_NE(html.find("class=\"view flagged\" id=\"view-v1\""), std::string::npos);
  EXPECT_NE(html.find("cannot be trusted: fgs, depth\">⚑ small_object</span>"), std::string::npos);
  EXPECT_NE(html.find("class=\"view\" id=\"view-v0\""), std::string::npos);
}

TEST(EvalRecords, ColumnsFlattenToScalars) {
  const json records = ColumnRecords(Report());
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0]["depth.mean_acc_delta_depth"], 0.25);
  EXPECT_EQ(records[1]["feature.mean_residual"], 0.2);
  EXPECT_FALSE(records[0].contains("depth.flagged"));  // arrays are not scalars
}

TEST(Html, EscapesAndEncodes) {
  EXPECT_EQ(HtmlEscape("<a href=\"x\">'&'</a>"), "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
  EXPECT_EQ(UrlPath("images/a b#1.png"), "images/a%20b%231.png");
  EXPECT_EQ(HtmlNumber(0.12345, 2), "0.12");
  EXPECT_EQ(HtmlNumber(std::nan(""), 2), "–");
}

}  // namespace
}  // namespace al::eval
