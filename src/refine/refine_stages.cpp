// The refine stages (al/refine/stages.hpp): load, graph, solve + decide, ground-truth scores.
#include "al/refine/stages.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <utility>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/metrics/removal_scores.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/refine/fgs_mask.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

int TargetFromLabels(const std::string& labels, const std::optional<int>& object_id) {
  if (object_id) return *object_id;
  const fs::path target = fs::path(labels).parent_path() / "target.json";
  if (!fs::exists(target))
    throw Error(labels + ": no --object-id and no target.json beside the labels", ExitCode::kUsage);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ReadInputFile(target.string(), std::uint64_t(1) << 20));
    return j.at("object_id").get<int>();
  } catch (const Error&) {
    throw;  // not a regular file, too large
  } catch (const std::exception&) {
    throw Error(target.string() + ": expected {\"object_id\": k}", ExitCode::kBadInput);
  }
}

// Fills the features / feature_source / colour_fallback of inputs from the feature spec; `scene` is
// the freshly read scene, whose feature columns move into the inputs.
void LoadFeatures(const RefineOptions& o, Scene& scene, RefineInputs& in, nlohmann::json& report) {
  const std::string& feat = in.feature_spec;
  if (feat == "colour") {
    in.colour_fallback = true;
  } else if (EndsWith(feat, ".npy")) {
    in.SetFeatures(ReadMatrixNpy(feat));
    in.feature_source = feat;
    AddInputFile(report, "features", feat);
  } else if (EndsWith(feat, ".ply")) {
    PlyReadOptions fo;
    fo.require_scales = false;
    Scene fs_scene = ReadScene(feat, fo);
    if (fs_scene.features.cols() == 0) throw Error(feat + ": no feature columns found", ExitCode::kBadInput);
    in.SetFeatures(std::move(fs_scene.features));
    in.feature_source = feat + " (" + fs_scene.feature_prefix + "*)";
    AddInputFile(report, "features", feat);
  } else if (scene.features.cols() > 0) {
    in.SetFeatures(std::move(scene.features));
    scene.features.resize(0, 0);
    in.feature_source = scene.feature_prefix + "*";
  } else {
    in.colour_fallback = true;
    report["warnings"].push_back("no feature columns found (features '" + feat + "'): using the colour fallback");
  }
}

// What the feature rows need after they were found, for files and memory alike: the row count,
// the decoder, the colour fallback.
void FinishFeatures(const RefineOptions& o, RefineInputs& in) {
  const std::size_t N = in.scene->size();
  if (!in.colour_fallback && in.features().rows() != static_cast<Eigen::Index>(N))
    throw Error(in.feature_source + ": " + std::to_string(in.features().rows()) + " feature rows for " +
                std::to_string(N) + " Gaussians", ExitCode::kBadInput);
  if (!o.decoder.empty()) {
    if (in.colour_fallback) throw Error("--decoder needs semantic features", ExitCode::kUsage);
    const auto comma = o.decoder.find(',');
    if (comma == std::string::npos) throw Error("--decoder: expected W.npy,b.npy", ExitCode::kUsage);
    in.SetFeatures(ApplyDecoder(in.features(), o.decoder.substr(0, comma), o.decoder.substr(comma + 1)));
    in.feature_source += " decoded by " + o.decoder;
  }
  if (in.colour_fallback) {
    in.SetFeatures(ColourFeatures(*in.scene));
    in.feature_source = "colour (RGB = 0.5 + C0*f_dc, raw Euclidean distance)";
  }
}

// Says which features a preset chose when the user did not (sags and gg take what the scene has),
// so the source is never silent.
void NoteFeatureSource(const RefineOptions& o, const RefineInputs& in, nlohmann::json& report) {
  if (!in.colour_fallback && o.features.empty() && in.feature_spec != "semantic_")
    report["warnings"].push_back("--method " + o.method + ": features " + in.feature_source + ", " +
                                 std::to_string(in.features().cols()) + "-D");
}

