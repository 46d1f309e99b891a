// The refine stages' last steps (al/refine/stages.hpp: RunLastSteps), once per refinement after
// the final growth round: restores the method's own regions or features argue against stay
// removed, and one-sided completions of a second object or of a feature group are bounded
// (docs/refine.md pipeline steps 9-11, items 10, 11, 13-15).
#include <cstdio>
#include <string>
#include <utility>

#include "al/core/timer.hpp"
#include "al/graph/continuing_body.hpp"
#include "al/graph/either_object.hpp"
#include "al/graph/restore_window.hpp"
#include "al/graph/taken_whole.hpp"
#include "al/refine/stages.hpp"

namespace al {
namespace {

// The scene's positions as one 3N array, copied at most once per refinement and only when a last
// step needs them (the taken-whole walk and the readings' nearest parts both do).
class ScenePositions {
 public:
  explicit ScenePositions(const Scene& scene) : scene_(scene) {}
  const std::vector<float>& Get() {
    if (xyz_.size() != 3 * scene_.size()) {
      xyz_.resize(3 * scene_.size());
      for (std::size_t i = 0; i < scene_.size(); ++i)
        for (int a = 0; a < 3; ++a) xyz_[3 * i + std::size_t(a)] = scene_.means(Eigen::Index(i), a);
    }
    return xyz_;
  }

