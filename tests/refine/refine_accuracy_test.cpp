// End to end on synthetic scenes with ground truth (fixed seeds, all three presets): the default
// refine stages (centred features, feature prior, candidate growth, restore; al/refine/stages.hpp)
// with bk. For every simulator refinement never lowers F1 by more than 0.01 (one documented
// look-alike case: 0.02); for GaussianCut's boundary errors it raises F1 on every scene and
// recovers most misses.
// The gen_scenes.py half of the accuracy regression is tests/accuracy (docs/accuracy.md).
// (ScoreRemoval's F1 is by count; opacity is passed only for the weighted scores.)
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "al/fixtures/synth.hpp"
#include "al/refine/stages.hpp"
#include "al/solver.hpp"

namespace {

// An in-memory synthetic scene as the refine stages see it after loading (no preset).
al::RefineInputs InputsOf(const al::fixtures::SynthScene& s, const std::vector<bool>& removed) {
  al::RefineInputs in;
  in.scene = std::make_shared<const al::Scene>(s.scene);
  in.SetFeatures(s.scene.features);
  in.feature_source = "semantic_*";
  in.removal.removed = removed;
  for (bool b : removed) in.removal.num_removed += b;
  return in;
}

// The refine stages on an in-memory synthetic scene (what `al-refine refine --method generic`
// does after loading).
al::SolveOutcome RefineDefault(const al::fixtures::SynthScene& s, const std::vector<bool>& removed,
                               const al::DecisionOptions& decision = {}) {
  const al::RefineInputs in = InputsOf(s, removed);
  auto solver = al::MakeSolver("bk");
  return al::BuildAndSolve(in, al::GraphOptions{}, *solver, decision).outcome;
}

al::fixtures::SynthScene Scene(const std::string& preset, std::uint64_t seed, bool masks,
                               std::size_t gaussians = 20000) {
  al::fixtures::SynthOptions so;
  so.preset = preset;
  so.num_gaussians = gaussians;
  so.seed = seed;
  so.num_views = masks ? 8 : 2;
  so.width = masks ? 64 : 32;
  so.height = masks ? 48 : 24;
  so.compute_masks = masks;  // the SAGS simulator needs masks
  return al::fixtures::Synthesize(so);
}

TEST(RefineAccuracy, SyntheticScenesFixedSeeds) {
  // 15 scenes (~0.5 s each): 5 seeds would let one lucky or unlucky draw decide "most".
  int gc_raised = 0, gc_runs = 0, runs = 0;
  double gc_recovered = 0;
  for (const std::string preset : {"room", "counter", "garden"})
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const al::fixtures::SynthScene s = Scene(preset, seed, false);
      for (const auto& [method, removed] : s.removed) {
        const al::SolveOutcome out = RefineDefault(s, removed);
        if (out.empty_graph) continue;
        ++runs;
        const auto before = al::ScoreRemoval(removed, s.labels, s.target_id);
        const auto after = al::ScoreRemoval(out.refined, s.labels, s.target_id);
        // One known exception, garden seed 2: FGS grabbed 70 % of a look-alike and refinement
        // completes part of it (-0.017 F1; docs/refine.md, what the model cannot know).
        const bool lookalike = method == "fgs" && preset == "garden" && seed == 2;
        EXPECT_GE(after.f1, before.f1 - (lookalike ? 0.02 : 0.01)) << method << " " << preset << " seed " << seed;
        if (method == "gc") {
          ++gc_runs;
          gc_raised += after.f1 > before.f1;
          gc_recovered += double(after.true_positive - before.true_positive) / double(before.false_negative);
        }
      }
    }
  EXPECT_EQ(runs, 45);
  ASSERT_EQ(gc_runs, 15);
  EXPECT_EQ(gc_raised, 15);
  EXPECT_GT(gc_recovered / gc_runs, 0.5);  // share of GC's misses recovered, mean over scenes
}

// SAGS needs target masks (its vote projects centres into them), which cost more: fewer scenes.
TEST(RefineAccuracy, SagsNeverLowersF1) {
  for (const std::string preset : {"room", "counter", "garden"}) {
    const al::fixtures::SynthScene s = Scene(preset, 1, true);
    ASSERT_EQ(s.removed.count("sags"), 1u) << preset;
    const auto& removed = s.removed.at("sags");
    const al::SolveOutcome out = RefineDefault(s, removed);
    ASSERT_FALSE(out.empty_graph) << preset;
    const double before = al::ScoreRemoval(removed, s.labels, s.target_id).f1;
    const double after = al::ScoreRemoval(out.refined, s.labels, s.target_id).f1;
    EXPECT_GE(after, before - 0.01) << preset;
  }
}

