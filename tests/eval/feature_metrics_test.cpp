// The feature metrics (docs/eval.md, "Feature metrics") on both scene sources with ground truth:
// `al-refine synth` (in-process) and ../shared/scenes/gen_scenes.py (run with the system python,
// plain and CLIP-like features). On each:
//  * the perfect removal (every target Gaussian) gives residual ≈ 0 and IoU_post ≈ 0;
//  * the empty removal gives IoU_drop = 0 exactly (same renders, same segmentation);
//  * across removals that leave known parts of the target (the simulated methods' masks and random
//    subsets), residual_feat rank-correlates with the share of the target's visible opacity left
//    (its Σ α·T over the after renders / over the before renders, computed here with the renderer);
//  * the feature segmentation of the before render matches the ground-truth object masks (labels
//    rendered, share >= 0.5): IoU per view (numbers in docs/eval.md).
// Test seeds (3, 4) differ from the seeds the defaults were looked at on (1, 2).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <numeric>

#include <gtest/gtest.h>

#include "al/eval/eval.hpp"
#include "al/eval/inputs.hpp"
#include "al/fixtures/synth.hpp"
#include "al/io/cameras.hpp"
#include "al/io/masks.hpp"
#include "al/io/ply.hpp"
#include "fixtures/rng.hpp"
#include "test_data.hpp"

namespace al::eval {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string name;
  Scene scene;
  std::vector<std::int32_t> labels;
  int target = 0;
  std::vector<Camera> cameras;
  std::vector<std::pair<std::string, std::vector<bool>>> masks;  // simulated removals
};

std::vector<bool> TargetSet(const Case& c) {
  std::vector<bool> t(c.labels.size());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = c.labels[i] == c.target;
  return t;
}

// A random share of the target's Gaussians (deterministic).
std::vector<bool> RandomPart(const Case& c, double share, std::uint64_t seed) {
  std::vector<bool> r(c.labels.size(), false);
  fixtures::Rng rng(seed, 17);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = c.labels[i] == c.target && rng.Uniform() < share;
  return r;
}

// Per removal: Σ over views of the target's α·T left in the after render / in the before render.
std::vector<double> VisibleShareLeft(const Case& c, const std::vector<EvalColumn>& columns) {
  const std::vector<bool> target = TargetSet(c);
  RenderOptions o;
  o.weight_subset = &target;
  o.compute_front_id = false;
  double before = 0;
  std::vector<double> after(columns.size(), 0.0);
  for (const Camera& cam : c.cameras) {
    for (float w : Render(c.scene, cam, o).subset_weight) before += w;
    for (std::size_t k = 0; k < columns.size(); ++k)
      for (float w : Render(c.scene, cam, o, columns[k].removed).subset_weight) after[k] += w;
  }
  for (double& a : after) a = before > 0 ? a / before : 0.0;
  return after;
}

std::vector<double> Ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return v[a] < v[b]; });
  std::vector<double> rank(v.size());
  for (std::size_t i = 0; i < order.size();) {  // ties share their average rank
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) rank[order[k]] = 0.5 * double(i + j);
    i = j + 1;
  }
  return rank;
}

