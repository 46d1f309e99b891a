// RunRefine: the whole `refine` flow as a library call (see al/refine/refine.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/fixtures/synth.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/refine/fgs_mask.hpp"
#include "al/refine/refine.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

// What a --method preset sets (SPEC §3 table); reported under params.preset.
struct Preset {
  std::string features;  // "semantic_", "obj_dc_", "auto" or "colour"
  RemovedIs removed_is = RemovedIs::kRemoved;
  bool gc_polarity = false;
};

Preset PresetFor(const std::string& method) {
  if (method == "fgs") return {"semantic_", RemovedIs::kRemoved, false};
  if (method == "gg") return {"obj_dc_", RemovedIs::kRemaining, false};
  if (method == "sags") return {"colour", RemovedIs::kRemoved, false};
  if (method == "gc") return {"colour", RemovedIs::kRemoved, true};
  if (method == "generic") return {"auto", RemovedIs::kRemoved, false};
  throw Error("--method: unknown '" + method + "' (fgs, gg, sags, gc, generic)", ExitCode::kUsage);
}

int TargetFromLabels(const std::string& labels, const std::optional<int>& object_id) {
  if (object_id) return *object_id;
  const fs::path target = fs::path(labels).parent_path() / "target.json";
  std::ifstream in(target);
  if (!in)
    throw Error(labels + ": no --object-id and no target.json beside the labels", ExitCode::kUsage);
  nlohmann::json j;
  try {
    in >> j;
    return j.at("object_id").get<int>();
  } catch (const std::exception& e) {
    throw Error(target.string() + ": expected {\"object_id\": k}", ExitCode::kBadInput);
  }
}

}  // namespace