// The failure the old segment rule existed for (docs/refine.md): on this scene FGS grabs most of a
// look-alike tray (its contact band with the table and its "off" part stay), and completing that
// tray lost 0.026 F1. The feature prior gives the tray's kept part no credit (it lies below the
// removed set's spread), so the default adds almost none of it and F1 does not drop.
TEST(RefineAccuracy, ASplitLookAlikeIsNotCompleted) {
  const al::fixtures::SynthScene s = Scene("counter", 11, false);
  const auto& removed = s.removed.at("fgs");
  std::size_t lookalike_kept = 0;
  for (std::size_t i = 0; i < removed.size(); ++i) lookalike_kept += !removed[i] && s.labels[i] == s.distractor_id;
  ASSERT_GT(lookalike_kept, 100u);
  const al::SolveOutcome out = RefineDefault(s, removed);
  std::size_t lookalike_added = 0;
  for (std::size_t i = 0; i < removed.size(); ++i)
    lookalike_added += out.refined[i] && !removed[i] && s.labels[i] == s.distractor_id;
  EXPECT_LT(lookalike_added, lookalike_kept / 10);
  const double before = al::ScoreRemoval(removed, s.labels, s.target_id).f1;
  EXPECT_GE(al::ScoreRemoval(out.refined, s.labels, s.target_id).f1, before - 0.01);
}

// --prototype-credit auto follows the preset (on for sags only); on/off override it.
TEST(RefineAccuracy, PrototypeCreditFollowsThePreset) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("fgs"));
  auto rows = [&](const al::MethodPreset& preset, al::PriorSwitch credit) {
    in.preset = preset;
    al::GraphOptions o;
    o.prior.prototype_credit = credit;
    o.prior.second_object_guard = al::PriorSwitch::kOff;  // this fgs mask holds a look-alike's part
    return al::BuildGraphFor(in, o).stats.prior.prototype_rows;
  };
  using C = al::PriorSwitch;
  EXPECT_GT(rows({.prototype_credit = true}, C::kAuto), 0u);
  EXPECT_EQ(rows({.prototype_credit = false}, C::kAuto), 0u);
  EXPECT_GT(rows(al::MethodPresetFor("sags"), C::kAuto), 0u);
  EXPECT_EQ(rows(al::MethodPresetFor("generic"), C::kAuto), 0u);
  EXPECT_GT(rows({.prototype_credit = false}, C::kOn), 0u);
  EXPECT_EQ(rows({.prototype_credit = true}, C::kOff), 0u);
}

// --prior-weight auto: the preset's weight (0.55 for gg and sags), 0.5 without one; a number wins.
TEST(RefineAccuracy, PriorWeightFollowsThePreset) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("fgs"));
  auto weight = [&](const al::MethodPreset& preset, std::optional<double> w) {
    in.preset = preset;
    al::GraphOptions o;
    o.prior.weight = w;
    return al::BuildGraphFor(in, o).stats.prior.weight;
  };
  EXPECT_DOUBLE_EQ(weight({.prior_weight = 0.55}, std::nullopt), 0.55);
  EXPECT_DOUBLE_EQ(weight(al::MethodPresetFor("gg"), std::nullopt), 0.55);
  EXPECT_DOUBLE_EQ(weight(al::MethodPresetFor("fgs"), std::nullopt), 0.5);
  EXPECT_DOUBLE_EQ(weight(al::MethodPresetFor("generic"), std::nullopt), 0.5);
  EXPECT_DOUBLE_EQ(weight({.prior_weight = 0.55}, 0.25), 0.25);
}

