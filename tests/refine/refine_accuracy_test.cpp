// End to end on synthetic scenes with ground truth (fixed seeds, all three presets): graph + bk +
// the default decision (threshold 0.5, segment rule). For every simulator refinement never lowers
// F1 by more than 0.01 (it only adds); for the FGS simulator it raises F1 on most scenes.
// (The tests' ScoreRemoval F1 is by count; opacity is passed only for the weighted scores.)
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "al/decision.hpp"
#include "al/fixtures/synth.hpp"
#include "al/graph/graph.hpp"
#include "al/solver.hpp"

namespace {

TEST(RefineAccuracy, SyntheticScenesFixedSeeds) {
  // 15 scenes (~0.4 s each): 5 seeds would let one lucky or unlucky draw decide "most".
  const std::vector<std::pair<std::string, std::uint64_t>> scenes = {
      {"room", 1},    {"room", 2},    {"room", 3},    {"room", 4},    {"room", 5},
      {"counter", 1}, {"counter", 2}, {"counter", 3}, {"counter", 4}, {"counter", 5},
      {"garden", 1},  {"garden", 2},  {"garden", 3},  {"garden", 4},  {"garden", 5}};
  int fgs_improved = 0, fgs_runs = 0, runs = 0;
  for (const auto& [preset, seed] : scenes) {
    al::fixtures::SynthOptions so;
    so.preset = preset;
    so.num_gaussians = 20000;
    so.seed = seed;
    so.num_views = 2;
    so.width = 32;
    so.height = 24;
    so.compute_masks = false;  // the SAGS simulator needs masks: fgs, gg, gc only
    const al::fixtures::SynthScene s = al::fixtures::Synthesize(so);
    std::vector<float> opacity(s.scene.opacity_logits.data(),
                               s.scene.opacity_logits.data() + s.scene.size());
    for (const auto& [method, removed] : s.removed) {
      const auto graph = al::BuildRefineGraph(s.scene, s.scene.features, removed, {});
      if (graph.problem.num_edges() == 0) continue;
      ++runs;
      const auto sol = al::MakeSolver("bk")->Solve(graph.problem);
      const auto d = al::ApplyDecision(removed, graph.problem, sol.p);
      const double before = al::ScoreRemoval(removed, s.labels, s.target_id, opacity).f1;
      const double after = al::ScoreRemoval(d.refined, s.labels, s.target_id, opacity).f1;
      EXPECT_GE(after, before - 0.01) << method << " " << preset << " seed " << seed;
      if (method == "fgs") {
        ++fgs_runs;
        fgs_improved += after > before;
      }
    }
  }
  EXPECT_EQ(runs, 3 * int(scenes.size()));
  ASSERT_EQ(fgs_runs, int(scenes.size()));
  EXPECT_GT(fgs_improved, fgs_runs / 2) << fgs_improved << " of " << fgs_runs;
}

// SAGS needs target masks (its vote projects centres into them), which cost more: fewer scenes.
TEST(RefineAccuracy, SagsNeverLowersF1) {
  for (const std::string preset : {"room", "counter", "garden"}) {
    al::fixtures::SynthOptions so;
    so.preset = preset;
    so.num_gaussians = 20000;
    so.seed = 1;
    so.num_views = 8;
    so.width = 64;
    so.height = 48;
    const al::fixtures::SynthScene s = al::fixtures::Synthesize(so);
    ASSERT_EQ(s.removed.count("sags"), 1u) << preset;
    const auto& removed = s.removed.at("sags");
    const auto graph = al::BuildRefineGraph(s.scene, s.scene.features, removed, {});
    ASSERT_GT(graph.problem.num_edges(), 0u) << preset;
    const auto sol = al::MakeSolver("bk")->Solve(graph.problem);
    const auto d = al::ApplyDecision(removed, graph.problem, sol.p);
    const double before = al::ScoreRemoval(removed, s.labels, s.target_id).f1;
    const double after = al::ScoreRemoval(d.refined, s.labels, s.target_id).f1;
    EXPECT_GE(after, before - 0.01) << preset;
  }
}

// The failure the segment rule exists for (docs/refine.md): on this scene FGS grabs 38 % of the
// look-alike (a tray: its contact band with the table and its "off" part stay), the cut completes
// that segment and the plain rule of SPEC §5 loses 0.026 F1; the segment rule holds it back.
TEST(RefineAccuracy, SegmentRuleLeavesASplitLookAlikeAlone) {
  al::fixtures::SynthOptions so;
  so.preset = "counter";
  so.num_gaussians = 20000;
  so.seed = 11;
  so.num_views = 2;
  so.width = 32;
  so.height = 24;
  so.compute_masks = false;
  const al::fixtures::SynthScene s = al::fixtures::Synthesize(so);
  const auto& removed = s.removed.at("fgs");
  const auto graph = al::BuildRefineGraph(s.scene, s.scene.features, removed, {});
  const auto sol = al::MakeSolver("bk")->Solve(graph.problem);
  al::DecisionOptions plain;
  plain.min_segment_share = 0.0;
  const auto d_plain = al::ApplyDecision(removed, graph.problem, sol.p, plain);
  const auto d_rule = al::ApplyDecision(removed, graph.problem, sol.p);
  auto f1 = [&](const std::vector<bool>& m) { return al::ScoreRemoval(m, s.labels, s.target_id).f1; };
  const double before = f1(removed);
  EXPECT_LT(f1(d_plain.refined), before - 0.02);
  EXPECT_GE(f1(d_rule.refined), before - 0.01);
  EXPECT_GT(d_rule.held_back, 50u);
  // What is held back is the look-alike, not the target.
  std::size_t held_distractor = 0, held = 0;
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (d_plain.refined[i] && !d_rule.refined[i]) {
      ++held;
      held_distractor += s.labels[i] == s.distractor_id;
    }
  EXPECT_EQ(held, d_rule.held_back);
  EXPECT_GT(held_distractor, held * 9 / 10);
}

}  // namespace