// A removed set above half the scene is almost always a remaining set read the wrong way round.
void WarnIfMostOfTheScene(const RefineInputs& in, nlohmann::json& report) {
  const std::size_t n_scene = in.scene->size();
  if (2 * in.removal.num_removed > n_scene)
    report["warnings"].push_back(
        "the removed set holds " + std::to_string(in.removal.num_removed) + " of " + std::to_string(n_scene) +
        " Gaussians, more than half the scene (read as the " +
        (in.removed_is == RemovedIs::kRemaining ? "complement of the remaining rows" : "removed rows") +
        "): check --removed and --removed-is");
}

// auto = what the preset says.
void ResolvePriorSwitch(bool preset_value, PriorSwitch& value) {
  if (value == PriorSwitch::kAuto) value = preset_value ? PriorSwitch::kOn : PriorSwitch::kOff;
}

// auto = the preset's restore.
DecisionOptions ResolveRestore(const MethodPreset& preset, DecisionOptions decision) {
  if (decision.restore == Restore::kAuto) decision.restore = preset.restore ? Restore::kOn : Restore::kOff;
  return decision;
}

// The graph options with the feature kind and the preset's autos resolved.
GraphOptions GraphOptionsFor(const RefineInputs& inputs, GraphOptions go) {
  go.normalize_features = !inputs.colour_fallback;
  ResolvePriorSwitch(inputs.preset.prototype_credit, go.prior.prototype_credit);
  ResolvePriorSwitch(inputs.preset.wide_credit, go.prior.wide_credit);
  if (go.centre == Centring::kAuto) go.centre = inputs.preset.centre;
  if (!go.prior.weight) go.prior.weight = inputs.preset.prior_weight;
  if (!go.feature_width) go.feature_width = inputs.preset.feature_width;
  return go;
}

GraphResult BuildGraphGrown(const RefineInputs& inputs, const GraphOptions& options,
                            const std::vector<std::uint8_t>* extra_seeds) {
  return BuildRefineGraph(*inputs.scene, inputs.features(), inputs.removal.removed, GraphOptionsFor(inputs, options),
                          extra_seeds);
}

// A later growth round: only what the new seeds add is searched and compared (GrowRefineGraph).
GraphResult GrowGraph(const RefineInputs& inputs, const GraphOptions& options, GraphResult previous,
                      const std::vector<std::uint8_t>& grown, const std::vector<std::int64_t>* new_rows) {
  return GrowRefineGraph(*inputs.scene, inputs.features(), inputs.removal.removed, GraphOptionsFor(inputs, options),
                         std::move(previous), grown, new_rows);
}

nlohmann::json RefinementChangeJson(const GroundTruth& truth, const std::vector<bool>& before,
                                    const std::vector<bool>& after) {
  std::size_t added = 0, added_object = 0, misses = 0, restored = 0, restored_background = 0, over = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const bool object = truth.labels[i] == truth.target;
    misses += object && !before[i];
    over += !object && before[i];
    if (after[i] && !before[i]) ++added, added_object += object;
    if (before[i] && !after[i]) ++restored, restored_background += !object;
  }
  auto ratio = [](std::size_t a, std::size_t b) { return b ? nlohmann::json(double(a) / double(b)) : nlohmann::json(nullptr); };
  return {{"added", added}, {"added_object", added_object}, {"precision_added", ratio(added_object, added)},
          {"misses", misses}, {"misses_recovered", ratio(added_object, misses)},
          {"restored", restored}, {"restored_background", restored_background},
          {"precision_restored", ratio(restored_background, restored)},
          {"over_removed", over}, {"over_removed_restored", ratio(restored_background, over)}};
}

// The previous round's solution on the grown graph's nodes (both lists ascending scene rows, the
// old one a subset): each old node keeps its component and value, a new node has none.
// A saturated component stays saturated only where no observation moved by more than this (the
// prior is re-fitted on the grown candidate set, so every y moves a little): cp's own merge and
// stopping tolerance.
constexpr double kWarmSaturationTolerance = 1e-3;

