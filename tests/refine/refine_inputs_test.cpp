// What refine reads (issue 13, item 4): a mask or index list is the removed set whatever the
// preset (only a subset PLY may be a remaining scene), a removed set above half the scene is
// warned about, and presets without features of their own (sags, gg on a scene without obj_dc_*)
// take the scene's semantic features when present, colour otherwise, and say which.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

#include "al/core/report.hpp"
#include "al/fixtures/synth.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

// A small synthetic room written once: scene.ply (with semantic_*), plain.ply (no features),
// mask.npy (the FGS simulator's removal), remaining.ply (the complement, GG's output form).
struct Fixture {
  fs::path dir;
  std::size_t n = 0, removed = 0;
  Fixture() {
    dir = fs::temp_directory_path() / ("al_refine_inputs_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fixtures::SynthOptions so;
    so.num_gaussians = 3000;
    so.seed = 3;
    so.num_views = 1;
    so.compute_masks = false;
    fixtures::SynthScene s = fixtures::Synthesize(so);
    n = s.scene.size();
    const std::vector<bool>& mask = s.removed.at("fgs");
    for (bool b : mask) removed += b;
    WritePly((dir / "scene.ply").string(), s.scene);
    WriteNpyBool((dir / "mask.npy").string(), mask);
    std::vector<bool> keep(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) keep[i] = !mask[i];
    WritePly((dir / "remaining.ply").string(), s.scene, keep);
    std::vector<bool> most(n, false);
    for (std::size_t i = 0; i < n / 2 + 1; ++i) most[i] = true;
    WriteNpyBool((dir / "most.npy").string(), most);
    std::vector<bool> half(n, false);
    for (std::size_t i = 0; i < n / 2; ++i) half[i] = true;
    WriteNpyBool((dir / "half.npy").string(), half);
    s.scene.features.resize(0, 0);
    WritePly((dir / "plain.ply").string(), s.scene);
  }
  ~Fixture() { fs::remove_all(dir); }
};

const Fixture& F() {
  static const Fixture f;
  return f;
}

RefineInputs Load(const std::string& method, const std::string& scene, const std::string& removed,
                  nlohmann::json& report, std::optional<RemovedIs> is = std::nullopt) {
  RefineOptions o;
  o.method = method;
  o.scene = (F().dir / scene).string();
  o.removed = (F().dir / removed).string();
  o.removed_is = is;
  report = NewReport("refine");
  return LoadRefineInputs(o, report);
}

bool AnyWarningHas(const nlohmann::json& report, const std::string& text) {
  for (const auto& w : report["warnings"])
    if (w.get<std::string>().find(text) != std::string::npos) return true;
  return false;
}

TEST(RefineInputs, AMaskIsTheRemovedSetForEveryPreset) {
  ASSERT_GT(F().removed, 0u);
  ASSERT_LT(2 * F().removed, F().n);
  for (const std::string method : {"fgs", "gg", "sags", "gc", "generic"}) {
    nlohmann::json report;
    const RefineInputs in = Load(method, "scene.ply", "mask.npy", report);
    EXPECT_EQ(in.removal.num_removed, F().removed) << method;
    EXPECT_EQ(in.removed_is, RemovedIs::kRemoved) << method;
    EXPECT_FALSE(AnyWarningHas(report, "more than half")) << method;
  }
}

TEST(RefineInputs, GgReadsASubsetPlyAsTheRemainingScene) {
  nlohmann::json report;
  const RefineInputs in = Load("gg", "scene.ply", "remaining.ply", report);
  EXPECT_EQ(in.removed_is, RemovedIs::kRemaining);
  EXPECT_EQ(in.removal.num_removed, F().removed);
  // Other presets read a subset PLY as removed rows: here the remaining rows, > half the scene.
  const RefineInputs as_removed = Load("sags", "scene.ply", "remaining.ply", report);
  EXPECT_EQ(as_removed.removal.num_removed, F().n - F().removed);
  EXPECT_TRUE(AnyWarningHas(report, "more than half"));
}

TEST(RefineInputs, RemovedIsRemainingComplementsAMaskWhenAsked) {
  nlohmann::json report;
  const RefineInputs in = Load("generic", "scene.ply", "mask.npy", report, RemovedIs::kRemaining);
  EXPECT_EQ(in.removal.num_removed, F().n - F().removed);
  EXPECT_TRUE(AnyWarningHas(report, "more than half"));
  EXPECT_TRUE(AnyWarningHas(report, "complement of the remaining rows"));
}

TEST(RefineInputs, WarnsOnlyAboveHalfTheScene) {
  nlohmann::json report;
  Load("generic", "scene.ply", "most.npy", report);
  EXPECT_TRUE(AnyWarningHas(report, "more than half"));
  Load("generic", "scene.ply", "half.npy", report);
  EXPECT_FALSE(AnyWarningHas(report, "more than half"));
}

TEST(RefineInputs, SagsAndGgTakeTheScenesSemanticFeaturesAndSaySo) {
  for (const std::string method : {"sags", "gg"}) {
    nlohmann::json report;
    const RefineInputs in = Load(method, "scene.ply", "mask.npy", report);
    EXPECT_FALSE(in.colour_fallback) << method;
    EXPECT_EQ(in.feature_source, "semantic_*") << method;
    EXPECT_EQ(in.features().cols(), 16) << method;
    EXPECT_TRUE(AnyWarningHas(report, "--method " + method + ": features semantic_*")) << report["warnings"];
  }
}

TEST(RefineInputs, SagsFallsBackToColourOnlyWithoutFeaturesAndSaysSo) {
  nlohmann::json report;
  const RefineInputs in = Load("sags", "plain.ply", "mask.npy", report);
  EXPECT_TRUE(in.colour_fallback);
  EXPECT_EQ(in.features().cols(), 3);
  EXPECT_TRUE(AnyWarningHas(report, "no feature columns found")) << report["warnings"];
  EXPECT_TRUE(AnyWarningHas(report, "colour")) << report["warnings"];
}

TEST(RefineInputs, TheSummaryLineNamesTheFeatureSource) {
  RefineOptions o;
  o.method = "sags";
  o.scene = (F().dir / "scene.ply").string();
  o.removed = (F().dir / "mask.npy").string();
  o.solver = "bk";
  o.out_dir = (F().dir / "out").string();
  const RefineResult r = RunRefine(o);
  EXPECT_NE(r.message.find("features semantic_*"), std::string::npos) << r.message;
  EXPECT_EQ(r.report["params"]["feature_source"], "semantic_*");
}

}  // namespace
}  // namespace al
