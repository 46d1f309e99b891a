// Sweep grids, points, ids, shards and manifests (al/refine/sweep.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/text.hpp"
#include "al/decision.hpp"
#include "al/refine/stages.hpp"
#include "al/refine/sweep.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

std::string GridError(const std::string& what) { return "--grid: " + what; }

template <class T>
void PushUnique(std::vector<T>& values, const T& v) {
  if (std::find(values.begin(), values.end(), v) == values.end()) values.push_back(v);
}

std::string Num(double v) { return nlohmann::json(v).dump(); }

// A value of an options field, parsed and range-checked by that field's table exactly as the CLI
// flag (--k, --threshold, ...) is: the whole options struct is checked with the value in place.
template <class O>
O WithGridValue(const O& base, const std::string& field, const std::string& text) {
  O probe = base;
  try {
    O::Table().SetText(probe, field, text);
    probe.Check();
  } catch (const Error& e) {
    throw Error(GridError(e.what()), ExitCode::kUsage);
  }
  return probe;
}

const char* const kGridKeys = "k, delta, hops, radius_scale, lambda, solver, threshold, segment_share";

void AddGridValue(SweepGrid& g, const std::string& key, const std::string& v, const RefineOptions& base) {
  if (key == "k") {
    PushUnique(g.k, WithGridValue(base.graph, key, v).k);
  } else if (key == "delta") {
    PushUnique(g.delta, WithGridValue(base.graph, key, v).delta);
  } else if (key == "hops") {
    PushUnique(g.hops, WithGridValue(base.graph, key, v).hops);
  } else if (key == "radius_scale") {
    PushUnique(g.radius_scale, WithGridValue(base.graph, key, v).radius_scale);
  } else if (key == "lambda") {
    PushUnique(g.lambda, WithGridValue(base.graph, key, v).lambda);
  } else if (key == "solver") {
    const auto names = SolverNames();
    if (std::find(names.begin(), names.end(), v) == names.end())
      throw Error(GridError("unknown solver '" + v + "'"), ExitCode::kUsage);
    PushUnique(g.solver, v);
  } else if (key == "threshold") {
    PushUnique(g.threshold, WithGridValue(base.decision, "threshold", v).rule.ToString());
  } else if (key == "segment_share") {
    PushUnique(g.segment_share, WithGridValue(base.decision, "min_segment_share", v).min_segment_share);
  } else {
    throw Error(GridError("unknown key '" + key + "' (" + kGridKeys + ")"), ExitCode::kUsage);
  }
}

// Axes the grid does not name take the base options' single value.
void FillUnnamedAxes(SweepGrid& g, const RefineOptions& base) {
  if (g.k.empty()) g.k = {base.graph.k};
  if (g.delta.empty()) g.delta = {base.graph.delta};
  if (g.hops.empty()) g.hops = {base.graph.hops};
  if (g.radius_scale.empty()) g.radius_scale = {base.graph.radius_scale};
  if (g.lambda.empty()) g.lambda = {base.graph.lambda};
  if (g.solver.empty()) g.solver = {ResolveSolverName(base.solver)};
  if (g.threshold.empty()) g.threshold = {base.decision.rule.ToString()};
  if (g.segment_share.empty()) g.segment_share = {base.decision.min_segment_share};
}

}  // namespace

std::size_t SweepGrid::size() const {
  return k.size() * delta.size() * hops.size() * radius_scale.size() * lambda.size() * solver.size() *
         threshold.size() * segment_share.size();
}

SweepGrid ParseSweepGrid(const std::string& text, const RefineOptions& base) {
  base.Check();  // a grid value is checked with the other options in place: they must be valid first
  SweepGrid g;
  std::set<std::string> seen;
  for (const std::string& item : SplitTrimmed(text, ';')) {
    if (item.empty()) continue;  // tolerate "a=1;;b=2" and a trailing ';'
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw Error(GridError("expected key=v1,v2,... in '" + item + "'"), ExitCode::kUsage);
    const std::string key = Trim(item.substr(0, eq));
    if (!seen.insert(key).second) throw Error(GridError("'" + key + "' given twice"), ExitCode::kUsage);
    const std::vector<std::string> values = SplitTrimmed(item.substr(eq + 1), ',');
    if (values.empty()) throw Error(GridError(key + ": no values"), ExitCode::kUsage);
    for (const std::string& v : values) {
      if (v.empty()) throw Error(GridError(key + ": empty value"), ExitCode::kUsage);
      AddGridValue(g, key, v, base);
    }
  }
  FillUnnamedAxes(g, base);
  return g;
}

std::vector<SweepPoint> EnumeratePoints(const SweepGrid& g) {
  std::vector<SweepPoint> points;
  points.reserve(g.size());
  for (int k : g.k)
    for (double d : g.delta)
      for (int h : g.hops)
        for (double r : g.radius_scale)
          for (const std::optional<double>& l : g.lambda)
            for (const auto& s : g.solver)
              for (const auto& t : g.threshold)
                for (double m : g.segment_share) points.push_back({k, d, h, r, l, s, t, m});
  return points;
}

