// Input helpers of the evaluator shared by `eval` and `demo`: ground-truth labels, the target
// object (target.json written by `synth`), and default names for table rows and columns.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/eval/eval.hpp"
#include "al/io/camera.hpp"
#include "al/scene/scene.hpp"

namespace al::eval {

// int32 object id per Gaussian from an integer .npy of shape (N,); throws al::Error naming the file.
std::vector<std::int32_t> LoadLabels(const std::string& path, std::size_t num_gaussians);

struct TargetInfo {
  int object_id = 0;
  std::string name, preset;  // from target.json when present
};
// The target: `object_id` when given, else target.json beside the labels ({"object_id", "name",
// "preset"}). Throws al::Error when neither says which object.
TargetInfo ResolveTarget(const std::string& labels_path, std::optional<int> object_id);

// "removed_fgs.npy" → "fgs"; other files → their stem.
std::string ColumnLabelFromPath(const std::string& path);

// "NAME=PATH" → {NAME, PATH}; a plain PATH → {"", PATH}.
std::pair<std::string, std::string> SplitNamedPath(const std::string& spec);

// The files of one evaluation (the `eval` subcommand's inputs).
struct EvalFiles {
  std::string scene, removed, removed_is = "removed", label, cameras, views = "all";
  std::vector<std::string> refined, seg_refined, sam_refined;  // refined: [NAME=]FILE, repeatable
  std::string object_masks, labels, seg_after, sam_after, row_name;
  std::optional<int> object_id;
  void Check() const;  // the object source is given; no more segmentation folders than refined sets
  std::vector<std::string> Paths() const;  // every input path (an output set must not replace them)
};

// The loaded inputs, ready for RunEval, and the report skeleton (inputs with hashes, warnings,
// params, load timings).
struct EvalInputs {
  Scene scene;
  std::vector<Camera> views;
  std::vector<EvalColumn> columns;  // the method's set ("after"), then each refined set
  ObjectSource object;
  std::string row;                  // table row: --row-name, else PRESET-OBJECT, else the folder name
  nlohmann::json report;
};
EvalInputs LoadEvalInputs(const EvalFiles& files);

}  // namespace al::eval