// --feature-width auto: the preset's (2 for sags), 1 without one; a number wins.
TEST(RefineAccuracy, FeatureWidthFollowsThePreset) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("fgs"));
  auto sigma_over_gate = [&](const char* method, std::optional<double> width) {
    in.preset = al::MethodPresetFor(method);
    al::GraphOptions o;
    o.feature_width = width;
    const al::GraphStats st = al::BuildGraphFor(in, o).stats;
    return st.sigma_f / st.gate_distance;
  };
  EXPECT_DOUBLE_EQ(sigma_over_gate("sags", std::nullopt), 2.0);
  for (const char* method : {"fgs", "gg", "gc", "generic"}) EXPECT_DOUBLE_EQ(sigma_over_gate(method, std::nullopt), 1.0);
  EXPECT_DOUBLE_EQ(sigma_over_gate("sags", 1.0), 1.0);
  EXPECT_DOUBLE_EQ(sigma_over_gate("fgs", 3.0), 3.0);
}

// --lambda auto: the preset's λ for the solver (gg with bk: 1.5; cut pursuit and the other presets:
// 1), applied to the edge weights (the graph reports it); a number wins. λ scales every weight.
TEST(RefineAccuracy, LambdaFollowsThePresetAndTheSolver) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("gg"));
  auto solve = [&](const char* method, const char* solver_name, std::optional<double> lambda) {
    in.preset = al::MethodPresetFor(method);
    al::GraphOptions o;
    o.grow_rounds = 0;
    o.lambda = lambda;
    auto solver = al::MakeSolver(solver_name);
    return al::BuildAndSolve(in, o, *solver, al::DecisionOptions{}).graph;
  };
  EXPECT_DOUBLE_EQ(al::MethodPresetFor("gg").LambdaFor("bk"), 1.5);
  EXPECT_DOUBLE_EQ(al::MethodPresetFor("gg").LambdaFor("cp"), 1.0);
  EXPECT_DOUBLE_EQ(al::MethodPresetFor("gg").LambdaFor("exact"), 1.0);
  EXPECT_DOUBLE_EQ(al::MethodPresetFor("fgs").LambdaFor("bk"), 1.0);
  const al::GraphResult gg_bk = solve("gg", "bk", std::nullopt), gg_cp = solve("gg", "cp", std::nullopt);
  const al::GraphResult fgs_bk = solve("generic", "bk", std::nullopt), gg_bk_1 = solve("gg", "bk", 1.0);
  EXPECT_DOUBLE_EQ(gg_bk.stats.lambda, 1.5);
  EXPECT_DOUBLE_EQ(gg_cp.stats.lambda, 1.0);
  EXPECT_DOUBLE_EQ(fgs_bk.stats.lambda, 1.0);
  EXPECT_DOUBLE_EQ(gg_bk_1.stats.lambda, 1.0);
  ASSERT_EQ(gg_bk.problem.edge_weights.size(), gg_bk_1.problem.edge_weights.size());
  ASSERT_FALSE(gg_bk.problem.edge_weights.empty());
  for (std::size_t e = 0; e < gg_bk.problem.edge_weights.size(); e += 97)
    EXPECT_NEAR(gg_bk.problem.edge_weights[e], 1.5 * gg_bk_1.problem.edge_weights[e], 1e-12);
}

// --centre auto: the fgs preset's "shared" leaves a synth field (no strong shared component)
// uncentred; without a preset, or with another one, auto centres; an explicit choice wins.
TEST(RefineAccuracy, CentringFollowsThePreset) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("fgs"));
  auto centred = [&](const al::MethodPreset& preset, al::Centring centre) {
    in.preset = preset;
    al::GraphOptions o;
    o.centre = centre;
    const al::GraphStats st = al::BuildGraphFor(in, o).stats;
    EXPECT_LT(st.common_component, al::kSharedComponentNorm);
    return st.centred;
  };
  using C = al::Centring;
  EXPECT_FALSE(centred({.centre = C::kShared}, C::kAuto));
  EXPECT_FALSE(centred(al::MethodPresetFor("fgs"), C::kAuto));
  EXPECT_TRUE(centred({.centre = C::kOn}, C::kAuto));
  EXPECT_TRUE(centred(al::MethodPresetFor("generic"), C::kAuto));
  EXPECT_TRUE(centred({.centre = C::kShared}, C::kOn));
  EXPECT_FALSE(centred({.centre = C::kOn}, C::kOff));
}

