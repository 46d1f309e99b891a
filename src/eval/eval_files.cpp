// Loading the files of one evaluation (al/eval/inputs.hpp): scene, cameras, the removal sets as
// columns, the object source and the table row, with the report skeleton that records them.
#include <filesystem>

#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/eval/inputs.hpp"
#include "al/io/cameras.hpp"
#include "al/io/masks.hpp"
#include "al/io/ply.hpp"

namespace al::eval {
namespace {

namespace fs = std::filesystem;

void AddWarnings(nlohmann::json& report, const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) report["warnings"].push_back(w);
}

void AddIfFile(nlohmann::json& report, const std::string& key, const std::string& path) {
  if (fs::is_regular_file(path)) AddInputFile(report, key, path);
}

// The method's set first ("after", labelled by --label or the file name), then each refined set.
std::vector<EvalColumn> LoadColumns(const EvalFiles& f, const Scene& scene, nlohmann::json& report) {
  RemovalLoadOptions ro;
  ro.removed_is = f.removed_is == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
  RemovalSet removal = LoadRemovalSet(f.removed, scene, ro);
  AddWarnings(report, removal.warnings);
  AddIfFile(report, "removed", f.removed);
  const std::string method = f.label.empty() ? ColumnLabelFromPath(f.removed) : f.label;
  std::vector<EvalColumn> columns;
  columns.push_back({"after", method, std::move(removal.removed), f.seg_after, f.sam_after});
  for (std::size_t i = 0; i < f.refined.size(); ++i) {
    auto [name, path] = SplitNamedPath(f.refined[i]);
    if (name.empty()) name = f.refined.size() == 1 ? "refined" : "refined" + std::to_string(i + 1);
    RemovalSet set = LoadRemovalSet(path, scene, {});
    AddWarnings(report, set.warnings);
    AddIfFile(report, "refined_" + name, path);
    columns.push_back({name, method + "+" + name, std::move(set.removed),
                       i < f.seg_refined.size() ? f.seg_refined[i] : "", i < f.sam_refined.size() ? f.sam_refined[i] : ""});
  }
  return columns;
}

// A synth scene names its target in target.json beside scene.ply: "PRESET-OBJECT".
std::string RowFromSceneTarget(const std::string& scene_path) {
  const fs::path target = fs::path(scene_path).parent_path() / "target.json";
  if (!fs::is_regular_file(target)) return "";
  try {
    const TargetInfo t = ResolveTarget(target.string(), std::nullopt);
    if (!t.name.empty() && !t.preset.empty()) return t.preset + "-" + t.name;
  } catch (const Error&) {  // not a synth target file: fall back to the folder name
  }
  return "";
}

// The object (masks folder or labels + id) and the table row name.
void ResolveObject(const EvalFiles& f, EvalInputs& in) {
  in.object.masks_dir = f.object_masks;
  if (!f.object_masks.empty()) in.report["inputs"]["object_masks"] = {{"path", f.object_masks}};
  std::string row = f.row_name;
  if (!f.labels.empty()) {
    in.object.labels = LoadLabels(f.labels, in.scene.size());
    AddInputFile(in.report, "labels", f.labels);
    const TargetInfo target = ResolveTarget(f.labels, f.object_id);
    in.object.object_id = target.object_id;
    if (row.empty() && !target.name.empty())
      row = (target.preset.empty() ? fs::path(f.scene).parent_path().filename().string() : target.preset) + "-" +
            target.name;
  }
  if (row.empty() && f.labels.empty()) row = RowFromSceneTarget(f.scene);
  if (row.empty()) row = fs::path(f.scene).parent_path().filename().string();
  if (row.empty()) row = fs::path(f.scene).stem().string();
  in.row = row;
}

}  // namespace

void EvalFiles::Check() const {
  if (object_masks.empty() && labels.empty())
    throw Error("eval: give --object-masks DIR or --labels GT.npy (which pixels are the object)", ExitCode::kUsage);
  if (seg_refined.size() > refined.size() || sam_refined.size() > refined.size())
    throw Error("eval: more --seg-refined/--sam-refined folders than --refined sets", ExitCode::kUsage);
  if (removed_is != "removed" && removed_is != "remaining")
    throw Error("eval: --removed-is must be removed or remaining", ExitCode::kUsage);
}

std::vector<std::string> EvalFiles::Paths() const {
  std::vector<std::string> paths = {scene, removed, cameras, object_masks, labels, seg_after, sam_after};
  for (const auto* list : {&refined, &seg_refined, &sam_refined})
    for (const auto& p : *list) paths.push_back(SplitNamedPath(p).second);
  return paths;
}

EvalInputs LoadEvalInputs(const EvalFiles& f) {
  f.Check();
  EvalInputs in;
  in.report = NewReport("eval");
  Timer t;
  in.scene = ReadScene(f.scene);
  AddInputFile(in.report, "scene", f.scene);
  const double load_scene_s = t.Seconds();
  t.Reset();
  CameraLoadResult loaded = ReadCameras(f.cameras);
  AddWarnings(in.report, loaded.warnings);
  in.views = SelectViews(loaded.cameras, f.views);
  AddIfFile(in.report, "cameras", f.cameras);
  in.columns = LoadColumns(f, in.scene, in.report);
  ResolveObject(f, in);
  in.report["params"] = {{"scene", f.scene},   {"removed", f.removed}, {"removed_is", f.removed_is},
                         {"label", in.columns[0].label}, {"refined", f.refined}, {"cameras", f.cameras},
                         {"views", f.views},   {"labels", f.labels}};
  in.report["timings_s"] = {{"load_scene", load_scene_s}, {"load_inputs", t.Seconds()}};
  return in;
}

}  // namespace al::eval
