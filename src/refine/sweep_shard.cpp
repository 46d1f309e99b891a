// shard.json (al/refine/sweep.hpp): the identity of the sweep a shard folder is a slice of, so
// that merge can refuse folders of different sweeps and sweep can refuse to resume one.
#include <filesystem>
#include <fstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/report.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

constexpr const char* kShardFormat = "al-refine sweep shard 1";
constexpr std::uintmax_t kHashLimit = 64u << 20;  // as report.json inputs: larger files by size only

// An input file by absolute path, size and (up to 64 MiB) content: two shards that read different
// files, or one file that changed between them, are different sweeps.
nlohmann::json InputIdentity(const std::string& path) {
  if (path.empty()) return nullptr;
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec).lexically_normal();
  nlohmann::json j = {{"path", ec ? path : abs.string()}};
  if (fs::is_regular_file(abs, ec)) {
    const auto bytes = fs::file_size(abs, ec);
    j["bytes"] = bytes;
    if (!ec && bytes <= kHashLimit) j["sha256"] = Sha256File(abs);
  }
  return j;
}

bool IsFeatureFile(const std::string& f) { return f.ends_with(".npy") || f.ends_with(".ply"); }

// Everything of a scene that the grid does not vary: its inputs and the fixed refine flags.
nlohmann::json SceneIdentity(const SweepScene& s) {
  const RefineOptions& o = s.options;
  nlohmann::json decoder = nlohmann::json::array();
  for (std::size_t pos = 0; !o.decoder.empty() && pos <= o.decoder.size();) {
    const std::size_t comma = std::min(o.decoder.find(',', pos), o.decoder.size());
    decoder.push_back(InputIdentity(o.decoder.substr(pos, comma - pos)));
    pos = comma + 1;
  }
  const bool feature_file = IsFeatureFile(o.features);
  return {{"name", s.name},
          {"inputs",
           {{"scene", InputIdentity(o.scene)}, {"removed", InputIdentity(o.removed)},
            {"labels", InputIdentity(o.labels)}, {"cameras", InputIdentity(s.cameras)},
            {"object_masks", InputIdentity(s.object_masks)},
            {"features", feature_file ? InputIdentity(o.features) : nullptr},
            {"prompt_embeddings", InputIdentity(o.prompt_embeddings)}, {"decoder", decoder}}},
          {"flags",
           {{"method", o.method}, {"features", feature_file ? "" : o.features},
            {"removed_is", !o.removed_is ? "" : *o.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
            {"object_id", o.object_id ? nlohmann::json(*o.object_id) : nlohmann::json()},
            {"max_unmatched", o.max_unmatched}, {"match_tol", o.match_tol}, {"positives", o.positives},
            {"fgs_threshold", o.fgs_threshold},
            {"delta_mode", o.graph.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
            {"spatial", o.graph.spatial}, {"knn_checks", o.graph.knn_checks},
            {"kl_smoothing", o.graph.kl_smoothing}, {"normalize_features", o.graph.normalize_features},
            {"restore", DecisionOptions::Table().ToJson(o.decision).at("restore")}}}};
}

// The running executable: results of two builds must not be mixed in one sweep.
const nlohmann::json& BinaryIdentity() {
  static const nlohmann::json identity = [] {
    nlohmann::json j = {{"version", NewReport("sweep")["version"]}};
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    j["sha256"] = ec ? std::string("unknown") : Sha256File(exe);
    return j;
  }();
  return identity;
}

// "k: [6,10] vs [6,14]" for the first value that differs below `path`, or "" when equal.
std::string FirstDifference(const nlohmann::json& a, const nlohmann::json& b, const std::string& path) {
  if (a == b) return "";
  if (a.is_object() && b.is_object()) {
    for (const auto& [key, value] : a.items()) {
      const std::string sub = path.empty() ? key : path + "." + key;
      if (!b.contains(key)) return sub + ": only in one of them";
      if (const std::string d = FirstDifference(value, b[key], sub); !d.empty()) return d;
    }
    for (const auto& [key, value] : b.items())
      if (!a.contains(key)) return (path.empty() ? key : path + "." + key) + ": only in one of them";
  }
  if (a.is_array() && b.is_array() && a.size() == b.size() && !a.empty() && a[0].is_structured()) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (const std::string d = FirstDifference(a[i], b[i], path + "[" + std::to_string(i) + "]"); !d.empty())
        return d;
  }
  auto brief = [](const nlohmann::json& v) {
    const std::string s = v.dump();
    return s.size() <= 80 ? s : s.substr(0, 77) + "...";
  };
  return (path.empty() ? std::string("value") : path) + ": " + brief(a) + " vs " + brief(b);
}

std::size_t Count(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_number_unsigned())
    throw Error(where + ": '" + key + "' missing or not a count", ExitCode::kBadInput);
  return j[key].get<std::size_t>();
}

}  // namespace

nlohmann::json GridToJson(const SweepGrid& g) {
  nlohmann::json lambda = nlohmann::json::array();  // "auto" for an unset λ
  for (const auto& l : g.lambda) lambda.push_back(l ? nlohmann::json(*l) : nlohmann::json("auto"));
  return {{"k", g.k}, {"delta", g.delta}, {"hops", g.hops}, {"radius_scale", g.radius_scale},
          {"lambda", lambda}, {"solver", g.solver}, {"threshold", g.threshold},
          {"segment_share", g.segment_share}};
}

