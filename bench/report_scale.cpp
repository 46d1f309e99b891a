// bench_scale_collect: gathers what bench/scale measured (each stage's report.json: peak_rss_mib,
// timings_s, status, counts, graph; the script's wall time, exit code and sampled RSS timeline)
// into one JSON file, bench/results/scale_3m.json, which bench_report turns into the scale section
// of docs/benchmarks.md. A C++ tool because python/jq are not guaranteed on CI machines.
//   bench_scale_collect --out FILE --scene-file PLY --scene TEXT --synth-command TEXT
//       --machine TEXT --run "name=refine_bk;exit=0;wall_s=12.3;report=DIR/report.json;rss=FILE"...
//       [--note TEXT]...
// Exit codes: 0 ok, 1 usage, 2 bad input (al::ExitCode).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/atomic_file.hpp"
#include "bench/tool_main.hpp"
#include "al/core/error.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// "a=1;b=x" -> {a: 1, b: x}
std::map<std::string, std::string> ParseFields(const std::string& spec) {
  std::map<std::string, std::string> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ';')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw al::Error("bench_scale_collect: --run field without '=': " + item, al::ExitCode::kUsage);
    out[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return out;
}

double ToDouble(const std::string& s, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  throw al::Error("bench_scale_collect: " + what + " is not a number: '" + s + "'", al::ExitCode::kUsage);
}

using Samples = std::vector<std::pair<double, double>>;  // (seconds since start, MiB)

// RSS samples "seconds KiB" per line, as bench/scale's sampler writes them.
Samples ReadSamples(const fs::path& path) {
  std::ifstream in(path);
  Samples s;
  double t = 0, kib = 0;
  while (in >> t >> kib) s.emplace_back(t, kib / 1024.0);
  return s;
}