// --restore auto: the gc preset's "off" keeps every removed Gaussian removed; other presets, no
// preset, or an explicit --restore on let the cut return them.
TEST(RefineAccuracy, RestoreFollowsThePreset) {
  const al::fixtures::SynthScene s = Scene("room", 2, false);
  al::RefineInputs in = InputsOf(s, s.removed.at("fgs"));
  // Restored count; the report's decision says whether restore was on.
  auto restored = [&](const al::MethodPreset& preset, al::Restore restore, bool expect_on) {
    in.preset = preset;
    al::DecisionOptions d;
    d.restore = restore;
    auto solver = al::MakeSolver("bk");
    const al::SolveOutcome out = al::BuildAndSolve(in, al::GraphOptions{}, *solver, d).outcome;
    EXPECT_EQ(out.decision.at("restore").get<bool>(), expect_on);
    return out.restored;
  };
  using R = al::Restore;
  const std::size_t base = restored({.restore = true}, R::kAuto, true);
  ASSERT_GT(base, 0u);  // the scene has something to restore
  EXPECT_EQ(restored({.restore = false}, R::kAuto, false), 0u);
  EXPECT_EQ(restored(al::MethodPresetFor("gc"), R::kAuto, false), 0u);
  EXPECT_EQ(restored(al::MethodPresetFor("generic"), R::kAuto, true), base);
  EXPECT_EQ(restored({.restore = false}, R::kOn, true), base);
  EXPECT_EQ(restored({.restore = true}, R::kOff, false), 0u);
}

}  // namespace