// The previous round's solution on the grown graph's nodes (both node lists ascending scene rows,
// the old one a subset): each old node keeps its component and value, a new node has none.
SolverWarmStart WarmStartFor(const RefineProblem& old_problem, const SolveOutcome& before, const RefineProblem& grown) {
  SolverWarmStart w;
  const std::vector<std::int64_t>&old_ids = old_problem.node_ids, &new_ids = grown.node_ids;
  if (before.partition.size() != old_ids.size() || before.p.size() != old_ids.size()) return w;
  w.component.assign(new_ids.size(), -1);
  std::int32_t components = 0;
  for (std::int32_t c : before.partition) components = std::max(components, c + 1);
  w.value.assign(std::size_t(components), 0.0);
  w.saturated = before.saturated;
  if (w.saturated.size() != w.value.size()) w.saturated.assign(w.value.size(), 0);
  for (std::size_t v = 0, o = 0; v < new_ids.size() && o < old_ids.size(); ++v) {
    if (new_ids[v] != old_ids[o]) continue;
    const std::size_t c = std::size_t(before.partition[o]);
    w.component[v] = before.partition[o];
    w.value[c] = before.p[o];
    if (std::abs(grown.y_remove[v] - old_problem.y_remove[o]) > kWarmSaturationTolerance) w.saturated[c] = 0;
    ++o;
  }
  return w;
}

// In-memory features: the caller's (N, D) float array (float32 borrowed, other float types
// converted), else the scene's own columns, else the colour fallback.
void FeaturesFromData(const RefineData& data, RefineInputs& in, nlohmann::json& report) {
  const NpyArray& f = data.features;
  if (f.data != nullptr) {
    if (!f.is_float() || f.shape.size() != 2 || f.shape[1] <= 0)
      throw Error(data.name + " features: expected a 2-D (N, D) float array, got dtype " + f.descr + " with " +
                  std::to_string(f.shape.size()) + " dimensions", ExitCode::kBadInput);
    if (f.descr == "f4") {
      in.BorrowFeatures(reinterpret_cast<const float*>(f.data), f.shape[0], f.shape[1]);
    } else {
      const std::vector<float> v = f.ToFloat();
      in.SetFeatures(Eigen::Map<const RowMatXf>(v.data(), f.shape[0], f.shape[1]));
    }
    in.feature_source = data.name + " features (" + f.descr + ")";
  } else if (in.feature_spec != "colour" && in.scene->features.cols() > 0) {
    const Scene& s = *in.scene;
    in.BorrowFeatures(s.features.data(), s.features.rows(), s.features.cols());
    in.feature_source = s.feature_prefix + "*";
  } else {
    in.colour_fallback = true;
    if (in.feature_spec != "colour")
      report["warnings"].push_back("no features given and none in the scene: using the colour fallback");
  }
}

// A target that no Gaussian carries would score every run 0 -> 0 in silence: refused instead.
void CheckTargetPresent(const std::vector<std::int32_t>& labels, int target) {
  if (std::find(labels.begin(), labels.end(), target) != labels.end()) return;
  std::set<std::int32_t> ids(labels.begin(), labels.end());
  std::string present;
  for (auto it = ids.begin(); it != ids.end() && present.size() < 60; ++it)
    present += (present.empty() ? "" : ", ") + std::to_string(*it);
  throw Error("labels: object id " + std::to_string(target) + " is not among the labels (ids present: " +
                  (present.empty() ? "none" : present) + (ids.size() > 12 ? ", ..." : "") + ")",
              ExitCode::kBadInput);
}

GroundTruth MakeGroundTruth(std::vector<std::int32_t> labels, int target, const Scene& scene) {
  CheckTargetPresent(labels, target);
  const std::size_t N = scene.size();
  GroundTruth truth;
  truth.labels = std::move(labels);
  truth.target = target;
  if (scene.opacity_logits.size() == static_cast<Eigen::Index>(N))
    truth.opacity_logits.assign(scene.opacity_logits.data(), scene.opacity_logits.data() + N);
  return truth;
}

GroundTruth LoadGroundTruth(const RefineOptions& o, const Scene& scene, nlohmann::json& report) {
  const std::size_t N = scene.size();
  const NpyArray la = ReadNpy(o.labels);
  if (!la.is_integer() || la.size() != N)
    throw Error(o.labels + ": expected an integer array with " + std::to_string(N) + " entries",
                ExitCode::kBadInput);
  AddInputFile(report, "labels", o.labels);
  const std::vector<std::int64_t> l64 = la.ToInt64();
  return MakeGroundTruth({l64.begin(), l64.end()}, TargetFromLabels(o.labels, o.object_id), scene);
}