// [[seconds, MiB], ...] thinned to at most max_points, always keeping the peak sample.
json Thin(const Samples& s, std::size_t max_points = 150) {
  json out = json::array();
  if (s.empty()) return out;
  const auto peak = std::max_element(s.begin(), s.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  const std::size_t step = std::max<std::size_t>(1, (s.size() + max_points - 1) / max_points);
  const std::size_t peak_index = static_cast<std::size_t>(peak - s.begin());
  for (std::size_t i = 0; i < s.size(); ++i)
    if (i % step == 0 || i == peak_index || i + 1 == s.size())
      out.push_back({std::round(s[i].first * 100) / 100, std::round(s[i].second * 10) / 10});
  return out;
}

// Where the memory goes: the stages of a command run one after the other in this order (the
// report's timings_s is an unordered JSON object), so cumulative stage times cut the sampled RSS
// timeline into windows; each stage gets the highest RSS sampled in its window. Commands whose
// stages interleave (eval renders, scores and writes per view) are not split.
const std::map<std::string, std::vector<std::string>> kStageOrder = {
    {"synth", {"generate", "masks", "simulate", "write"}},
    {"refine", {"load_scene", "load_removed", "load_labels", "graph", "solve", "decide",
                "ground_truth", "write"}}};

json RssByStage(const std::string& command, const json& timings, const Samples& timeline) {
  json out = json::array();  // [[stage, MiB], ...] in pipeline order
  const auto order = kStageOrder.find(command);
  if (order == kStageOrder.end() || !timings.is_object() || timeline.empty()) return out;
  // The process starts slightly after the sampler's t = 0; the remainder of the wall time that the
  // stages do not account for is start-up, so windows are shifted by it.
  double known = 0;
  for (const auto& st : order->second)
    if (timings.contains(st) && timings[st].is_number()) known += timings[st].get<double>();
  const double total = timings.contains("total") && timings["total"].is_number() ? timings["total"].get<double>() : known;
  const double last_t = timeline.back().first;
  double t = std::max(0.0, last_t - total);
  for (const auto& st : order->second) {
    if (!timings.contains(st) || !timings[st].is_number()) continue;
    const double end = t + timings[st].get<double>();
    double peak = NAN;
    for (const auto& [pt, mib] : timeline)
      if (pt >= t && pt <= end + 0.25) peak = std::isnan(peak) ? mib : std::max(peak, mib);
    if (std::isfinite(peak)) out.push_back({st, peak});
    t = end;
  }
  return out;
}

json CollectRun(const std::map<std::string, std::string>& f) {
  auto get = [&](const std::string& k) {
    auto it = f.find(k);
    if (it == f.end()) throw al::Error("bench_scale_collect: --run needs " + k + "=", al::ExitCode::kUsage);
    return it->second;
  };
  json r;
  const std::string name = get("name");
  r["name"] = name;
  // "refine_bk" -> stage refine, solver bk: the report groups refine runs by solver.
  const auto us = name.find('_');
  r["stage"] = name.substr(0, us);
  if (us != std::string::npos) r["solver"] = name.substr(us + 1);
  r["exit_code"] = static_cast<int>(ToDouble(get("exit"), "exit"));
  r["wall_s"] = ToDouble(get("wall_s"), "wall_s");
  if (auto it = f.find("load"); it != f.end()) r["load_average"] = ToDouble(it->second, "load");
  Samples samples;
  if (auto it = f.find("rss"); it != f.end() && fs::exists(it->second)) samples = ReadSamples(it->second);
  if (!samples.empty()) {
    r["rss_timeline_s_mib"] = Thin(samples);
    r["sampled_peak_rss_mib"] = std::max_element(samples.begin(), samples.end(), [](const auto& a, const auto& b) {
                                  return a.second < b.second;
                                })->second;
  }
  const fs::path report = get("report");
  if (fs::exists(report)) {
    std::ifstream in(report);
    json rep;
    try {
      rep = json::parse(in);
    } catch (const json::exception& e) {
      throw al::FileError(report.string(), std::string("not valid JSON: ") + e.what());
    }
    r["report"] = report.string();
    for (const char* key : {"status", "peak_rss_mib", "timings_s", "counts", "graph"})
      if (rep.contains(key)) r[key] = rep[key];
    if (rep.contains("solver") && rep["solver"].is_object()) r["solver_result"] = rep["solver"];
    if (rep.contains("gt") && rep["gt"].contains("after")) r["f1_after"] = rep["gt"]["after"].value("f1", NAN);
    if (!samples.empty() && r.contains("timings_s"))
      r["rss_by_stage_mib"] = RssByStage(r["stage"], r["timings_s"], samples);
  } else {
    r["status"] = "no report.json";
  }
  return r;
}

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

using Series = std::map<std::string, std::vector<double>>;  // "wall", "peak_rss_mib", "f1_after", stages

void AddRun(const json& r, Series& s) {
  s["wall"].push_back(r["wall_s"].get<double>());
  for (const char* key : {"peak_rss_mib", "f1_after", "load_average"})
    if (r.contains(key) && r[key].is_number()) s[key].push_back(r[key].get<double>());
  if (r.contains("timings_s") && r["timings_s"].is_object())
    for (const auto& [k, v] : r["timings_s"].items())
      if (v.is_number()) s["stage " + k].push_back(v.get<double>());
}

// Per solver: medians of the new and the old code's runs (refine_X, old-refine_X) and their ratio;
// printed as a table. Empty when there are no old runs.
json CompareWithBaseline(const json& runs) {
  json out = json::object();
  for (const std::string solver : {"bk", "cp"}) {
    Series now, old;
    for (const json& r : runs) {
      if (r.value("solver", std::string()) != solver || r.value("exit_code", 1) != 0) continue;
      const std::string stage = r.value("stage", std::string());
      if (stage == "refine") AddRun(r, now);
      else if (stage == "old-refine") AddRun(r, old);
    }
    if (now.empty() || old.empty()) continue;
    json rows = json::object();
    std::cout << "\n" << solver << " (medians of " << now["wall"].size() << " new / " << old["wall"].size()
              << " old runs)\n  " << std::left;
    std::printf("%-22s %10s %10s %8s\n", "", "new", "old", "new/old");
    for (const Series* s : {&now, &old})
      for (const auto& [key, values] : *s) {
        if (rows.contains(key)) continue;
        const double a = now.count(key) ? Median(now[key]) : NAN, b = old.count(key) ? Median(old[key]) : NAN;
        rows[key] = {{"new", a}, {"old", b}, {"ratio", a / b}};
        std::printf("  %-22s %10.4g %10.4g %8.3f\n", key.c_str(), a, b, a / b);
      }
    out[solver] = {{"ratio_wall", Median(now["wall"]) / Median(old["wall"])}, {"rows", rows},
                   {"runs_new", now["wall"].size()}, {"runs_old", old["wall"].size()}};
  }
  return out;
}

int Main(int argc, char** argv) {
  fs::path out, scene_file;
  json doc;
  doc["runs"] = json::array();
  doc["notes"] = json::array();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) throw al::Error("bench_scale_collect: " + a + " needs a value", al::ExitCode::kUsage);
    const std::string v = argv[++i];
    if (a == "--out") out = v;
    else if (a == "--scene-file") scene_file = v;
    else if (a == "--scene") doc["scene"] = v;
    else if (a == "--synth-command") doc["synth_command"] = v;
    else if (a == "--machine") doc["machine"] = v;
    else if (a == "--run") doc["runs"].push_back(CollectRun(ParseFields(v)));
    else if (a == "--note") doc["notes"].push_back(v);
    else throw al::Error("bench_scale_collect: unknown argument '" + a + "'", al::ExitCode::kUsage);
  }
  if (out.empty()) throw al::Error("bench_scale_collect: --out is required", al::ExitCode::kUsage);
  if (!scene_file.empty() && fs::exists(scene_file)) {
    doc["scene_file_bytes"] = fs::file_size(scene_file);
    doc["scene_file_mib"] = static_cast<double>(fs::file_size(scene_file)) / (1024.0 * 1024.0);
  } else {
    doc["notes"].push_back("scene file missing: synth failed?");
  }
  // The SPEC §8 memory check, stated where the numbers are.
  if (doc.contains("scene_file_mib"))
    for (const json& r : doc["runs"])
      if (r.value("stage", std::string()) == "refine" && r.contains("peak_rss_mib")) {
        const double ratio = r["peak_rss_mib"].get<double>() / doc["scene_file_mib"].get<double>();
        std::ostringstream o;
        o.precision(3);
        o << "refine (" << r.value("solver", std::string("?")) << ") peak RSS = " << ratio
          << "x the scene file: " << (ratio < 3 ? "within" : "OVER") << " the 3x target";
        doc["notes"].push_back(o.str());
      }
  doc["comparison"] = CompareWithBaseline(doc["runs"]);
  al::WriteFileAtomically(out, doc.dump(2) + "\n");
  std::cout << "bench_scale_collect: wrote " << out.string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return al::bench::RunTool("bench_scale_collect", [&] { return Main(argc, argv); });
}