double Spearman(const std::vector<double>& a, const std::vector<double>& b) {
  const std::vector<double> ra = Ranks(a), rb = Ranks(b);
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / double(ra.size());
  const double mb = std::accumulate(rb.begin(), rb.end(), 0.0) / double(rb.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

struct Outcome {
  EvalResult result;
  std::vector<std::string> names;
  std::vector<double> share_left;
};

// Evaluates the perfect, empty, simulated and random removals with the feature metrics on.
Outcome Evaluate(const Case& c, bool use_labels) {
  std::vector<EvalColumn> columns = {{"perfect", "perfect", TargetSet(c), "", ""},
                                     {"empty", "empty", std::vector<bool>(c.labels.size(), false), "", ""}};
  for (const auto& [name, mask] : c.masks) columns.push_back({name, name, mask, "", ""});
  for (double share : {0.5, 0.9})
    columns.push_back({"random" + std::to_string(int(share * 100)), "random", RandomPart(c, share, 5), "", ""});
  ObjectSource object;
  object.labels = c.labels;
  object.object_id = c.target;
  EvalOptions o;
  o.out_dir = (test::TempDir() / "eval").string();
  o.progress = false;
  o.write_images = false;
  o.write_depth_pngs = false;
  o.feature.mode = FeatureEvalOptions::Mode::kOn;
  o.feature.use_labels = use_labels;
  Outcome out;
  out.result = RunEval(c.scene, c.cameras, columns, object, o);
  for (const EvalColumn& col : columns) out.names.push_back(col.name);
  out.share_left = VisibleShareLeft(c, columns);
  return out;
}

void CheckOutcome(const Case& c, const Outcome& out, double min_spearman, double min_mean_iou) {
  const EvalResult& r = out.result;
  ASSERT_GT(r.evaluated, 0u) << c.name;
  const metrics::FeatureSummary& perfect = *r.summaries.at(0).feature;
  const metrics::FeatureSummary& empty = *r.summaries.at(1).feature;
  EXPECT_LT(perfect.residual.mean, 0.02) << c.name;
  EXPECT_LT(perfect.semantic.iou_after, 0.02) << c.name;
  EXPECT_EQ(empty.semantic.iou_drop, 0.0) << c.name;
  EXPECT_EQ(empty.residual.mean, 1.0) << c.name;
  // The before segmentation against the ground-truth masks.
  EXPECT_GT(perfect.semantic.iou_before, min_mean_iou) << c.name;
  std::vector<double> residual;
  std::string table;
  for (std::size_t k = 0; k < out.names.size(); ++k) {
    residual.push_back(r.summaries[k].feature->residual.mean);
    table += "  " + out.names[k] + ": visible share left " + std::to_string(out.share_left[k]) + ", residual " +
             std::to_string(residual.back()) + "\n";
  }
  const double rho = Spearman(out.share_left, residual);
  EXPECT_GE(rho, min_spearman) << c.name << "\n" << table;
  std::printf("%s: Spearman %.3f, IoU(before seg, GT) %.3f\n%s", c.name.c_str(), rho, perfect.semantic.iou_before,
              table.c_str());
}

Case SynthCase(const std::string& preset, std::uint64_t seed) {
  fixtures::SynthOptions o;
  o.preset = preset;
  o.num_gaussians = 20000;
  o.seed = seed;
  o.num_views = 5;
  o.width = 160;
  o.height = 120;
  fixtures::SynthScene s = fixtures::Synthesize(o);
  Case c;
  c.name = "synth " + preset + " seed " + std::to_string(seed);
  c.scene = std::move(s.scene);
  c.labels = s.labels;
  c.target = s.target_id;
  c.cameras = s.cameras;
  for (const char* m : {"fgs", "sags", "gg", "gc"}) c.masks.push_back({m, s.removed.at(m)});
  return c;
}

TEST(FeatureMetrics, SynthRoom) {
  const Case c = SynthCase("room", 3);
  CheckOutcome(c, Evaluate(c, true), 0.9, 0.85);
}

TEST(FeatureMetrics, SynthCounter) {
  const Case c = SynthCase("counter", 4);
  CheckOutcome(c, Evaluate(c, true), 0.9, 0.85);
}

// ../shared/scenes/gen_scenes.py needs python3 with numpy and scipy (scripts/setup installs them).
fs::path GenScenes() {
  if (const char* env = std::getenv("AL_GEN_SCENES"); env && *env) return env;
  return fs::path(AL_SOURCE_DIR) / ".." / "shared" / "scenes" / "gen_scenes.py";
}

std::string Python() {
  const char* env = std::getenv("AL_PYTHON");
  return env && *env ? env : "/usr/bin/python3";
}

// Generates a gen_scenes.py scene into a temporary folder; empty path (and a message) when the
// generator or its python cannot run.
fs::path Generate(std::uint64_t seed, const std::string& style, std::string& why) {
  const fs::path script = GenScenes();
  if (!fs::is_regular_file(script)) {
    why = script.string() + " not found (set AL_GEN_SCENES)";
    return {};
  }
  if (std::system((Python() + " -c 'import numpy, scipy' > /dev/null 2>&1").c_str()) != 0) {
    why = Python() + " lacks numpy/scipy (scripts/setup installs python3-numpy python3-scipy; or set AL_PYTHON)";
    return {};
  }
  const fs::path dir = test::TempDir() / ("gen_" + style + std::to_string(seed));
  const std::string cmd = Python() + " " + script.string() + " --out " + dir.string() + " --seed " +
                          std::to_string(seed) + " --n-gaussians 20000 --feature-style " + style + " > " +
                          (dir.string() + ".log") + " 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    why = "gen_scenes.py failed: see " + dir.string() + ".log";
    return {};
  }
  return dir;
}

Case GenCase(const fs::path& dir, const std::string& name) {
  Case c;
  c.name = name;
  c.scene = ReadScene((dir / "scene.ply").string());
  c.labels = LoadLabels((dir / "labels.npy").string(), c.scene.size());
  c.target = ResolveTarget((dir / "labels.npy").string(), std::nullopt).object_id;
  // 4 of the 12 views keep the test fast.
  c.cameras = SelectViews(ReadCameras((dir / "cameras.json").string()).cameras, "all");
  std::vector<Camera> every_third;
  for (std::size_t v = 0; v < c.cameras.size(); v += 3) every_third.push_back(c.cameras[v]);
  c.cameras = every_third;
  for (const char* m : {"fgs_like", "sags_like", "gg_like"})
    c.masks.push_back({m, LoadRemovalSet((dir / ("removed_" + std::string(m) + ".npy")).string(), c.scene).removed});
  return c;
}

#define AL_REQUIRE_GEN_SCENE(dir, seed, style)                                                        \
  std::string why;                                                                                     \
  const fs::path dir = Generate(seed, style, why);                                                     \
  if (dir.empty()) {                                                                                   \
    if (const char* req = std::getenv("AL_REQUIRE_TEST_DATA"); req && std::string(req) == "1")        \
      FAIL() << "AL_REQUIRE_TEST_DATA=1 but " << why;                                                  \
    GTEST_SKIP() << "*** SKIPPED: " << why << " ***";                                                  \
  }

TEST(FeatureMetrics, GenScenesClipWithLabels) {
  AL_REQUIRE_GEN_SCENE(dir, 3, "clip");
  const Case c = GenCase(dir, "gen_scenes clip seed 3");
  CheckOutcome(c, Evaluate(c, true), 0.9, 0.85);
}

// Without labels: the target prototype from the removal (the perfect one, column 0) and k-means
// competitors; plain features this time.
TEST(FeatureMetrics, GenScenesPlainWithoutLabels) {
  AL_REQUIRE_GEN_SCENE(dir, 4, "plain");
  const Case c = GenCase(dir, "gen_scenes plain seed 4, no labels");
  CheckOutcome(c, Evaluate(c, false), 0.9, 0.85);
}

}  // namespace
}  // namespace al::eval