// The FGS deletion rule on the inputs' features (method fgs with prompt embeddings).
void DeriveFgsRemoval(const RefineOptions& o, RefineInputs& in, nlohmann::json& report) {
  const RowMatXf prompts = ReadMatrixNpy(o.prompt_embeddings);
  AddInputFile(report, "prompt_embeddings", o.prompt_embeddings);
  if (in.colour_fallback) throw Error("--prompt-embeddings needs semantic features", ExitCode::kUsage);
  FgsMaskOptions fo;
  fo.positives = o.positives;
  fo.threshold = o.fgs_threshold;
  const FgsMaskResult m = FgsDerivedMask(in.features(), prompts, fo);
  in.removal.removed = m.removed;
  in.removal.num_removed = m.num_removed;
  in.fgs_mask = {{"removed", m.num_removed}, {"by_argmax", m.by_argmax},
                 {"by_threshold_only", m.by_threshold_only}, {"near_threshold", m.near_threshold},
                 {"zero_norm", m.zero_norm}, {"threshold", o.fgs_threshold}, {"positives", o.positives}};
  if (m.near_threshold > 0)
    report["warnings"].push_back(std::to_string(m.near_threshold) +
                                 " Gaussians lie within 1e-3 of the FGS threshold (upstream float16 may flip them)");
}

RemovalLoadOptions RemovalOptionsFor(const RefineOptions& o, const RefineInputs& in, const MethodPreset& preset) {
  RemovalLoadOptions lo;
  lo.removed_is = in.removed_is;
  lo.max_unmatched = o.max_unmatched;
  lo.match_tolerance = o.match_tol;
  lo.gc_polarity = preset.gc_polarity;
  return lo;
}

// Calls the optional stage callback and records the stage's seconds under report.timings_s.
struct StageClock {
  const RefineOptions& o;
  nlohmann::json& report;
  Timer t;
  void Done(const std::string& name) {
    const double s = t.Seconds();
    report["timings_s"][name] = s;
    if (o.on_stage) o.on_stage(name, s);
    t.Reset();
  }
};

nlohmann::json ScoresToJson(const RemovalScores& s) {
  return {{"precision", s.precision}, {"recall", s.recall}, {"f1", s.f1}, {"iou", s.iou},
          {"precision_w", s.precision_w}, {"recall_w", s.recall_w}, {"f1_w", s.f1_w},
          {"iou_w", s.iou_w}, {"removed", s.removed}, {"target", s.target}};
}

// λ auto = the preset's for this solver.
GraphOptions WithLambdaFor(const RefineInputs& inputs, GraphOptions options, const Solver& solver) {
  if (!options.lambda) options.lambda = inputs.preset.LambdaFor(solver.name());
  return options;
}

}  // namespace

Eigen::Map<const RowMatXf> RefineInputs::features() const {
  if (borrowed_ != nullptr) return {borrowed_, borrowed_rows_, borrowed_dim_};
  return {owned_features_.data(), owned_features_.rows(), owned_features_.cols()};
}

void RefineInputs::SetFeatures(RowMatXf rows) {
  owned_features_ = std::move(rows);
  borrowed_ = nullptr;
}

void RefineInputs::BorrowFeatures(const float* rows, Eigen::Index count, Eigen::Index dim) {
  owned_features_.resize(0, 0);
  borrowed_ = rows;
  borrowed_rows_ = count;
  borrowed_dim_ = dim;
}

std::string ResolveSolverName(const std::string& name) {
  if (!name.empty()) return name;
  const auto names = SolverNames();
  return std::find(names.begin(), names.end(), "cp") != names.end() ? "cp" : "bk";
}