SweepGrid GridFromJson(const nlohmann::json& j) {
  SweepGrid g;
  try {
    j.at("k").get_to(g.k);
    j.at("delta").get_to(g.delta);
    j.at("hops").get_to(g.hops);
    j.at("radius_scale").get_to(g.radius_scale);
    for (const auto& l : j.at("lambda"))
      g.lambda.push_back(l == "auto" ? std::nullopt : std::optional<double>(l.get<double>()));
    j.at("solver").get_to(g.solver);
    j.at("threshold").get_to(g.threshold);
    j.at("segment_share").get_to(g.segment_share);
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("grid: ") + e.what(), ExitCode::kBadInput);
  }
  return g;
}

nlohmann::json ShardInfo::ToJson() const {
  return {{"format", kShardFormat},  {"shard", shard.ToString()}, {"shard_index", shard.index},
          {"shard_count", shard.count}, {"points_total", points_total}, {"first_point", first},
          {"points_in_shard", end - first}, {"grid", grid}, {"scenes", scenes}, {"fixed", fixed},
          {"binary", binary}};
}

ShardInfo MakeShardInfo(const SweepOptions& o) {
  ShardInfo info;
  info.shard = o.shard;
  info.points_total = o.scenes.size() * o.grid.size();
  std::tie(info.first, info.end) = ShardRange(info.points_total, o.shard);
  info.grid = GridToJson(o.grid);
  info.scenes = nlohmann::json::array();
  for (const auto& s : o.scenes) info.scenes.push_back(SceneIdentity(s));
  info.fixed = {{"solver_options", o.solver_options}, {"eval_views", o.eval_views}};
  info.binary = BinaryIdentity();
  return info;
}

ShardInfo ReadShardInfo(const std::string& dir, Links links) {
  const fs::path path = fs::path(dir) / "shard.json";
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw Error(dir + ": no shard.json (not a sweep output, or written by an al-refine before shard.json; "
                "rerun that shard with the same command to add it)", ExitCode::kBadInput);
  const std::string text = ReadInputFile(path.string(), std::uint64_t(1) << 26, links);  // refuses a FIFO at once
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw FileError(path.string(), std::string("not valid JSON (") + e.what() + ")");
  }
  const std::string where = path.string();
  if (!j.is_object() || j.value("format", "") != kShardFormat) throw FileError(where, "not an al-refine shard.json");
  ShardInfo info;
  info.shard = {Count(j, "shard_index", where), Count(j, "shard_count", where)};
  info.points_total = Count(j, "points_total", where);
  info.first = Count(j, "first_point", where);
  info.end = info.first + Count(j, "points_in_shard", where);
  if (info.shard.count == 0 || info.shard.index >= info.shard.count || info.end > info.points_total ||
      !j.contains("scenes") || !j["scenes"].is_array())
    throw FileError(where, "inconsistent shard, point counts or scenes");
  for (const auto& s : j["scenes"])
    if (!s.is_object() || !s.contains("name") || !s["name"].is_string()) throw FileError(where, "a scene without a name");
  info.grid = j["grid"];
  info.scenes = j["scenes"];
  info.fixed = j["fixed"];
  info.binary = j["binary"];
  if (GridFromJson(info.grid).size() * info.scenes.size() != info.points_total ||
      ShardRange(info.points_total, info.shard) != std::make_pair(info.first, info.end))
    throw FileError(where, "points_total or the slice do not match the grid and scenes");
  return info;
}

void WriteShardInfo(const std::string& dir, const ShardInfo& info) {
  WriteFileAtomically(fs::path(dir) / "shard.json", info.ToJson().dump(2) + "\n");
}

std::vector<std::string> SweepDifferences(const ShardInfo& a, const ShardInfo& b) {
  std::vector<std::string> out;
  if (a.shard.count != b.shard.count)
    out.push_back("shard count (" + std::to_string(a.shard.count) + " vs " + std::to_string(b.shard.count) + ")");
  const std::pair<const char*, std::pair<const nlohmann::json*, const nlohmann::json*>> groups[] = {
      {"grid", {&a.grid, &b.grid}},
      {"scenes", {&a.scenes, &b.scenes}},
      {"fixed flags", {&a.fixed, &b.fixed}},
      {"binary", {&a.binary, &b.binary}}};
  for (const auto& [name, pair] : groups)
    if (*pair.first != *pair.second) out.push_back(std::string(name) + " (" + FirstDifference(*pair.first, *pair.second, "") + ")");
  if (out.empty() && a.points_total != b.points_total)
    out.push_back("points_total (" + std::to_string(a.points_total) + " vs " + std::to_string(b.points_total) + ")");
  return out;
}

std::vector<std::string> SweepPointIds(const ShardInfo& info, std::size_t first, std::size_t end) {
  const std::vector<SweepPoint> points = EnumeratePoints(GridFromJson(info.grid));
  std::vector<std::string> ids;
  if (points.empty()) return ids;
  ids.reserve(end - first);
  for (std::size_t j = first; j < end && j / points.size() < info.scenes.size(); ++j)
    ids.push_back(PointId(info.scenes[j / points.size()]["name"].get<std::string>(), points[j % points.size()]));
  return ids;
}

}  // namespace al