RefineResult RunRefine(const RefineOptions& o) {
  Timer total;
  auto stage_done = [&](const std::string& name, Timer& t, nlohmann::json& timings) {
    const double s = t.Seconds();
    timings[name] = s;
    if (o.on_stage) o.on_stage(name, s);
    t.Reset();
  };
  if (o.scene.empty()) throw Error("--scene is required", ExitCode::kUsage);
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  const Preset preset = PresetFor(o.method);
  const bool derive_fgs = o.removed.empty() && !o.prompt_embeddings.empty();
  if (o.removed.empty() && !derive_fgs)
    throw Error("--removed is required (or, with --method fgs, --prompt-embeddings and --positive)",
                ExitCode::kUsage);
  if (derive_fgs && o.method != "fgs")
    throw Error("--prompt-embeddings needs --method fgs", ExitCode::kUsage);
  std::string solver_name = o.solver;
  if (solver_name.empty()) {
    const auto names = SolverNames();
    solver_name = std::find(names.begin(), names.end(), "cp") != names.end() ? "cp" : "bk";
  }
  auto solver = MakeSolver(solver_name, o.solver_options);  // fails early on a bad name/options

  nlohmann::json report = NewReport("refine");
  nlohmann::json& timings = report["timings_s"];
  nlohmann::json& warnings = report["warnings"];
  Timer t;

  // Features source: explicit, else the preset's.
  const std::string feat = o.features.empty() ? preset.features : o.features;
  const bool feat_file = EndsWith(feat, ".npy") || EndsWith(feat, ".ply");
  PlyReadOptions ro;
  ro.feature_prefix = (feat == "colour" || feat_file) ? "none" : feat;
  Scene scene = ReadScene(o.scene, ro);
  const std::size_t N = scene.size();
  AddInputFile(report, "scene", o.scene);
  std::string feature_source;
  RowMatXf features;
  bool colour = false;
  if (feat == "colour") {
    colour = true;
  } else if (EndsWith(feat, ".npy")) {
    features = ReadMatrixNpy(feat);
    feature_source = feat;
    AddInputFile(report, "features", feat);
  } else if (EndsWith(feat, ".ply")) {
    PlyReadOptions fo;
    fo.require_scales = false;
    Scene fs_scene = ReadScene(feat, fo);
    if (fs_scene.features.cols() == 0) throw Error(feat + ": no feature columns found", ExitCode::kBadInput);
    features = std::move(fs_scene.features);
    feature_source = feat + " (" + fs_scene.feature_prefix + "*)";
    AddInputFile(report, "features", feat);
  } else if (scene.features.cols() > 0) {
    features = std::move(scene.features);
    feature_source = scene.feature_prefix + "*";
  } else {
    colour = true;
    warnings.push_back("no feature columns found (features '" + feat + "'): using the colour fallback");
  }
  if (!colour && features.rows() != static_cast<Eigen::Index>(N))
    throw Error(feature_source + ": " + std::to_string(features.rows()) + " feature rows for " +
                std::to_string(N) + " Gaussians", ExitCode::kBadInput);
  if (!o.decoder.empty()) {
    if (colour) throw Error("--decoder needs semantic features", ExitCode::kUsage);
    const auto comma = o.decoder.find(',');
    if (comma == std::string::npos) throw Error("--decoder: expected W.npy,b.npy", ExitCode::kUsage);
    features = ApplyDecoder(features, o.decoder.substr(0, comma), o.decoder.substr(comma + 1));
    feature_source += " decoded by " + o.decoder;
  }
  if (colour) {
    features = ColourFeatures(scene);
    feature_source = "colour (RGB = 0.5 + C0*f_dc, raw Euclidean distance)";
  }
  stage_done("load_scene", t, timings);

  // Removed set.
  RemovalSet removal;
  nlohmann::json fgs_json;
  const RemovedIs removed_is = o.removed_is.value_or(preset.removed_is);
  if (derive_fgs) {
    const RowMatXf prompts = ReadMatrixNpy(o.prompt_embeddings);
    AddInputFile(report, "prompt_embeddings", o.prompt_embeddings);
    if (colour) throw Error("--prompt-embeddings needs semantic features", ExitCode::kUsage);
    FgsMaskOptions fo;
    fo.positives = o.positives;
    fo.threshold = o.fgs_threshold;
    const FgsMaskResult m = FgsDerivedMask(features, prompts, fo);
    removal.removed = m.removed;
    removal.num_removed = m.num_removed;
    fgs_json = {{"removed", m.num_removed}, {"by_argmax", m.by_argmax},
                {"by_threshold_only", m.by_threshold_only}, {"near_threshold", m.near_threshold},
                {"zero_norm", m.zero_norm}, {"threshold", o.fgs_threshold}, {"positives", o.positives}};
    if (m.near_threshold > 0)
      warnings.push_back(std::to_string(m.near_threshold) +
                         " Gaussians lie within 1e-3 of the FGS threshold (upstream float16 may flip them)");
  } else {
    RemovalLoadOptions lo;
    lo.removed_is = removed_is;
    lo.max_unmatched = o.max_unmatched;
    lo.match_tolerance = o.match_tol;
    lo.gc_polarity = preset.gc_polarity;
    removal = LoadRemovalSet(o.removed, scene, lo);
    AddInputFile(report, "removed", o.removed);
    for (const auto& w : removal.warnings) warnings.push_back(w);
  }
  stage_done("load_removed", t, timings);

  // Graph.
  GraphOptions go = o.graph;
  go.normalize_features = !colour;
  GraphResult graph = BuildRefineGraph(scene, features, removal.removed, go);
  for (const auto& w : graph.warnings) warnings.push_back(w);
  stage_done("graph", t, timings);

  RefineResult result;
  result.removed = removal.removed;
  const GraphStats& gs = graph.stats;
  nlohmann::json decision_json, solver_json;
  if (gs.edges == 0) {
    result.status = "empty_graph";
    result.exit_code = static_cast<int>(ExitCode::kEmptyGraph);
    result.refined = removal.removed;
    result.message =
        "empty graph: no edge survived the semantic gate (removed " + std::to_string(removal.num_removed) +
        ", candidates " + std::to_string(gs.nodes) + ", kNN edges " + std::to_string(gs.edges_knn) +
        ", k = " + std::to_string(go.k) + ", delta = " + nlohmann::json(go.delta).dump() +
        (go.delta_mode == DeltaMode::kCosine ? " (cosine)" : "") + ", zero-norm features " +
        std::to_string(gs.zero_norm_features) + "). " +
        (removal.num_removed == 0 ? "The removed set is empty: check --removed / --removed-is. "
                                  : "Try a larger --delta (e.g. 1.0 or 1.2), a larger --k, --hops 2 or "
                                    "--radius-scale 2; check that --features match the scene. ") +
        "The output mask equals the input mask.";
    warnings.push_back(result.message);
  } else {
    const SolverResult sr = solver->Solve(graph.problem);
    for (const auto& w : sr.warnings) warnings.push_back(w);
    solver_json = {{"name", sr.solver}, {"objective", sr.objective}, {"iterations", sr.iterations},
                   {"converged", sr.converged}, {"seconds", sr.seconds}, {"stats", sr.stats}};
    stage_done("solve", t, timings);
    const DecisionResult d = ApplyDecision(removal.removed, graph.problem, sr.p, o.decision);
    result.refined = d.refined;
    decision_json = d.ToJson();
    decision_json["rule"] = o.decision.rule.ToString();
    decision_json["restore"] = o.decision.restore;
    result.message = "refined: " + std::to_string(d.added) + " Gaussians added" +
                     (o.decision.restore ? ", " + std::to_string(d.restored) + " restored" : "") +
                     " (rule " + o.decision.rule.ToString() + ", threshold " +
                     nlohmann::json(d.threshold).dump() + ")";
  }
  stage_done("decide", t, timings);

  // Ground truth.
  if (!o.labels.empty()) {
    const NpyArray la = ReadNpy(o.labels);
    if (!la.is_integer() || la.size() != N)
      throw Error(o.labels + ": expected an integer array with " + std::to_string(N) + " entries",
                  ExitCode::kBadInput);
    AddInputFile(report, "labels", o.labels);
    const std::vector<std::int64_t> l64 = la.ToInt64();
    const std::vector<std::int32_t> labels(l64.begin(), l64.end());
    const int target = TargetFromLabels(o.labels, o.object_id);
    std::vector<float> opacity;
    if (scene.opacity_logits.size() == static_cast<Eigen::Index>(N))
      opacity.assign(scene.opacity_logits.data(), scene.opacity_logits.data() + N);
    auto pick = [](const fixtures::RemovalScores& s) {
      return nlohmann::json{{"precision", s.precision}, {"recall", s.recall}, {"f1", s.f1},
                            {"iou", s.iou}, {"precision_w", s.precision_w}, {"recall_w", s.recall_w},
                            {"f1_w", s.f1_w}, {"iou_w", s.iou_w}, {"removed", s.removed},
                            {"target", s.target}};
    };
    report["gt"] = {{"object_id", target},
                    {"before", pick(fixtures::ScoreRemoval(removal.removed, labels, target, opacity))},
                    {"after", pick(fixtures::ScoreRemoval(result.refined, labels, target, opacity))}};
    stage_done("ground_truth", t, timings);
  }

  // Outputs (each written atomically).
  fs::create_directories(o.out_dir);
  const fs::path out(o.out_dir);
  WriteNpyBool((out / "refined.npy").string(), result.refined);
  WriteIndexText((out / "refined.txt").string(), MaskToIndices(result.refined), "refined removed set");
  std::vector<bool> added(N, false), keep(N);
  std::size_t n_added = 0, n_restored = 0, n_refined = 0;
  for (std::size_t i = 0; i < N; ++i) {
    added[i] = result.refined[i] && !removal.removed[i];
    n_added += added[i];
    n_restored += removal.removed[i] && !result.refined[i];
    n_refined += result.refined[i];
    keep[i] = !result.refined[i];
  }
  WriteIndexText((out / "added.txt").string(), MaskToIndices(added), "Gaussians added by refinement");
  WritePly((out / "remaining.ply").string(), scene, keep);
  stage_done("write", t, timings);

  report["status"] = result.status;
  nlohmann::json preset_json = {{"features", preset.features},
                                {"removed_is", preset.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
                                {"gc_polarity", preset.gc_polarity}};
  report["params"] = {
      {"scene", o.scene}, {"removed", o.removed},
      {"removed_is", removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
      {"method", o.method}, {"preset", preset_json}, {"features", feat},
      {"feature_source", feature_source}, {"colour_fallback", colour}, {"decoder", o.decoder},
      {"k", go.k}, {"delta", go.delta},
      {"delta_mode", go.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
      {"lambda", go.lambda}, {"spatial", go.spatial}, {"hops", go.hops},
      {"radius_scale", go.radius_scale}, {"knn_checks", go.knn_checks},
      {"kl_smoothing", go.kl_smoothing}, {"solver", solver_name}, {"solver_options", o.solver_options},
      {"threshold", o.decision.rule.ToString()}, {"restore", o.decision.restore},
      {"labels", o.labels}, {"max_unmatched", o.max_unmatched}, {"match_tol", o.match_tol},
      {"prompt_embeddings", o.prompt_embeddings}, {"positive", o.positives},
      {"fgs_threshold", o.fgs_threshold}, {"out", o.out_dir}};
  report["counts"] = {{"num_gaussians", N}, {"removed_input", removal.num_removed},
                      {"candidates", gs.nodes}, {"edges", gs.edges}, {"refined", n_refined},
                      {"added", n_added}, {"restored", n_restored},
                      {"excluded_nonfinite", gs.excluded_nonfinite}};
  report["removed_set"] = removal.stats;
  if (!fgs_json.is_null()) report["fgs_mask"] = fgs_json;
  report["graph"] = GraphStatsToJson(gs);
  report["solver"] = solver_json.is_null() ? nlohmann::json{{"name", solver_name}, {"skipped", true}}
                                           : solver_json;
  report["decision"] = decision_json.is_null() ? nlohmann::json{{"rule", o.decision.rule.ToString()},
                                                                {"skipped", true}}
                                               : decision_json;
  report["message"] = result.message;
  timings["total"] = total.Seconds();
  WriteReport(out, report);
  result.report = report;
  return result;
}

}  // namespace al