RefineInputs LoadRefineInputs(const RefineOptions& o, nlohmann::json& report, SceneColumns columns) {
  if (o.scene.empty()) throw Error("--scene is required", ExitCode::kUsage);
  const MethodPreset preset = MethodPresetFor(o.method);
  const bool derive_fgs = o.removed.empty() && !o.prompt_embeddings.empty();
  if (o.removed.empty() && !derive_fgs)
    throw Error("--removed is required (or, with --method fgs, --prompt-embeddings and --positive)",
                ExitCode::kUsage);
  if (derive_fgs && o.method != "fgs") throw Error("--prompt-embeddings needs --method fgs", ExitCode::kUsage);
  StageClock clock{o, report, {}};

  RefineInputs in;
  in.preset = preset;
  in.feature_spec = o.features.empty() ? preset.features : o.features;
  const bool feat_file = EndsWith(in.feature_spec, ".npy") || EndsWith(in.feature_spec, ".ply");
  PlyReadOptions ro;
  ro.feature_prefix = (in.feature_spec == "colour" || feat_file) ? "none" : in.feature_spec;
  ro.sh_rest = columns == SceneColumns::kAll;
  ro.rotations = columns == SceneColumns::kAll || EndsWith(o.removed, ".ply");  // subset matching compares them
  ro.f_dc = ro.rotations || ro.feature_prefix == "none";  // else the scene's features serve, never colour
  Scene scene = ReadScene(o.scene, ro);
  AddInputFile(report, "scene", o.scene);
  LoadFeatures(o, scene, in, report);
  in.scene = std::make_shared<const Scene>(std::move(scene));
  FinishFeatures(o, in);
  NoteFeatureSource(o, in, report);
  clock.Done("load_scene");

  in.removed_is = o.removed_is.value_or(EndsWith(o.removed, ".ply") ? preset.subset_ply_is : RemovedIs::kRemoved);
  if (derive_fgs) {
    DeriveFgsRemoval(o, in, report);
  } else {
    in.removal = LoadRemovalSet(o.removed, *in.scene, RemovalOptionsFor(o, in, preset));
    AddInputFile(report, "removed", o.removed);
    for (const auto& w : in.removal.warnings) report["warnings"].push_back(w);
  }
  WarnIfMostOfTheScene(in, report);
  clock.Done("load_removed");

  if (!o.labels.empty()) {
    in.ground_truth = LoadGroundTruth(o, *in.scene, report);
    clock.Done("load_labels");
  }
  return in;
}

RefineInputs InputsFromData(const RefineData& data, const RefineOptions& o, nlohmann::json& report) {
  if (!data.scene) throw Error("refine: no scene given", ExitCode::kUsage);
  const MethodPreset preset = MethodPresetFor(o.method);
  const bool derive_fgs = data.removed.data == nullptr && !o.prompt_embeddings.empty();
  if (data.removed.data == nullptr && !derive_fgs)
    throw Error("refine: a removed set is required (or, with method fgs, prompt_embeddings and positive)",
                ExitCode::kUsage);
  if (derive_fgs && o.method != "fgs") throw Error("prompt_embeddings needs method fgs", ExitCode::kUsage);
  if (!data.labels.empty() && !data.object_id) throw Error("refine: labels need an object id", ExitCode::kUsage);
  StageClock clock{o, report, {}};

  RefineInputs in;
  in.scene = data.scene;
  in.preset = preset;
  in.feature_spec = o.features.empty() ? preset.features : o.features;
  FeaturesFromData(data, in, report);
  FinishFeatures(o, in);
  NoteFeatureSource(o, in, report);
  clock.Done("load_scene");

  in.removed_is = o.removed_is.value_or(RemovedIs::kRemoved);  // an array is never a subset PLY
  if (derive_fgs) {
    DeriveFgsRemoval(o, in, report);
  } else {
    in.removal = RemovalSetFromArray(data.removed, data.name + " removed set", in.scene->size(),
                                     RemovalOptionsFor(o, in, preset));
    for (const auto& w : in.removal.warnings) report["warnings"].push_back(w);
  }
  WarnIfMostOfTheScene(in, report);
  clock.Done("load_removed");

  if (!data.labels.empty()) {
    if (data.labels.size() != in.scene->size())
      throw Error(data.name + " labels: " + std::to_string(data.labels.size()) + " entries for " +
                  std::to_string(in.scene->size()) + " Gaussians", ExitCode::kBadInput);
    in.ground_truth = MakeGroundTruth(data.labels, *data.object_id, *in.scene);
    clock.Done("load_labels");
  }
  return in;
}