namespace {

// FGS took a second object with its target (al/graph/removed_parts.hpp): with the fgs preset's
// wide credit, crediting kept Gaussians completed the other object (garden seed 2: 109 credited,
// 106 of the 108 added not the target, F1 −0.019). The guard finds the second part and credits no
// kept Gaussian; turned off, the old behaviour returns.
TEST(RefineAccuracy, ASecondObjectInTheRemovedSetGetsNoFeatureCredit) {
  const al::fixtures::SynthScene s = Scene("garden", 2, false);
  const auto& removed = s.removed.at("fgs");
  al::RefineInputs in = InputsOf(s, removed);
  in.preset = al::MethodPresetFor("fgs");
  auto refine = [&](al::PriorSwitch guard, al::GraphStats& st) {
    al::GraphOptions o;
    o.prior.second_object_guard = guard;
    o.second_object_tolerance = 1.0;  // the credit alone (the trim is the next test's)
    auto solver = al::MakeSolver("bk");
    const al::GrownSolve run = al::BuildAndSolve(in, o, *solver, al::DecisionOptions{});
    st = run.graph.stats;
    std::size_t other_added = 0;
    for (std::size_t i = 0; i < removed.size(); ++i)
      other_added += run.outcome.refined[i] && !removed[i] && s.labels[i] != s.target_id;
    return std::pair{other_added, al::ScoreRemoval(run.outcome.refined, s.labels, s.target_id).f1};
  };
  al::GraphStats guarded, unguarded;
  const auto [other_guarded, f1_guarded] = refine(al::PriorSwitch::kAuto, guarded);
  const auto [other_unguarded, f1_unguarded] = refine(al::PriorSwitch::kOff, unguarded);
  ASSERT_TRUE(guarded.second_object.Found());
  EXPECT_GT(guarded.second_object.share, al::kSecondShare);
  EXPECT_LT(guarded.second_object.cosine, al::kSameObjectCosine);
  EXPECT_FALSE(guarded.prior.kept_credit);
  EXPECT_EQ(guarded.prior.kept_doubted, 0u);
  EXPECT_TRUE(unguarded.prior.kept_credit);
  EXPECT_GT(unguarded.prior.kept_doubted, 50u);
  EXPECT_LT(other_guarded + 40, other_unguarded);
  EXPECT_GT(f1_guarded, f1_unguarded + 0.005);
}

// The trim (al/graph/either_object.hpp), on the bench's worst synth fgs scene (garden seed 31 at
// 60k, the accuracy bench's mask): FGS took 3,616 Gaussians of a look-alike and 2,910 of the
// target, and the cut completes the look-alike through its own edges, credit or not (F1 0.559 →
// 0.544 untrimmed). Read both ways, those additions cost the other reading more than the
// tolerance; taken back farthest first (194, all look-alike), F1 drops by less than 0.01 (0.553).
TEST(RefineAccuracy, OneSidedCompletionOfASecondObjectIsTrimmed) {
  const al::fixtures::SynthScene s = Scene("garden", 31, false, 60000);
  const auto& removed = s.removed.at("fgs");
  al::RefineInputs in = InputsOf(s, removed);
  in.preset = al::MethodPresetFor("fgs");
  auto refine = [&](double tolerance) {
    al::GraphOptions o;
    o.second_object_tolerance = tolerance;
    auto solver = al::MakeSolver("bk");
    return al::BuildAndSolve(in, o, *solver, al::DecisionOptions{}).outcome;
  };
  const al::SolveOutcome trimmed = refine(al::kEitherObjectTolerance), untrimmed = refine(1.0);
  ASSERT_TRUE(trimmed.decision.contains("either_object"));
  const nlohmann::json& eo = trimmed.decision["either_object"];
  const std::size_t back = eo["trimmed"].get<std::size_t>();
  EXPECT_GT(back, 100u);
  EXPECT_EQ(trimmed.added + back, untrimmed.added);
  EXPECT_FALSE(untrimmed.decision.contains("either_object"));
  EXPECT_LT(eo["worst_reading_dF1_before"].get<double>(), -al::kEitherObjectTolerance);
  EXPECT_GE(eo["worst_reading_dF1_after"].get<double>(), -al::kEitherObjectTolerance);
  std::size_t lookalike_back = 0, target_back = 0;
  for (std::size_t i = 0; i < removed.size(); ++i) {
    if (removed[i] || !untrimmed.refined[i] || trimmed.refined[i]) continue;
    (s.labels[i] == s.target_id ? target_back : lookalike_back) += 1;
  }
  EXPECT_EQ(target_back + lookalike_back, back);
  EXPECT_GT(lookalike_back, 4 * target_back);
  const double before = al::ScoreRemoval(removed, s.labels, s.target_id).f1;
  EXPECT_LT(al::ScoreRemoval(untrimmed.refined, s.labels, s.target_id).f1, before - 0.01);
  EXPECT_GE(al::ScoreRemoval(trimmed.refined, s.labels, s.target_id).f1, before - 0.01);
}

// An object part the method took whole (al/graph/taken_whole.hpp): on this scene GG's hull took
// the mug together with a part of it whose features are off (synth's "off parts") and some table
// top; the prior doubts the part like the table top, and the cut gave it back (F1 0.854 → 0.780
// with the guard off). Its feature region is mostly removed, so it stays removed; the table top
// is still restored.
TEST(RefineAccuracy, AnObjectPartTheMethodTookWholeStaysRemoved) {
  const al::fixtures::SynthScene s = Scene("counter", 28, false);
  const auto& removed = s.removed.at("gg");
  al::RefineInputs in = InputsOf(s, removed);
  in.preset = al::MethodPresetFor("gg");
  auto refine = [&](al::PriorSwitch guard) {
    al::GraphOptions o;
    o.taken_whole_guard = guard;
    auto solver = al::MakeSolver("bk");
    return al::BuildAndSolve(in, o, *solver, al::DecisionOptions{}).outcome;
  };
  const al::SolveOutcome guarded = refine(al::PriorSwitch::kAuto), unguarded = refine(al::PriorSwitch::kOff);
  const double before = al::ScoreRemoval(removed, s.labels, s.target_id).f1;
  std::size_t object_restored = 0, background_restored = 0, kept_removed = 0;
  for (std::size_t i = 0; i < removed.size(); ++i) {
    if (!removed[i]) continue;
    (s.labels[i] == s.target_id ? object_restored : background_restored) += !guarded.refined[i];
    kept_removed += guarded.refined[i] && !unguarded.refined[i];
  }
  ASSERT_TRUE(guarded.decision.contains("taken_whole"));
  EXPECT_EQ(guarded.decision["taken_whole"]["kept"].get<std::size_t>(), kept_removed);
  EXPECT_GT(kept_removed, 200u);
  EXPECT_EQ(guarded.restored + kept_removed, unguarded.restored);
  EXPECT_LT(object_restored, 10u);
  EXPECT_GT(background_restored, 100u);
  EXPECT_LT(al::ScoreRemoval(unguarded.refined, s.labels, s.target_id).f1, before - 0.05);
  EXPECT_GT(al::ScoreRemoval(guarded.refined, s.labels, s.target_id).f1, before + 0.01);
}

}  // namespace