 private:
  const Scene& scene_;
  std::vector<float> xyz_;
};

// Per scene row: 1 = a node candidate of the graph's scene (not excluded as non-finite).
std::vector<std::uint8_t> ActiveRows(const GraphResult& graph) {
  std::vector<std::uint8_t> active(graph.excluded.size());
  for (std::size_t i = 0; i < active.size(); ++i) active[i] = !graph.excluded[i];
  return active;
}

// Scene rows the refinement gave back (removed, not refined), ascending.
std::vector<std::int64_t> RestoredRows(const std::vector<bool>& removed, const std::vector<bool>& refined) {
  std::vector<std::int64_t> rows;
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (removed[i] && !refined[i]) rows.push_back(static_cast<std::int64_t>(i));
  return rows;
}

// Restored Gaussians in a feature region the method took whole stay removed
// (al/graph/taken_whole.hpp): refined is updated, the stats say how many.
TakenWholeStats KeepRegionsTakenWhole(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                                      const std::vector<float>& xyz, std::vector<bool>& refined) {
  const std::vector<bool>& removed = inputs.removal.removed;
  const std::vector<std::int64_t> restored = RestoredRows(removed, refined);
  const std::vector<std::uint8_t> active = ActiveRows(graph);
  // The graph's own view of the features (its centring and scene mean).
  const SceneFeatureMap map{inputs.features(), !inputs.colour_fallback, graph.stats.centred, graph.feature_mean};
  TakenWholeStats st;
  const std::vector<std::uint8_t> keep =
      FindTakenWhole({xyz, active, removed, map, graph.stats.gate_distance, go.k}, restored, &st);
  for (std::size_t t = 0; t < restored.size(); ++t)
    if (keep[t]) refined[std::size_t(restored[t])] = true;
  return st;
}

// Once per refinement, after the last round (restores do not drive growth): the restored
// Gaussians of regions the method took whole stay removed; the outcome's counts and message follow.
// Not when the removed set holds a second object (al/graph/removed_parts.hpp): a region taken
// whole may then be that object, and giving it back is right (a look-alike FGS grabbed,
// RefineAccuracy.ASplitLookAlikeIsNotCompleted).
void KeepRestoresTakenWhole(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                            ScenePositions& xyz, SolveOutcome& out) {
  if (out.empty_graph || out.restored == 0 || go.taken_whole_guard == PriorSwitch::kOff ||
      graph.stats.second_object.Found())
    return;
  const TakenWholeStats tw = KeepRegionsTakenWhole(inputs, graph, go, xyz.Get(), out.refined);
  out.decision["taken_whole"] = tw.ToJson();
  if (tw.kept == 0) return;
  out.restored -= tw.kept;
  out.decision["restored"] = out.restored;
  out.message += "; " + std::to_string(tw.kept) + " of those stay removed, in " +
                 (tw.regions == 1 ? "a feature region" : std::to_string(tw.regions) + " feature regions") +
                 " the method took whole (--taken-whole-guard): " + std::to_string(out.restored) + " restored";
}

// Once per refinement, after the taken-whole guard: restored Gaussians that look like the removed
// set (al/graph/restore_window.hpp) stay removed; the outcome's counts and message follow. Not
// when the removed set holds a second object: the object-like restores are then that object.
void KeepRestoresInWindow(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                          SolveOutcome& out) {
  if (out.empty_graph || out.restored == 0 || go.restore_window != PriorSwitch::kOn || inputs.colour_fallback ||
      graph.stats.second_object.Found())
    return;
  const std::vector<bool>& removed = inputs.removal.removed;
  const std::vector<std::int64_t> restored = RestoredRows(removed, out.refined);
  const std::vector<std::uint8_t> active = ActiveRows(graph);
  // Centred whatever the graph did: the window is about where a row sits in the removed set's
  // spread, which a shared component would compress (the scene mean is computed for fgs too).
  const bool centre = graph.feature_mean.size() > 0 && graph.feature_mean.norm() > 0;
  const SceneFeatureMap map{inputs.features(), true, centre, graph.feature_mean};
  RestoreWindowStats st;
  const std::vector<std::uint8_t> keep =
      InRestoreWindow(map, removed, active, restored, go.restore_window_mads, &st);
  out.decision["restore_window"] = st.ToJson();
  if (st.kept == 0) return;
  for (std::size_t t = 0; t < restored.size(); ++t)
    if (keep[t]) out.refined[std::size_t(restored[t])] = true;
  out.restored -= st.kept;
  out.decision["restored"] = out.restored;
  out.message += "; " + std::to_string(st.kept) + " of those stay removed, their features like the removed set's " +
                 "(--restore-window): " + std::to_string(out.restored) + " restored";
}

// Item 11's readings of the additions against two parts (al/graph/either_object.hpp): what the
// tolerance takes back leaves `refined` and the counts; the stats go to decision[key]. Returns
// the stats and how many were taken back.
std::pair<EitherObjectStats, std::size_t> TakeBackOneSided(const RefineInputs& inputs, const std::vector<float>& xyz,
                                                           const std::vector<std::int64_t>& part_a,
                                                           const std::vector<std::int64_t>& part_b, double tolerance,
                                                           const char* key, SolveOutcome& out) {
  EitherObjectStats st;
  const std::vector<std::int64_t> back =
      TrimOneSidedAdditions({xyz, inputs.removal.removed, part_a, part_b, tolerance}, out.refined, &st);
  out.decision[key] = st.ToJson();
  for (std::int64_t row : back) out.refined[std::size_t(row)] = false;
  out.added -= back.size();
  if (!back.empty()) out.decision["added"] = out.added;
  return {st, back.size()};
}

// Once per refinement, after the last round: when the removed set holds a second object, the
// additions completing one of the two stop where F1 against the other could fall by more than
// --second-object-tolerance; the outcome's counts and message follow.
void TrimOneSidedCompletion(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                            ScenePositions& xyz, SolveOutcome& out) {
  const SecondObject& so = graph.stats.second_object;
  if (out.empty_graph || out.added == 0 || !so.Found() || go.second_object_tolerance >= 1.0) return;
  const std::size_t back = TakeBackOneSided(inputs, xyz.Get(), so.largest_scene_rows, so.second_scene_rows,
                                            go.second_object_tolerance, "either_object", out).second;
  if (back == 0) return;
  out.message += "; " + std::to_string(back) + " of those taken back, farthest first: the removed set " +
                 "holds two objects, either may be the target, and the additions completed mostly one of them " +
                 "(--second-object-tolerance 1 keeps them): " + std::to_string(out.added) + " added";
}

// Whether item 13's bound applies (--feature-group-bound): always, never, or (auto) where the
// additions are a layer of a body that goes on beyond them (al/graph/continuing_body.hpp), which
// the decision reports. A tolerance of 1 takes nothing back, so then nothing is measured.
bool FeatureGroupBoundApplies(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                              const std::vector<float>& xyz, SolveOutcome& out) {
  if (go.feature_group_tolerance >= 1.0) return false;
  if (go.feature_group_bound != PriorSwitch::kAuto) return go.feature_group_bound == PriorSwitch::kOn;
  const std::vector<std::uint8_t> active = ActiveRows(graph);
  const SceneFeatureMap map{inputs.features(), !inputs.colour_fallback, graph.stats.centred, graph.feature_mean};
  const ContinuingBody body =
      MeasureContinuingBody({xyz, active, inputs.removal.removed, out.refined, map, go.k});
  out.decision["feature_groups_body"] = body.ToJson();
  return body.Continues();
}

// The same after an object group taken whole beside a group of other features taken in part
// (al/graph/removed_parts.hpp): the readings are reported always; additions are taken back as far
// as --feature-group-tolerance says where --feature-group-bound applies, and a completion left
// that the other reading would pay for beyond kEitherObjectTolerance gets a warning with the F1
// at stake (docs/refine.md items 13, 14).
void BoundFeatureGroupCompletion(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& go,
                                 ScenePositions& xyz, SolveOutcome& out) {
  const FeatureGroupParts& groups = graph.stats.whole_object_group;
  if (out.empty_graph || out.added == 0 || !groups.Found()) return;
  const bool bound = FeatureGroupBoundApplies(inputs, graph, go, xyz.Get(), out);
  const double tolerance = bound ? go.feature_group_tolerance : 1.0;
  const auto [st, back] =
      TakeBackOneSided(inputs, xyz.Get(), groups.object_rows, groups.other_rows, tolerance, "feature_groups", out);
  const std::string what = "the removed set holds an object taken whole and a group of other features taken in part, "
                           "and the additions completed mostly one of them";
  if (back > 0) {
    const char* why = go.feature_group_bound == PriorSwitch::kAuto ? ", a layer of a body that goes on beyond them" : "";
    out.message += "; " + std::to_string(back) + " of those taken back, farthest first: " + what + why +
                   " (--feature-group-bound off keeps them): " + std::to_string(out.added) + " added";
    return;
  }
  if (st.worst_before >= -kEitherObjectTolerance) return;
  char at_stake[16];
  std::snprintf(at_stake, sizeof at_stake, "%.4f", -st.worst_before);
  out.warnings.push_back(what + "; read with the other as the object, they lower F1 by about " + at_stake +
                         " (--feature-group-bound on bounds that)");
}

}  // namespace

void RunLastSteps(const RefineInputs& inputs, const GraphResult& graph, const GraphOptions& options,
                  SolveOutcome& out) {
  Timer timer;
  ScenePositions xyz(*inputs.scene);
  KeepRestoresTakenWhole(inputs, graph, options, xyz, out);
  KeepRestoresInWindow(inputs, graph, options, out);
  TrimOneSidedCompletion(inputs, graph, options, xyz, out);
  BoundFeatureGroupCompletion(inputs, graph, options, xyz, out);
  out.last_steps_seconds = timer.Seconds();
}

}  // namespace al