GraphResult BuildGraphFor(const RefineInputs& inputs, const GraphOptions& options) {
  return BuildGraphGrown(inputs, options, nullptr);
}

GrownSolve BuildAndSolve(const RefineInputs& inputs, const GraphOptions& graph_options, Solver& solver,
                         const DecisionOptions& decision) {
  if (graph_options.grow_rounds < 0) throw Error("--grow-rounds must be >= 0", ExitCode::kUsage);
  const GraphOptions options = WithLambdaFor(inputs, graph_options, solver);
  Timer t;
  GraphResult first = BuildGraphGrown(inputs, options, nullptr);
  const double first_seconds = t.Seconds();
  GrownSolve r = SolveAndGrow(inputs, options, solver, decision, std::move(first));
  r.graph_seconds += first_seconds;
  return r;
}

namespace {

// Whether another round pays, with `grown` extended by what this round added when it does. A
// trickle at the border is not worth another graph: grow only while the round added at least
// 0.5 % of the removed count, and while growing from those brings at least as many new candidates
// into the graph (the most the next round can add; on the 3M room scene round 1 added 3,127 but
// they brought 106 new candidates: a second graph and solve cost 2 s and moved F1 by 0.0002).
// `rows` gets the new candidates when they were searched (for GrowGraph, not to search them again).
bool GrowFurther(const RefineInputs& inputs, GrownSolve& r, std::vector<std::uint8_t>& grown,
                 std::optional<std::vector<std::int64_t>>& rows) {
  const std::vector<bool>& removed = inputs.removal.removed;
  const std::size_t bar = inputs.removal.num_removed;  // counts below bar / 200 are a trickle
  std::vector<std::uint8_t> next = grown;
  std::size_t fresh = 0;  // added now, not yet grown around
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (r.outcome.refined[i] && !removed[i] && !grown[i]) next[i] = 1, ++fresh;
  r.growth_stop = "trickle";
  if (fresh == 0 || fresh * 200 < bar) return false;
  rows = NewCandidateRows(r.graph, next);
  r.growth_stop = "few new candidates";
  if (rows && (rows->empty() || rows->size() * 200 < bar)) return false;
  grown = std::move(next);
  return true;
}

}  // namespace

GrownSolve SolveAndGrow(const RefineInputs& inputs, const GraphOptions& graph_options, Solver& solver,
                        const DecisionOptions& decision, GraphResult first) {
  if (graph_options.grow_rounds < 0) throw Error("--grow-rounds must be >= 0", ExitCode::kUsage);
  const GraphOptions options = WithLambdaFor(inputs, graph_options, solver);
  const std::vector<bool>& removed = inputs.removal.removed;
  std::vector<std::uint8_t> grown(removed.size(), 0);  // everything added so far
  std::optional<std::vector<std::int64_t>> new_rows;   // what growing from it brings in (GrowFurther)
  GrownSolve r;
  r.graph = std::move(first);
  for (int round = 0;; ++round) {
    std::optional<SolverWarmStart> warm;
    if (round) {
      Timer t;
      RefineProblem old_nodes;  // what the warm start needs of the last graph
      old_nodes.node_ids = r.graph.problem.node_ids;
      old_nodes.y_remove = r.graph.problem.y_remove;
      r.graph = GrowGraph(inputs, options, std::move(r.graph), grown, new_rows ? &*new_rows : nullptr);
      warm = WarmStartFor(old_nodes, r.outcome, r.graph.problem);
      r.graph_seconds += t.Seconds();
    }
    r.rounds = round + 1;
    r.outcome = SolveAndDecide(inputs, r.graph, options, solver, decision, warm ? &*warm : nullptr);
    if (!r.outcome.empty_graph) r.solve_seconds += r.outcome.solver.value("seconds", 0.0);
    if (r.outcome.empty_graph || options.grow_rounds == 0) {
      r.growth_stop = r.outcome.empty_graph ? "empty graph" : "fixed";
      break;
    }
    if (!GrowFurther(inputs, r, grown, new_rows)) break;
    if (round >= options.grow_rounds) {
      r.capped = true;
      r.growth_stop = "capped";
      break;
    }
  }
  if (r.capped)
    r.outcome.warnings.push_back("candidate growth stopped after " + std::to_string(r.rounds) +
                                 " rounds while the cut was still adding (--grow-rounds)");
  RunLastSteps(inputs, r.graph, options, r.outcome);
  return r;
}

