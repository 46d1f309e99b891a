#include "al/eval/inputs.hpp"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/io/npy.hpp"

namespace al::eval {

namespace fs = std::filesystem;

std::vector<std::int32_t> LoadLabels(const std::string& path, std::size_t num_gaussians) {
  const NpyArray a = ReadNpy(path);
  if (!a.is_integer() || a.shape.size() != 1)
    throw FileError(path, "labels must be a 1-D integer array (object id per Gaussian), got " + a.descr);
  if (a.size() != num_gaussians)
    throw FileError(path, "has " + std::to_string(a.size()) + " labels, the scene " + std::to_string(num_gaussians) +
                              " Gaussians");
  const std::vector<std::int64_t> v = a.ToInt64();
  std::vector<std::int32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] < INT32_MIN || v[i] > INT32_MAX) throw FileError(path, "label out of the int32 range");
    out[i] = std::int32_t(v[i]);
  }
  return out;
}

TargetInfo ResolveTarget(const std::string& labels_path, std::optional<int> object_id) {
  TargetInfo t;
  const fs::path file = fs::path(labels_path).parent_path() / "target.json";
  if (fs::exists(file)) {
    try {
      const nlohmann::json j = nlohmann::json::parse(ReadInputFile(file.string(), std::uint64_t(1) << 20));
      t.object_id = j.at("object_id").get<int>();
      t.name = j.value("name", std::string());
      t.preset = j.value("preset", std::string());
    } catch (const Error&) {
      throw;  // not a regular file, too large
    } catch (const std::exception&) {
      if (!object_id) throw FileError(file.string(), "expected {\"object_id\": k, ...}");
    }
  } else if (!object_id) {
    throw Error(labels_path + ": no --object-id and no target.json beside the labels", ExitCode::kUsage);
  }
  if (object_id && *object_id != t.object_id) {
    t.object_id = *object_id;
    t.name.clear();  // target.json describes another object
  }
  return t;
}

std::string ColumnLabelFromPath(const std::string& path) {
  std::string stem = fs::path(path).stem().string();
  if (stem.rfind("removed_", 0) == 0 && stem.size() > 8) stem = stem.substr(8);
  return stem.empty() ? "removal" : stem;
}

std::pair<std::string, std::string> SplitNamedPath(const std::string& spec) {
  const auto eq = spec.find('=');
  // A '=' inside a directory name is left alone: a name never holds a path separator.
  if (eq == std::string::npos || eq == 0 || spec.substr(0, eq).find('/') != std::string::npos) return {"", spec};
  return {spec.substr(0, eq), spec.substr(eq + 1)};
}

}  // namespace al::eval
