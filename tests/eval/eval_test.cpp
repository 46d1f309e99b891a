// End-to-end evaluation on a small hand-built scene: a cone of Gaussians floating in front of a
// wall, seen by a few cameras. Removing the whole cone must score acc_Δdepth = 1, removing
// nothing 0 (and the feature metrics: residual 0 / IoU_post 0 and residual 1 / IoU_drop 0);
// segmentations given as folders drive IoU_drop and sim_SAM; a failing run writes nothing.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/eval/eval.hpp"
#include "al/eval/inputs.hpp"
#include "al/eval/view_metric.hpp"
#include "al/io/image.hpp"
#include "test_data.hpp"

namespace al::eval {
namespace {

namespace fs = std::filesystem;
constexpr float kC0 = 0.28209479177387814f;

struct BallScene {
  Scene scene;
  std::vector<std::int32_t> labels;  // 1 = the object
  std::vector<Camera> cameras;
};

// Wall: a 61×51 grid at z = 10 (x ∈ [−6, 6], y ∈ [−5, 5]); the object (label 1) in front; all
// opaque. Cameras at the origin looking along +z, shifted sideways a little.
const BallScene& Ball() {
  static const BallScene b = [] {
    BallScene s;
    std::vector<Eigen::Vector3f> pos;
    std::vector<float> scale;
    for (int iy = 0; iy <= 50; ++iy)
      for (int ix = 0; ix <= 60; ++ix) {
        pos.emplace_back(-6.f + 0.2f * ix, -5.f + 0.2f * iy, 10.f);
        scale.push_back(0.15f);
        s.labels.push_back(0);
      }
    // A cone of radius 0.5 opening towards the cameras: rim at z = 4, apex at z = 7 (z = 7 − 6ρ),
    // sampled uniformly in area. Its depth changes span [½, 1] of the largest. At 256×192 the GHT
    // prior (ν = 1000 pseudo-pixels) is weak against ~49k pixels and t lands in the gap between the
    // object's changes and the unchanged background (t ≈ 138), above the bytes of the rim pixels
    // (object share >= 0.5, so at least half the rim's change, byte <= ~128): removing the whole
    // object must score exactly 1. (At 96×72 the prior pulls t down to ~58 and the rim is lost.)
    const int cone = 4000;
    for (int i = 0; i < cone; ++i) {
      const float rho = 0.5f * std::sqrt((i + 0.5f) / cone), phi = 2.39996323f * i;
      pos.emplace_back(rho * std::cos(phi), rho * std::sin(phi), 7.f - 6.f * rho);
      scale.push_back(0.03f);
      s.labels.push_back(1);
    }
    const std::size_t n = pos.size();
    Scene& sc = s.scene;
    sc.means.resize(n, 3);
    sc.log_scales.resize(n, 3);
    sc.rotations = MatX4f::Zero(n, 4);
    sc.rotations.col(0).setOnes();
    sc.opacity_logits = Eigen::VectorXf::Constant(n, 4.f);
    sc.sh = RowMatXf::Zero(n, 3);
    sc.sh_degree = 0;
    sc.has_opacity = sc.has_scales = sc.has_rotations = sc.has_f_dc = true;
    // Semantic features: one direction for the wall, another for the object (4-D, not unit length).
    sc.features = RowMatXf::Zero(Eigen::Index(n), 4);
    sc.feature_prefix = "semantic_";
    for (std::size_t i = 0; i < n; ++i) {
      sc.means.row(i) = pos[i].transpose();
      sc.log_scales.row(i).setConstant(std::log(scale[i]));
      const bool obj = s.labels[i] == 1;
      sc.sh(i, 0) = ((obj ? 0.9f : 0.3f) - 0.5f) / kC0;
      sc.sh(i, 1) = ((obj ? 0.2f : 0.5f) - 0.5f) / kC0;
      sc.sh(i, 2) = ((obj ? 0.2f : 0.7f) - 0.5f) / kC0;
      sc.features.row(Eigen::Index(i)) << (obj ? 2.0f : 0.1f), (obj ? 0.2f : 3.0f), 0.3f, 0.0f;
    }
    for (int v = 0; v < 3; ++v) {
      Camera c;
      c.name = "v" + std::to_string(v);
      c.width = 256;
      c.height = 192;
      c.fx = c.fy = 213;
      c.cx = 128;
      c.cy = 96;
      c.t = Eigen::Vector3d(0.4 * (v - 1), 0.2 * (v - 1), 0);
      s.cameras.push_back(c);
    }
    return s;
  }();
  return b;
}

EvalColumn Col(std::string name, std::string label, std::vector<bool> removed, std::string seg = "",
               std::string sam = "") {
  return {std::move(name), std::move(label), std::move(removed), std::move(seg), std::move(sam)};
}

std::vector<bool> Removal(double fraction) {
  const auto& labels = Ball().labels;
  std::vector<bool> r(labels.size(), false);
  std::size_t k = 0;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == 1) r[i] = (k++ % 100) < fraction * 100;
  return r;
}

ObjectSource FromLabels() {
  ObjectSource o;
  o.labels = Ball().labels;
  o.object_id = 1;
  return o;
}

EvalOptions Options(const fs::path& out) {
  EvalOptions o;
  o.out_dir = out.string();
  o.progress = false;
  return o;
}

nlohmann::json ReadJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

TEST(Eval, PerfectRemovalScoresOneEmptyRemovalZero) {
  const fs::path out = test::TempDir() / "out";
  const std::vector<EvalColumn> columns = {Col("after", "none", Removal(0.0)),
                                           Col("refined", "all", Removal(1.0)),
                                           Col("half", "half", Removal(0.5))};
  const EvalResult r = RunEval(Ball().scene, Ball().cameras, columns, FromLabels(), Options(out));
  ASSERT_EQ(r.evaluated, 3u);
  for (const ViewRecord& v : r.views) {
    ASSERT_TRUE(v.evaluated) << v.name;
    EXPECT_GT(v.object_pixels, 2000u) << v.name;  // the object covers a good part of each view
    EXPECT_EQ(v.columns[0].depth8.acc_delta_depth, 0.0) << v.name;
    EXPECT_EQ(v.columns[1].depth8.acc_delta_depth, 1.0) << v.name;
    EXPECT_EQ(v.columns[1].depth_float.acc_delta_depth, 1.0) << v.name;
    // Nothing but the object changed: collateral damage only from its soft rim.
    EXPECT_LT(v.columns[1].depth8.collateral_depth, 0.05) << v.name;
    // Half of the object's Gaussians (interleaved) still cover much of its surface: partial change.
    EXPECT_LT(v.columns[2].depth8.acc_delta_depth, 1.0) << v.name;
  }
  EXPECT_EQ(r.summaries[0].depth8.acc_delta_depth.mean, 0.0);
  EXPECT_EQ(r.summaries[1].depth8.acc_delta_depth.mean, 1.0);
  EXPECT_EQ(r.summaries[0].identical, 3u);  // empty removal: renders identical outside the object
  // Feature metrics from the scene's own features (no segmentation folders given).
  for (const ViewRecord& v : r.views) {
    ASSERT_TRUE(v.columns[1].feature.has_value()) << v.name;
    const metrics::FeatureRecord& none = v.columns[0].feature->record;
    const metrics::FeatureRecord& all = v.columns[1].feature->record;
    const metrics::FeatureRecord& half = v.columns[2].feature->record;
    EXPECT_GT(all.semantic.iou_before, 0.9) << v.name;  // the before segmentation finds the object
    EXPECT_EQ(all.semantic.iou_after, 0.0) << v.name;   // nothing of it after the perfect removal
    EXPECT_EQ(all.residual, 0.0) << v.name;
    EXPECT_EQ(none.residual, 1.0) << v.name;             // the empty removal leaves all of it
    EXPECT_EQ(none.semantic.iou_drop, 0.0) << v.name;
    EXPECT_GT(half.residual, 0.5) << v.name;             // interleaved half: still mostly covered
  }
  ASSERT_TRUE(r.summaries[1].feature.has_value());
  EXPECT_EQ(r.summaries[1].feature->residual.mean, 0.0);
  EXPECT_EQ(r.summaries[1].feature->semantic.acc_seg.front().value, 1.0);  // IoU_post < 0.3 in every view
  EXPECT_EQ(r.summaries[0].feature->semantic.acc_seg.back().value, 0.0);   // IoU_post >= 0.9 in every view

  // Outputs of SPEC §6, and the report's view of the same numbers.
  for (const char* f : {"report.json", "metrics.csv", "table.md", "table.tex", "images/v0_before.png",
                        "images/v0_after.png", "images/v0_refined.png", "images/v0_depthdiff.png",
                        "images/v0_added.png", "images/v0_half_added.png", "depth/refined/before/v0.png",
                        "masks/v0.png", "images/v0_featseg.png", "images/v0_refined_featseg.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json report = ReadJson(out / "report.json");
  EXPECT_EQ(report["command"], "eval");
  EXPECT_EQ(report["metrics"]["columns"][1]["depth"]["mean_acc_delta_depth"], 1.0);
  EXPECT_EQ(report["metrics"]["columns"][1]["gt"]["f1"], 1.0);
  EXPECT_EQ(report["counts"]["evaluated"], 3);
  EXPECT_EQ(report["metrics"]["skipped"].size(), 6u);  // iou_drop and sim_sam for each column
  EXPECT_EQ(report["metrics"]["columns"][1]["feature"]["mean_residual"], 0.0);
  EXPECT_EQ(report["metrics"]["feature_segmentation"]["prototypes"]["source"], "labels");
  std::ifstream csv(out / "metrics.csv");
  std::size_t lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 1u + 3u);
  // The added overlay paints the object (all of it was added by "refined").
  const PngData added = ReadPng((out / "images" / "v1_added.png").string());
  const PngData plain = ReadPng((out / "images" / "v1_after.png").string());
  const std::size_t centre = (96 * 256 + 128) * 3, corner = 0;
  for (int c = 0; c < 3; ++c) {
    const double pink[3] = {255, 105, 180};
    EXPECT_EQ(added.values[centre + c], std::uint16_t(std::lround(0.35 * plain.values[centre + c] + 0.65 * pink[c])));
    EXPECT_EQ(added.values[corner + c], plain.values[corner + c]);  // the wall is not painted
  }
  // No staging folder is left behind.
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".eval-tmp"), std::string::npos);
}