SolveOutcome SolveAndDecide(const RefineInputs& inputs, const GraphResult& graph,
                            const GraphOptions& go, Solver& solver, const DecisionOptions& decision,
                            const SolverWarmStart* warm) {
  SolveOutcome out;
  const GraphStats& gs = graph.stats;
  const std::size_t num_removed = inputs.removal.num_removed;
  if (gs.edges == 0) {
    out.empty_graph = true;
    out.refined = inputs.removal.removed;
    out.message =
        "empty graph: no edge survived the semantic gate (removed " + std::to_string(num_removed) +
        ", candidates " + std::to_string(gs.nodes) + ", kNN edges " + std::to_string(gs.edges_knn) +
        ", k = " + std::to_string(go.k) + ", delta = " + nlohmann::json(go.delta).dump() +
        (go.delta_mode == DeltaMode::kCosine ? " (cosine)" : "") + ", zero-norm features " +
        std::to_string(gs.zero_norm_features) + "). " +
        (num_removed == 0 ? "The removed set is empty: check --removed / --removed-is. "
                          : "Try a larger --delta (e.g. 1.0 or 1.2), a larger --k, --hops 2 or "
                            "--radius-scale 2; check that --features match the scene. ") +
        "The output mask equals the input mask.";
    out.warnings.push_back(out.message);
    out.solver = {{"name", solver.name()}, {"skipped", true}};
    out.decision = {{"rule", decision.rule.ToString()}, {"skipped", true}};
    return out;
  }
  SolverResult sr = warm && !warm->component.empty() ? solver.SolveFrom(graph.problem, *warm)
                                                     : solver.Solve(graph.problem);
  out.partition = std::move(sr.partition);
  out.saturated = std::move(sr.saturated);
  out.warnings = sr.warnings;
  out.solver = sr.ToJson();
  const DecisionOptions resolved = ResolveRestore(inputs.preset, decision);
  const DecisionResult d = ApplyDecision(inputs.removal.removed, graph.problem, sr.p, resolved);
  out.refined = d.refined;
  out.added = d.added;
  out.restored = d.restored;
  out.p = std::move(sr.p);
  out.decision = d.ToJson();
  out.decision["rule"] = decision.rule.ToString();
  out.decision["restore"] = resolved.Restores();
  out.message = "refined (features " + inputs.feature_source + "): " + std::to_string(d.added) + " Gaussians added" +
                (resolved.Restores() ? ", " + std::to_string(d.restored) + " restored" : "") +
                // The segment rule departs from the plain threshold, so say when it acted.
                (d.held_back > 0 ? ", " + std::to_string(d.held_back) + " held back in " +
                                       std::to_string(d.segments_held_back) +
                                       (d.segments_held_back == 1 ? " segment" : " segments") + " the method mostly kept (--min-segment-share)"
                                 : "") +
                " (rule " + decision.rule.ToString() + ", threshold " + nlohmann::json(d.threshold).dump() + ")";
  return out;
}

nlohmann::json ScoreAgainstGroundTruth(const GroundTruth& truth, const std::vector<bool>& before,
                                       const std::vector<bool>& after) {
  return {{"object_id", truth.target},
          {"change", RefinementChangeJson(truth, before, after)},
          {"before", ScoresToJson(ScoreRemoval(before, truth.labels, truth.target,
                                                         truth.opacity_logits))},
          {"after", ScoresToJson(ScoreRemoval(after, truth.labels, truth.target,
                                                        truth.opacity_logits))}};
}

}  // namespace al
