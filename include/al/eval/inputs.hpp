// Input helpers of the evaluator shared by `eval` and `demo`: ground-truth labels, the target
// object (target.json written by `synth`), and default names for table rows and columns.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

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

}  // namespace al::eval