// Every metric of ViewMetrics() (al/eval/view_metric.hpp) reaches report.json, metrics.csv and
// report.html; object_colour_change agrees with the scene's colours: 0 for the empty removal, about
// |(0.9, 0.2, 0.2) − (0.3, 0.5, 0.7)| / 3 ≈ 0.467 where the wall replaces the whole object.
TEST(Eval, PlugInMetricsReachEveryOutput) {
  const fs::path out = test::TempDir() / "plugins";
  const std::vector<EvalColumn> columns = {Col("after", "none", Removal(0.0)), Col("refined", "all", Removal(1.0))};
  const EvalResult r = RunEval(Ball().scene, Ball().cameras, columns, FromLabels(), Options(out));
  const std::vector<ViewMetric>& plugins = ViewMetrics();
  std::size_t k = plugins.size();
  for (std::size_t i = 0; i < plugins.size(); ++i)
    if (plugins[i].name == "object_colour_change") k = i;
  ASSERT_LT(k, plugins.size());
  for (const ViewRecord& v : r.views) {
    ASSERT_EQ(v.columns[0].view_metrics.size(), plugins.size());
    EXPECT_EQ(v.columns[0].view_metrics[k], 0.0) << v.name;
    ASSERT_TRUE(v.columns[1].view_metrics[k].has_value());
    EXPECT_GT(*v.columns[1].view_metrics[k], 0.35) << v.name;  // the soft rim mixes both colours
    EXPECT_LT(*v.columns[1].view_metrics[k], 0.4667 + 1e-3) << v.name;
  }
  const nlohmann::json report = ReadJson(out / "report.json");
  for (const ViewMetric& p : plugins) {
    const nlohmann::json& j = report["metrics"]["columns"][1]["view_metrics"][p.name];
    EXPECT_EQ(j["count"], 3) << p.name;
    EXPECT_NEAR(j["mean"].get<double>(), r.summaries[1].view_metrics[&p - plugins.data()].mean, 1e-12);
    std::ifstream csv(out / "metrics.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_NE(header.find("refined_" + p.name), std::string::npos) << header;
    std::ifstream html(out / "report.html");
    const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
    EXPECT_NE(page.find(p.label.substr(0, p.label.find(' '))), std::string::npos) << p.label;
  }
}

// Ball() without the wall behind the object: only a strip at x < −3 remains (the left quarter of
// each view), so removing the object leaves its pixels with no depth at all.
BallScene FloatingCone() {
  const BallScene& b = Ball();
  std::vector<Eigen::Index> keep;
  for (std::size_t i = 0; i < b.labels.size(); ++i)
    if (b.labels[i] == 1 || b.scene.means(Eigen::Index(i), 0) < -3.f) keep.push_back(Eigen::Index(i));
  BallScene s;
  s.scene = b.scene;
  s.scene.means = b.scene.means(keep, Eigen::all);
  s.scene.log_scales = b.scene.log_scales(keep, Eigen::all);
  s.scene.rotations = b.scene.rotations(keep, Eigen::all);
  s.scene.opacity_logits = b.scene.opacity_logits(keep);
  s.scene.sh = b.scene.sh(keep, Eigen::all);
  s.scene.features = b.scene.features(keep, Eigen::all);
  for (Eigen::Index i : keep) s.labels.push_back(b.labels[std::size_t(i)]);
  s.cameras = b.cameras;
  return s;
}

TEST(Eval, AnObjectWithNothingBehindItCountsAsDepthChange) {
  const BallScene s = FloatingCone();
  std::vector<bool> all(s.labels.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = s.labels[i] == 1;
  ObjectSource object;
  object.labels = s.labels;
  object.object_id = 1;
  const fs::path tmp = test::TempDir();
  EvalOptions o = Options(tmp / "released");
  o.write_images = false;
  const EvalResult released = RunEval(s.scene, s.cameras, {Col("after", "all", all)}, object, o);
  o.out_dir = (tmp / "both").string();
  o.depth_holes = metrics::DepthHoles::kBoth;
  const EvalResult both = RunEval(s.scene, s.cameras, {Col("after", "all", all)}, object, o);
  ASSERT_EQ(released.evaluated, 3u);
  for (std::size_t v = 0; v < 3; ++v) {
    const ColumnViewMetrics &m = released.views[v].columns[0], &old = both.views[v].columns[0];
    // Every object pixel lost its depth: float mode puts them at the top bin, all changed.
    EXPECT_GT(m.holes_after_float, released.views[v].object_pixels);
    EXPECT_EQ(m.depth_float.acc_delta_depth, 1.0) << v;
    // 8-bit mode follows the released evaluator: |Δ| = the depth byte before, and near = small in
    // our 8-bit depth (METRICS.md §6: rim at z = 4 → byte 1, apex at z = 7 → 128), so only the far
    // part of the cone reads as changed (measured 0.15-0.16); the old rule sees nothing.
    EXPECT_GT(m.depth8.acc_delta_depth, 0.1) << v;
    EXPECT_LT(m.depth8.acc_delta_depth, 0.5) << v;
    EXPECT_EQ(old.depth8.acc_delta_depth, 0.0) << v;
    EXPECT_EQ(old.depth_float.acc_delta_depth, 0.0) << v;
    EXPECT_TRUE(old.constant8) << v;
  }
  EXPECT_EQ(released.report["params"]["depth_holes"], "before");
  EXPECT_EQ(both.report["params"]["depth_holes"], "both");
  EXPECT_EQ(released.report["metrics"]["columns"][0]["depth_float"]["depth_holes"], "before");
  EXPECT_GT(released.report["metrics"]["columns"][0]["depth_float"]["hole_pixels"]["after_only"].get<int>(), 6000);
}

TEST(Eval, TrustFlagsReachTheReportCsvAndTableFootnotes) {
  // A 1-in-2 removal of the cone at 256×192 is fine; with trust.min_object_pixels above the
  // object's size every view is flagged small_object.
  const fs::path out = test::TempDir() / "flags";
  EvalOptions o = Options(out);
  o.write_images = false;
  o.trust.min_object_pixels = 1000000;
  const EvalResult r = RunEval(Ball().scene, Ball().cameras, {Col("after", "all", Removal(1.0))}, FromLabels(), o);
  const auto& trust = r.report["metrics"]["columns"][0]["depth"]["trust"];
  EXPECT_EQ(trust["flagged_views"], 3);
  EXPECT_EQ(trust["flag_counts"]["small_object"], 3);
  EXPECT_EQ(trust["flagged"][0]["view"], "v0");
  EXPECT_TRUE(trust["mean_acc_delta_depth_trusted"].is_null());
  EXPECT_EQ(r.report["params"]["depth_trust"]["min_object_pixels"], 1000000);
  std::ifstream csv(out / "metrics.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_NE(header.find("after_depth_flags,after_depth_float_flags"), std::string::npos) << header;
  EXPECT_NE(row.find(",small_object,small_object"), std::string::npos) << row;
  std::ifstream md(out / "table.md");
  const std::string table((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(table.find("**1.00**<sup>1</sup>"), std::string::npos) << table;
  EXPECT_NE(table.find("<sup>1</sup> all: acc_Δdepth cannot be trusted in 3 of 3 views (small\\_object: all)"),
            std::string::npos)
      << table;
  // Default options: the clean removal of a large object is trusted, no footnote.
  o.trust = {};
  const EvalResult clean = RunEval(Ball().scene, Ball().cameras, {Col("after", "all", Removal(1.0))}, FromLabels(), o);
  EXPECT_EQ(clean.report["metrics"]["columns"][0]["depth"]["trust"]["flagged_views"], 0);
  EXPECT_TRUE(TableFromResult("x", {Col("after", "all", Removal(1.0))}, clean).notes.empty());
}

TEST(Eval, SegmentationsDriveIouDropAndSimSam) {
  const fs::path tmp = test::TempDir();
  const std::vector<EvalColumn> first = {Col("after", "all", Removal(1.0))};
  EvalOptions o = Options(tmp / "a");
  o.write_images = false;
  RunEval(Ball().scene, Ball().cameras, first, FromLabels(), o);
  // Detector "before" = the object mask itself, "after" = nothing detected (folder without files);
  // SAM lists: the object as one segment before and after, and a list for only one view.
  fs::create_directories(tmp / "seg_after");
  fs::create_directories(tmp / "sam_before");
  fs::create_directories(tmp / "sam_after");
  for (const Camera& c : Ball().cameras) {
    const PngData m = ReadPng((tmp / "a" / "masks" / (c.name + ".png")).string());
    nlohmann::json rows = nlohmann::json::array();
    for (int y = 0; y < m.height; ++y) {
      nlohmann::json row = nlohmann::json::array();
      for (int x = 0; x < m.width; ++x) row.push_back(m.values[std::size_t(y) * m.width + x] > 0 ? 1 : 0);
      rows.push_back(row);
    }
    const nlohmann::json list = nlohmann::json::array({{{"segmentation", rows}}});
    std::ofstream(tmp / "sam_before" / (c.name + ".json")) << list.dump();
    if (c.name == "v0") std::ofstream(tmp / "sam_after" / (c.name + ".json")) << list.dump();
  }
  EvalOptions o2 = Options(tmp / "b");
  o2.seg_before_dir = (tmp / "a" / "masks").string();
  o2.sam_before_dir = (tmp / "sam_before").string();
  std::vector<EvalColumn> cols = {Col("after", "all", Removal(1.0), (tmp / "seg_after").string(),
                                       (tmp / "sam_after").string())};
  const EvalResult r = RunEval(Ball().scene, Ball().cameras, cols, FromLabels(), o2);
  ASSERT_TRUE(r.summaries[0].semantic.has_value());
  EXPECT_EQ(r.summaries[0].semantic->iou_before, 1.0);
  EXPECT_EQ(r.summaries[0].semantic->iou_after, 0.0);
  EXPECT_EQ(r.summaries[0].semantic->iou_drop, 1.0);
  ASSERT_TRUE(r.summaries[0].sim_sam.has_value());
  EXPECT_EQ(r.summaries[0].sim_sam->count, 1u);
  EXPECT_EQ(r.summaries[0].sim_sam->mean, 1.0);
  EXPECT_EQ(r.summaries[0].sim_sam_missing, 2u);
  // Everything ran but residual_est, which needs a refinement as its ideal.
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].metric, "residual_est");
  const std::string md = [&] {
    std::ifstream in(tmp / "b" / "table.md");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  EXPECT_NE(md.find("**1.00**"), std::string::npos) << md;
}

TEST(Eval, BadInputWritesNothing) {
  const fs::path tmp = test::TempDir();
  // Object masks from a folder: v0 fine, v1 corrupt → the run fails at v1 and leaves no output.
  fs::create_directories(tmp / "masks");
  Image8 m{256, 192, 1, std::vector<std::uint8_t>(256 * 192, 0)};
  for (int y = 20; y < 50; ++y)
    for (int x = 30; x < 60; ++x) m.pixels[std::size_t(y) * 256 + x] = 255;
  WritePng8((tmp / "masks" / "v0.png").string(), m);
  std::ofstream(tmp / "masks" / "v1.png") << "not a png";
  ObjectSource object;
  object.masks_dir = (tmp / "masks").string();
  const std::vector<EvalColumn> cols = {Col("after", "all", Removal(1.0))};
  EXPECT_THROW(RunEval(Ball().scene, Ball().cameras, cols, object, Options(tmp / "out")), Error);
  EXPECT_FALSE(fs::exists(tmp / "out"));
  for (const auto& e : fs::directory_iterator(tmp))
    EXPECT_EQ(e.path().filename().string().find(".eval-tmp"), std::string::npos) << e.path();
  // Wrong mask length and unknown object id are refused before anything is written.
  std::vector<EvalColumn> short_cols = {Col("after", "x", std::vector<bool>(10, false))};
  EXPECT_THROW(RunEval(Ball().scene, Ball().cameras, short_cols, FromLabels(), Options(tmp / "out")), Error);
  ObjectSource wrong = FromLabels();
  wrong.object_id = 7;
  EXPECT_THROW(RunEval(Ball().scene, Ball().cameras, cols, wrong, Options(tmp / "out")), Error);
  EXPECT_FALSE(fs::exists(tmp / "out"));
  // A view whose mask is missing is excluded and counted, not an error.
  fs::remove(tmp / "masks" / "v1.png");
  const EvalResult r = RunEval(Ball().scene, Ball().cameras, cols, object, Options(tmp / "out"));
  EXPECT_EQ(r.evaluated, 1u);
  EXPECT_EQ(r.missing_object_masks, 2u);
}

TEST(EvalTable, BestBoldSecondUnderlined) {
  EXPECT_EQ(RankValues({0.5, 0.9, 0.7, std::nullopt}, true), (std::vector<int>{0, 1, 2, 0}));
  EXPECT_EQ(RankValues({0.5, 0.9, 0.7}, false), (std::vector<int>{1, 0, 2}));
  EXPECT_EQ(RankValues({0.861, 0.859, 0.2}, true), (std::vector<int>{1, 1, 2}));  // equal when printed
  Table t;
  t.methods = {"fgs", "fgs+bk", "fgs_cp"};
  t.rows.push_back({"room-mug", {0.1, 0.3, 0.2}, {0.5, std::nullopt, 0.9}, {0.4, 0.2, 0.3},
                    {0.8, 0.9, 0.95}, {0.2, 0.1, std::nullopt}, {}, {}, {}, {}, {}});
  const std::string md = TableMarkdown(t), tex = TableLatex(t);
  // The paper's groups, then the feature metrics (residual: lower is better).
  EXPECT_NE(md.find("| room-mug | 0.10 | **0.30** | <u>0.20</u> | <u>0.50</u> | – | **0.90** | 0.40 | **0.20** | "
                    "<u>0.30</u> | 0.80 | <u>0.90</u> | **0.95** | <u>0.20</u> | **0.10** | – |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("IoU_drop_feat ↑ fgs"), std::string::npos) << md;
  EXPECT_NE(tex.find("room-mug & 0.10 & \\textbf{0.30} & \\underline{0.20} & \\underline{0.50} & -- & \\textbf{0.90}"),
            std::string::npos)
      << tex;
  EXPECT_NE(tex.find("fgs\\_cp"), std::string::npos);
  EXPECT_NE(tex.find("\\begin{tabular}{lccc|ccc|ccc|ccc|ccc}"), std::string::npos);
  // A footnote on an acc_Δdepth cell: marked in both formats, text escaped per format, long view
  // lists cut.
  DepthTrustNote note;
  note.method = "fgs_cp";
  note.flagged = 8;
  note.views = 10;
  note.views_by_flag = {{"small_object", {"a", "b", "c", "d", "e", "f", "g", "h"}}};
  note.trusted_mean = 0.456;
  t.notes = {note};
  t.rows[0].acc_delta_depth_note = {0, 0, 1};
  const std::string md2 = TableMarkdown(t), tex2 = TableLatex(t);
  EXPECT_NE(md2.find("| **0.90**<sup>1</sup> |"), std::string::npos) << md2;
  EXPECT_NE(md2.find("<sup>1</sup> fgs\\_cp: acc_Δdepth cannot be trusted in 8 of 10 views (small\\_object: a, b, c, "
                     "d, e, f and 2 more); mean over the 2 other views 0.46."),
            std::string::npos)
      << md2;
  EXPECT_NE(tex2.find("\\textbf{0.90}$^{1}$"), std::string::npos) << tex2;
  EXPECT_NE(tex2.find("$^{1}$ fgs\\_cp: acc$_{\\Delta\\text{depth}}$ cannot be trusted"), std::string::npos) << tex2;
}

TEST(EvalInputs, NamesAndTargets) {
  EXPECT_EQ(ColumnLabelFromPath("/x/removed_fgs.npy"), "fgs");
  EXPECT_EQ(ColumnLabelFromPath("mask.txt"), "mask");
  EXPECT_EQ(SplitNamedPath("bk=/a/refined.npy"), (std::pair<std::string, std::string>{"bk", "/a/refined.npy"}));
  EXPECT_EQ(SplitNamedPath("/a=b/refined.npy").first, "");
  const fs::path tmp = test::TempDir();
  std::ofstream(tmp / "target.json") << R"({"object_id": 4, "name": "mug", "preset": "room"})";
  const TargetInfo t = ResolveTarget((tmp / "labels.npy").string(), std::nullopt);
  EXPECT_EQ(t.object_id, 4);
  EXPECT_EQ(t.name, "mug");
  EXPECT_EQ(ResolveTarget((tmp / "labels.npy").string(), 2).object_id, 2);
  EXPECT_THROW(ResolveTarget((tmp / "sub" / "labels.npy").string(), std::nullopt), Error);
}

}  // namespace
}  // namespace al::eval