bool SameGraph(const SweepPoint& a, const SweepPoint& b) {
  return a.k == b.k && a.delta == b.delta && a.hops == b.hops && a.radius_scale == b.radius_scale;
}

std::string PointId(const std::string& scene, const SweepPoint& p) {
  return scene + "|k=" + std::to_string(p.k) + "|delta=" + Num(p.delta) + "|hops=" + std::to_string(p.hops) +
         "|radius_scale=" + Num(p.radius_scale) + "|lambda=" + (p.lambda ? Num(*p.lambda) : "auto") + "|solver=" + p.solver +
         "|threshold=" + p.threshold + "|segment_share=" + Num(p.segment_share);
}

std::string Shard::ToString() const { return std::to_string(index) + "/" + std::to_string(count); }

Shard ParseShard(const std::string& text) {
  const auto slash = text.find('/');
  auto bad = [&] {
    return Error("--shard: expected i/n with 0 <= i < n (0-based, e.g. 0/3), got '" + text + "'", ExitCode::kUsage);
  };
  if (slash == std::string::npos) throw bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 10 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  Shard s{std::stoul(a), std::stoul(b)};
  if (s.count == 0 || s.index >= s.count) throw bad();
  return s;
}

std::pair<std::size_t, std::size_t> ShardRange(std::size_t total, const Shard& s) {
  // 128-bit-safe for any realistic sizes: total and count are far below 2^32.
  const auto begin = static_cast<std::size_t>(static_cast<unsigned long long>(s.index) * total / s.count);
  const auto end = static_cast<std::size_t>(static_cast<unsigned long long>(s.index + 1) * total / s.count);
  return {begin, end};
}

std::vector<SweepScene> ReadSweepManifest(const std::string& path, const RefineOptions& base) {
  return ParseSweepManifest(ReadInputFile(path, std::uint64_t(1) << 28), path, base);
}

std::vector<SweepScene> ParseSweepManifest(const std::string& text, const std::string& path, const RefineOptions& base) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw FileError(path, std::string("not valid JSON (") + e.what() + ")");
  }
  if (!j.is_array() || j.empty()) throw FileError(path, "expected a non-empty JSON list of scenes");
  const fs::path root = fs::path(path).parent_path();
  auto resolve = [&](const std::string& p) {
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (root / p).lexically_normal().string();
  };
  static const std::set<std::string> kKeys = {"name", "scene", "removed", "removed_is", "method", "features",
                                              "labels", "object_id", "cameras", "object_masks"};
  std::vector<SweepScene> scenes;
  std::set<std::string> names;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const nlohmann::json& e = j[i];
    const std::string where = path + ": entry " + std::to_string(i);
    if (!e.is_object()) throw Error(where + ": expected an object", ExitCode::kBadInput);
    for (const auto& [key, value] : e.items())
      if (!kKeys.count(key)) throw Error(where + ": unknown key '" + key + "'", ExitCode::kBadInput);
    auto str = [&](const char* key, bool required) -> std::string {
      if (!e.contains(key)) {
        if (required) throw Error(where + ": '" + key + "' is required", ExitCode::kBadInput);
        return "";
      }
      if (!e[key].is_string() || e[key].get<std::string>().empty())
        throw Error(where + ": '" + key + "' must be a non-empty string", ExitCode::kBadInput);
      return e[key].get<std::string>();
    };
    SweepScene s;
    s.name = str("name", true);
    if (s.name.find('|') != std::string::npos) throw Error(where + ": a name may not contain '|'", ExitCode::kBadInput);
    if (!names.insert(s.name).second) throw Error(where + ": name '" + s.name + "' is used twice", ExitCode::kBadInput);
    s.options = base;
    s.options.scene = resolve(str("scene", true));
    s.options.removed = resolve(str("removed", true));
    if (const auto r = str("removed_is", false); !r.empty()) {
      if (r != "removed" && r != "remaining")
        throw Error(where + ": removed_is must be 'removed' or 'remaining'", ExitCode::kBadInput);
      s.options.removed_is = r == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
    }
    if (const auto m = str("method", false); !m.empty()) s.options.method = m;
    if (const auto f = str("features", false); !f.empty()) {
      // A feature file is a path; a prefix, "auto" or "colour" is not.
      const bool file = f.size() > 4 && (f.ends_with(".npy") || f.ends_with(".ply"));
      s.options.features = file ? resolve(f) : f;
    }
    if (e.contains("labels")) s.options.labels = resolve(str("labels", false));
    if (e.contains("object_id")) {
      if (!e["object_id"].is_number_integer()) throw Error(where + ": object_id must be an integer", ExitCode::kBadInput);
      s.options.object_id = e["object_id"].get<int>();
    }
    s.cameras = resolve(str("cameras", false));
    s.object_masks = resolve(str("object_masks", false));
    scenes.push_back(std::move(s));
  }
  return scenes;
}

}  // namespace al
