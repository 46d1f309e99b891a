// bench_report: turns the Google Benchmark JSON files of one bench/run (bench/results/*.json, listed
// in run.json) and bench/scale's scale_3m.json into docs/benchmarks.md and gnuplot charts, so every
// number in the docs comes from a measurement file, never from a hand edit.
//   bench_report --results bench/results --out docs/benchmarks.md --charts docs/benchmarks
// A C++ tool rather than a script because python is not guaranteed on CI machines.
// Exit codes: 0 ok, 1 usage, 2 bad/missing input (al::ExitCode).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "al/core/atomic_file.hpp"
#include "bench/tool_main.hpp"
#include "al/core/error.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------
// Reading Google Benchmark output

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double ToMs(double t, const std::string& unit) {
  if (unit == "ns") return t * 1e-6;
  if (unit == "us") return t * 1e-3;
  if (unit == "s") return t * 1e3;
  return t;  // "ms"
}

// One benchmark case (all repetitions of one run_name).
struct Case {
  std::string name;                                    // e.g. "BM_RenderFull/2"
  std::vector<double> times_ms;                        // per repetition (iteration rows)
  std::map<std::string, std::vector<double>> counters; // per repetition
  std::map<std::string, std::map<std::string, double>> agg;  // "median" -> {"time_ms", counters}
  bool error = false;
  std::string error_message;

  double MedianMs() const {
    if (auto it = agg.find("median"); it != agg.end() && it->second.count("time_ms"))
      return it->second.at("time_ms");
    return Median(times_ms);
  }
  std::optional<double> MinMs() const {
    if (times_ms.empty()) return std::nullopt;
    return *std::min_element(times_ms.begin(), times_ms.end());
  }
  std::optional<double> MaxMs() const {
    if (times_ms.empty()) return std::nullopt;
    return *std::max_element(times_ms.begin(), times_ms.end());
  }
  int Repetitions() const {
    if (!times_ms.empty()) return static_cast<int>(times_ms.size());
    if (auto it = agg.find("median"); it != agg.end() && it->second.count("repetitions"))
      return static_cast<int>(it->second.at("repetitions"));
    return 0;
  }
  std::optional<double> Counter(const std::string& key) const {
    if (auto it = agg.find("median"); it != agg.end())
      if (auto c = it->second.find(key); c != it->second.end()) return c->second;
    if (auto it = counters.find(key); it != counters.end() && !it->second.empty())
      return Median(it->second);
    return std::nullopt;
  }
  std::optional<double> CvPercent() const {
    if (auto it = agg.find("cv"); it != agg.end() && it->second.count("time_ms"))
      return 100.0 * it->second.at("time_ms");
    return std::nullopt;
  }
};

struct BenchFile {
  std::string stem;  // "render_bench"
  json context;
  std::vector<Case> cases;  // in file order
  const Case* Find(const std::string& name) const {
    for (const Case& c : cases)
      if (c.name == name) return &c;
    return nullptr;
  }
};

// "BM_X/2/repeats:5/min_time:1.000/iterations:1/real_time" -> "BM_X/2": the harness settings
// are the same for every case of a run and only clutter the tables.
std::string ShortName(const std::string& run_name) {
  static const std::regex noise("/(repeats:[0-9]+|min_time:[0-9.]+|iterations:[0-9]+|real_time|manual_time)");
  return std::regex_replace(run_name, noise, "");
}

const std::vector<std::string> kNonCounterKeys = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
    "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit",
    "aggregate_name", "aggregate_unit", "label", "error_occurred", "error_message"};

json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw al::FileError(path.string(), "cannot open");
  std::string text(std::istreambuf_iterator<char>(in), {});
  // Google Benchmark writes NaN/inf (e.g. the cv of an all-zero counter), which is not JSON:
  // such values carry no information, so they become null.
  static const std::regex non_finite(R"((:\s*)-?(NaN|nan|inf|Inf|Infinity)\b)");
  text = std::regex_replace(text, non_finite, "$1null");
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw al::FileError(path.string(), std::string("not valid JSON: ") + e.what());
  }
}

BenchFile ReadBenchFile(const fs::path& path) {
  const json j = ReadJson(path);
  if (!j.contains("benchmarks") || !j["benchmarks"].is_array())
    throw al::FileError(path.string(), "no \"benchmarks\" array (not Google Benchmark JSON)");
  BenchFile f;
  f.stem = path.stem().string();
  f.context = j.value("context", json::object());
  std::map<std::string, std::size_t> index;
  for (const json& b : j["benchmarks"]) {
    const std::string run = ShortName(b.value("run_name", b.value("name", std::string("?"))));
    auto [it, fresh] = index.try_emplace(run, f.cases.size());
    if (fresh) {
      f.cases.emplace_back();
      f.cases.back().name = run;
    }
    Case& c = f.cases[it->second];
    if (b.value("error_occurred", false)) {
      c.error = true;
      c.error_message = b.value("error_message", std::string("error"));
      continue;
    }
    const std::string unit = b.value("time_unit", std::string("ns"));
    const bool aggregate = b.value("run_type", std::string("iteration")) == "aggregate";
    std::map<std::string, double> values;
    for (const auto& [k, v] : b.items())
      if (v.is_number() &&
          std::find(kNonCounterKeys.begin(), kNonCounterKeys.end(), k) == kNonCounterKeys.end())
        values[k] = v.get<double>();
    if (aggregate) {
      const std::string which = b.value("aggregate_name", std::string("?"));
      auto& a = c.agg[which];
      a = values;
      // cv is a fraction whatever time_unit says.
      a["time_ms"] = which == "cv" ? b.value("real_time", NAN) : ToMs(b.value("real_time", NAN), unit);
      a["repetitions"] = b.value("repetitions", 0);
    } else {
      c.times_ms.push_back(ToMs(b.value("real_time", NAN), unit));
      for (const auto& [k, v] : values) c.counters[k].push_back(v);
    }
  }
  return f;
}

// ---------------------------------------------------------------------------------------------
// Formatting

std::string Fmt(double v, int sig = 3) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream o;
  const double a = std::abs(v);
  if (a != 0 && (a < 1e-3 || a >= 1e7)) {
    o.precision(sig - 1);
    o << std::scientific << v;
  } else {
    o.precision(a >= std::pow(10.0, sig) ? 0 : sig - 1 - static_cast<int>(std::floor(std::log10(std::max(a, 1e-300)))));
    if (a == 0) o.precision(0);
    o << std::fixed << v;
  }
  return o.str();
}

std::string FmtOpt(const std::optional<double>& v, int sig = 3) { return v ? Fmt(*v, sig) : "–"; }

// Counters shown per case: everything the benchmark reports, in name order (medians).
std::string CounterList(const Case& c) {
  std::map<std::string, double> shown;
  if (auto it = c.agg.find("median"); it != c.agg.end())
    for (const auto& [k, v] : it->second)
      if (k != "time_ms" && k != "repetitions") shown[k] = v;
  for (const auto& [k, v] : c.counters)
    if (!shown.count(k)) shown[k] = Median(v);
  std::string out;
  for (const auto& [k, v] : shown) {
    std::string value = Fmt(v);
    if (k == "bytes_per_second") value = Fmt(v / 1e9) + " GB/s";
    out += (out.empty() ? "" : ", ") + k + " " + value;
  }
  return out.empty() ? "–" : out;
}

// ---------------------------------------------------------------------------------------------
// Targets (SPEC §8), each computed from the files of this run

struct Target {
  std::string what;
  std::string measured;   // human text
  std::string baseline;   // same-run baseline, if any
  std::string ratio;      // measured against the baseline
  std::string target;
  std::optional<bool> met;  // nullopt: not measured in this run
  double headroom = NAN;    // measured / limit, <= 1 means met (chart)
  std::string chart_label;
};

using Files = std::map<std::string, BenchFile>;

const Case* Lookup(const Files& files, const std::string& stem, const std::string& name) {
  auto it = files.find(stem);
  if (it == files.end()) return nullptr;
  const Case* c = it->second.Find(name);
  return c && !c->error ? c : nullptr;
}

Target NotMeasured(std::string what, std::string target, std::string why) {
  Target t;
  t.what = std::move(what);
  t.target = std::move(target);
  t.measured = "not measured (" + why + ")";
  return t;
}

std::vector<Target> ComputeTargets(const Files& files, const json& scale) {
  std::vector<Target> out;

  // PLY load: throughput and ratio against a plain read() of the same file.
  if (const Case* ply = Lookup(files, "ply_load_bench", "BM_ReadPly")) {
    Target t;
    t.what = "PLY load (223 MB INRIA SH3, page cache)";
    const double gbs = ply->Counter("bytes_per_second").value_or(NAN) / 1e9;
    t.measured = Fmt(gbs) + " GB/s (" + Fmt(ply->MedianMs()) + " ms)";
    t.target = "≥ 1 GB/s";
    t.met = gbs >= 1.0;
    t.headroom = 1.0 / gbs;
    t.chart_label = "PLY load";
    if (const Case* base = Lookup(files, "ply_load_bench", "BM_ReadFileBaseline")) {
      t.baseline = "plain read(): " + Fmt(base->Counter("bytes_per_second").value_or(NAN) / 1e9) +
                   " GB/s (" + Fmt(base->MedianMs()) + " ms)";
      t.ratio = Fmt(ply->MedianMs() / base->MedianMs()) + "× the read time";
    }
    out.push_back(t);
  } else {
    out.push_back(NotMeasured("PLY load", "≥ 1 GB/s", "ply_load_bench missing or failed"));
  }

  // Graph build on the 1M scene.
  if (const Case* g = Lookup(files, "graph_bench", "BM_GraphBuild1M")) {
    Target t;
    t.what = "Graph build, 1M scene, ~" + Fmt(g->Counter("nodes").value_or(NAN) / 1e3, 2) + "k nodes, k = 10";
    const double s = g->MedianMs() / 1e3;
    t.measured = Fmt(s) + " s";
    t.target = "< 0.5 s";
    t.met = s < 0.5;
    t.headroom = s / 0.5;
    t.chart_label = "graph build";
    if (auto py = g->Counter("baseline_gaussiancut_python_s")) {
      t.baseline = "GaussianCut Python loop (191 µs/node, quoted): " + Fmt(*py) + " s";
      t.ratio = Fmt(*py / s) + "× faster";
    }
    out.push_back(t);
  } else {
    out.push_back(NotMeasured("Graph build", "< 0.5 s", "graph_bench missing or failed"));
  }

  // bk against Kolmogorov's maxflow on the same network.
  if (const Case* m = Lookup(files, "maxflow_ref_bench", "BM_BkVsMaxflow1M")) {
    Target t;
    t.what = "bk vs libmaxflow 3.04, same 1M-scene network";
    const double r = m->Counter("ratio_bk_over_maxflow").value_or(NAN);
    t.measured = "bk " + Fmt(m->Counter("bk_s").value_or(NAN) * 1e3) + " ms (build " +
                 Fmt(m->Counter("bk_build_s").value_or(NAN) * 1e3) + " + flow " +
                 Fmt(m->Counter("bk_flow_s").value_or(NAN) * 1e3) + ")";
    t.baseline = "libmaxflow " + Fmt(m->Counter("maxflow_s").value_or(NAN) * 1e3) + " ms (build " +
                 Fmt(m->Counter("maxflow_build_s").value_or(NAN) * 1e3) + " + flow " +
                 Fmt(m->Counter("maxflow_flow_s").value_or(NAN) * 1e3) + ")";
    t.ratio = Fmt(r) + "× (median of per-repetition ratios); flow values differ by " +
              Fmt(m->Counter("flow_rel_diff").value_or(NAN), 2) + " rel., " +
              Fmt(m->Counter("label_mismatches").value_or(NAN)) + " labels differ";
    t.target = "≤ 1.5×";
    t.met = r <= 1.5;
    t.headroom = r / 1.5;
    t.chart_label = "bk / maxflow";
    out.push_back(t);
  } else {
    out.push_back(NotMeasured("bk vs libmaxflow", "≤ 1.5×",
                              "maxflow_ref_bench not run: needs libmaxflow-dev, -DAL_BENCH_MAXFLOW=ON"));
  }

  // cp against the exact parametric optimum (time and objective gap), 2 threads; the baseline is cp
  // with every split cut by Boykov-Kolmogorov alone (the max-flow before the hybrid), same run.
  const Case* cp = Lookup(files, "solver_bench", "BM_Cp/threads:2/sat:1/maxflow:0");
  const Case* cp_bk = Lookup(files, "solver_bench", "BM_Cp/threads:2/sat:1/maxflow:1");
  const Case* exact = Lookup(files, "solver_bench", "BM_Exact/maxflow:0");
  if (cp) {
    Target t;
    t.what = "cp, 100k-node kNN problem, 2 threads: time";
    const double s = cp->MedianMs() / 1e3;
    t.measured = Fmt(s) + " s";
    t.target = "< 1 s";
    t.met = s < 1.0;
    t.headroom = s;
    t.chart_label = "cp time";
    if (cp_bk) {
      t.baseline = "cp with BK-only max-flow: " + Fmt(cp_bk->MedianMs() / 1e3) + " s";
      t.ratio = Fmt(cp->MedianMs() / cp_bk->MedianMs()) + "×";
    }
    if (exact) {
      t.baseline += std::string(cp_bk ? "; " : "") + "exact: " + Fmt(exact->MedianMs() / 1e3) + " s";
      t.ratio += std::string(cp_bk ? " (" : "") + Fmt(cp->MedianMs() / exact->MedianMs()) + "× the exact time" +
                 (cp_bk ? ")" : "");
    }
    out.push_back(t);
    Target g;
    g.what = "cp, 100k-node kNN problem: objective gap to exact";
    const double gap = cp->Counter("rel_gap_to_exact").value_or(NAN);
    g.measured = Fmt(gap, 2) + " relative";
    g.target = "≤ 1e-3";
    g.met = gap <= 1e-3;
    g.headroom = gap / 1e-3;
    g.chart_label = "cp gap";
    if (exact) g.baseline = "exact objective " + Fmt(exact->Counter("objective").value_or(NAN), 6);
    out.push_back(g);
  } else {
    out.push_back(NotMeasured("cp vs exact", "< 1 s, gap ≤ 1e-3", "solver_bench missing or failed"));
  }

  // Render: full frame, and incremental "after" against full in the same run.
  const Case* full = Lookup(files, "render_bench", "BM_RenderFull/2");
  const Case* inc = Lookup(files, "render_bench", "BM_RenderIncremental/2");
  if (full) {
    Target t;
    t.what = "Render 1M Gaussians, 1280×720, 2 threads";
    const double s = full->MedianMs() / 1e3;
    t.measured = Fmt(s) + " s";
    t.target = "< 1 s";
    t.met = s < 1.0;
    t.headroom = s;
    t.chart_label = "render full";
    out.push_back(t);
  } else {
    out.push_back(NotMeasured("Render 1M", "< 1 s", "render_bench missing or failed"));
  }
  if (full && inc) {
    Target t;
    const double frac = inc->Counter("object_image_fraction").value_or(NAN);
    t.what = "Incremental \"after\" render (object covers " + Fmt(100 * frac, 2) + " % of the image)";
    const double speedup = full->MedianMs() / inc->MedianMs();
    t.measured = Fmt(inc->MedianMs()) + " ms";
    t.baseline = "full render " + Fmt(full->MedianMs()) + " ms";
    t.ratio = Fmt(speedup) + "× faster";
    t.target = "≥ 5× faster (object < 5 %)";
    t.met = speedup >= 5.0 && frac < 0.05;
    t.headroom = 5.0 / speedup;
    t.chart_label = "incremental";
    out.push_back(t);
  }

  // Evaluation: per-view time of eval_bench's BM_Eval (or the first case with a "views" counter),
  // extrapolated to 100 views; baseline: BM_FullRenders (plain full renders, same scene and views).
  bool eval_done = false;
  if (auto it = files.find("eval_bench"); it != files.end()) {
    std::vector<const Case*> order;
    if (const Case* e = it->second.Find("BM_Eval"); e && !e->error) order.push_back(e);
    for (const Case& c : it->second.cases)
      if (!c.error) order.push_back(&c);
    for (const Case* c : order) {
      const auto views = c->Counter("views");
      if (!views || *views <= 0) continue;
      Target t;
      const double per_view = c->MedianMs() / 1e3 / *views;
      t.what = "Evaluation (" + c->name + ", " + Fmt(*views) + " views" +
               (c->Counter("gaussians") ? ", " + Fmt(*c->Counter("gaussians") / 1e6, 2) + "M Gaussians" : "") + ")";
      t.measured = Fmt(per_view) + " s per view → " + Fmt(100 * per_view) + " s for 100 views" +
                   (*views == 100 ? "" : " (extrapolated)");
      if (const Case* full = Lookup(files, "eval_bench", "BM_FullRenders"); full && full != c)
        if (auto fpv = full->Counter("seconds_per_view")) {
          t.baseline = "full renders only: " + Fmt(*fpv) + " s per view";
          t.ratio = Fmt(per_view / *fpv) + "× the full-render time";
        }
      t.target = "100 views of 1M < 120 s";
      t.met = 100 * per_view < 120;
      t.headroom = 100 * per_view / 120;
      t.chart_label = "eval 100 views";
      out.push_back(t);
      eval_done = true;
      break;
    }
  }
  if (!eval_done)
    out.push_back(NotMeasured("Evaluation, 100 views of 1M", "< 120 s",
                              "no eval_bench result with a \"views\" counter"));

  // Memory: refine peak RSS against 3x the scene file (bench/scale).
  bool mem_done = false;
  if (scale.is_object() && scale.contains("runs")) {
    const double file_mib = scale.value("scene_file_mib", NAN);
    for (const json& r : scale["runs"]) {
      if (r.value("stage", std::string()) != "refine" || !r.contains("peak_rss_mib")) continue;
      Target t;
      const double rss = r["peak_rss_mib"].get<double>();
      t.what = "refine peak RSS, " + scale.value("scene", std::string("3M scene")) + ", solver " +
               r.value("solver", std::string("?"));
      t.measured = Fmt(rss) + " MiB";
      t.baseline = "scene file " + Fmt(file_mib) + " MiB";
      t.ratio = Fmt(rss / file_mib) + "× the file";
      t.target = "< 3× the file";
      t.met = rss < 3 * file_mib;
      t.headroom = rss / (3 * file_mib);
      t.chart_label = "RSS " + r.value("solver", std::string("?"));
      out.push_back(t);
      mem_done = true;
    }
  }
  if (!mem_done)
    out.push_back(NotMeasured("refine peak RSS", "< 3× the scene file", "no bench/results/scale_3m.json"));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Charts

// Writes a gnuplot script and its data into a scratch directory and renders `png`; the PNG is
// written under a temporary name and renamed, like every other output. Returns false (and says
// why on stderr) if gnuplot is missing or fails: the report then links no chart.
bool Plot(const std::string& gnuplot, const fs::path& png, const std::string& data,
          const std::string& script) {
  const fs::path scratch = fs::temp_directory_path() /
                           ("al-bench-report-" + std::to_string(::getpid()) + "-" + png.stem().string());
  fs::create_directories(scratch);
  const fs::path tmp_png = png.string() + ".tmp.png";
  {
    std::ofstream(scratch / "data.dat") << data;
    std::ofstream(scratch / "plot.gp") << "set terminal pngcairo size 1000,520 font 'sans,10'\n"
                                        << "set output '" << tmp_png.string() << "'\n"
                                        << "set termoption noenhanced\n"
                                        << "cd '" << scratch.string() << "'\n"
                                        << script;
  }
  const std::string cmd = gnuplot + " '" + (scratch / "plot.gp").string() + "' 2>'" +
                          (scratch / "err.txt").string() + "'";
  const int rc = std::system(cmd.c_str());
  bool ok = rc == 0 && fs::exists(tmp_png) && fs::file_size(tmp_png) > 0;
  if (ok) {
    fs::rename(tmp_png, png);
  } else {
    std::ifstream err(scratch / "err.txt");
    std::cerr << "bench_report: chart " << png.filename().string() << " not drawn (gnuplot exit "
              << rc << "): " << std::string(std::istreambuf_iterator<char>(err), {}) << "\n";
    fs::remove(tmp_png);
  }
  fs::remove_all(scratch);
  return ok;
}

std::string Quote(std::string s) {
  std::replace(s.begin(), s.end(), '"', '\'');
  return "\"" + s + "\"";
}

// measured / limit per target (1 = exactly on target), log scale.
bool TargetsChart(const std::string& gnuplot, const fs::path& png, const std::vector<Target>& targets) {
  std::ostringstream data;
  int n = 0;
  for (const Target& t : targets)
    if (t.met && std::isfinite(t.headroom) && t.headroom > 0)
      data << n++ << " " << Quote(t.chart_label) << " " << t.headroom << " " << (*t.met ? 1 : 0) << "\n";
  if (n == 0) return false;
  const std::string script =
      "set title 'Targets (SPEC §8): measured / limit, below 1 = met'\n"
      "set logscale y\nset grid ytics\nset style fill solid 0.8\nset boxwidth 0.6\n"
      "set xtics rotate by -30\nset key off\nset ylabel 'measured / limit'\n"
      "set yrange [*:*]\nset xrange [-0.7:" + std::to_string(n) + "-0.3]\n"
      "plot 'data.dat' using 1:3:($4 > 0.5 ? 0x2e8b57 : 0xcc3333):xtic(2) with boxes lc rgb variable, 1 with lines lw 2 lc rgb 'black'\n";
  return Plot(gnuplot, png, data.str(), script);
}

// Median per case with min..max bars (min/max only where the file keeps the repetitions).
bool TimingsChart(const std::string& gnuplot, const fs::path& png, const Files& files,
                  const std::vector<std::string>& order) {
  std::ostringstream data;
  int n = 0;
  for (const std::string& stem : order) {
    auto it = files.find(stem);
    if (it == files.end()) continue;
    for (const Case& c : it->second.cases) {
      if (c.error || !std::isfinite(c.MedianMs())) continue;
      const double med = c.MedianMs();
      data << n++ << " " << Quote(c.name) << " " << med << " " << c.MinMs().value_or(med) << " "
           << c.MaxMs().value_or(med) << "\n";
    }
  }
  if (n == 0) return false;
  const std::string script =
      "set title 'Median time per benchmark case (bars: min..max over repetitions)'\n"
      "set logscale y\nset grid ytics\nset style fill solid 0.7\nset boxwidth 0.6\n"
      "set xtics rotate by -35 font ',8'\nset key off\nset ylabel 'ms'\nset bmargin 9\n"
      "set xrange [-0.7:" + std::to_string(n) + "-0.3]\n"
      "plot 'data.dat' using 1:3:xtic(2) with boxes lc rgb '#4682b4', '' using 1:3:4:5 with yerrorbars lc rgb 'black' ps 0\n";
  return Plot(gnuplot, png, data.str(), script);
}

// bench/scale: seconds per stage (stacked, one bar per run) and the sampled RSS of each run over
// time against 3x the scene file (where in a run the memory goes).
bool ScaleChart(const std::string& gnuplot, const fs::path& png, const json& scale) {
  if (!scale.is_object() || !scale.contains("runs")) return false;
  std::vector<std::string> stages;
  for (const json& r : scale["runs"]) {
    const json ts = r.value("timings_s", json::object());  // named: items() must not outlive it
    for (const auto& [k, v] : ts.items())
      if (k.find("total") == std::string::npos && v.is_number() &&
          std::find(stages.begin(), stages.end(), k) == stages.end())
        stages.push_back(k);
  }
  if (stages.empty()) return false;
  // Block 0: the stage table; blocks 1..: one RSS timeline per run (gnuplot "index").
  std::ostringstream data;
  data << "run";
  for (const auto& s : stages) data << " " << s;
  data << "\n";
  std::vector<std::string> labels;
  for (const json& r : scale["runs"]) {
    std::string label = r.value("stage", std::string("?"));
    if (r.contains("solver")) label += " " + r["solver"].get<std::string>();
    labels.push_back(label);
    data << Quote(label);
    const json ts = r.value("timings_s", json::object());
    for (const auto& s : stages) data << " " << (ts.contains(s) && ts[s].is_number() ? ts[s].get<double>() : 0.0);
    data << "\n";
  }
  std::string titles;
  for (const json& r : scale["runs"]) {
    data << "\n\n";
    const json tl = r.value("rss_timeline_s_mib", json::array());
    if (tl.empty()) data << "0 0\n";
    for (const json& p : tl) data << p[0].get<double>() << " " << p[1].get<double>() << "\n";
  }
  for (std::string l : labels) {  // word() splits on spaces: "refine bk" -> "refine_bk"
    std::replace(l.begin(), l.end(), ' ', '_');
    titles += (titles.empty() ? "" : " ") + l;
  }
  const double limit = 3 * scale.value("scene_file_mib", NAN);
  std::ostringstream script;
  // 18 distinct colours so stacked stages (synth + refine + eval: 16 today) never share one.
  const char* colours[] = {"#4682b4", "#e69f00", "#009e73", "#cc3333", "#9467bd", "#8c564b",
                           "#e377c2", "#7f7f7f", "#bcbd22", "#17becf", "#000000", "#f0e442",
                           "#1f3b73", "#ff7f0e", "#98df8a", "#c5b0d5", "#7b4173", "#ad494a"};
  for (int i = 0; i < 18; ++i) script << "set linetype " << i + 1 << " lc rgb '" << colours[i] << "'\n";
  script << "set linetype cycle 18\n"
         << "set multiplot layout 1,2 title 'bench/scale: " << scale.value("scene", std::string("3M scene")) << "'\n"
         << "set style data histograms\nset style histogram rowstacked\nset style fill solid 0.85\n"
         << "set boxwidth 0.6\nset grid ytics\nset key outside bottom horizontal font ',8'\n"
         << "set title 'seconds per stage (report.json timings_s)'\nset ylabel 's'\n"
         << "plot for [c=2:" << 1 + stages.size() << "] 'data.dat' index 0 using c:xtic(1) title columnheader(c)\n"
         << "set style data lines\nset title 'sampled RSS (red: 3× scene file)'\nset ylabel 'MiB'\n"
         << "set xlabel 's since start'\nset yrange [0:*]\nset key inside bottom right font ',8'\n"
         << "names = \"" << titles << "\"\n"
         << "plot for [i=1:" << labels.size() << "] 'data.dat' index i using 1:2 lw 2 title word(names, i), "
         << (std::isfinite(limit) ? limit : 0) << " lw 2 lc rgb '#cc3333' dt 2 title '3x file'\n"
         << "unset multiplot\n";
  return Plot(gnuplot, png, data.str(), script.str());
}

// ---------------------------------------------------------------------------------------------

std::string MetText(const std::optional<bool>& met) {
  if (!met) return "n/a";
  return *met ? "met" : "**not met**";
}

std::string MachineLine(const json& run, const Files& files) {
  std::ostringstream o;
  o << run.value("cpu_model", std::string("unknown CPU")) << ", " << run.value("cores", 0) << " cores";
  for (const auto& [stem, f] : files) {
    if (f.context.contains("mhz_per_cpu")) o << " (" << f.context["mhz_per_cpu"] << " MHz)";
    if (f.context.contains("load_avg") && f.context["load_avg"].is_array() && !f.context["load_avg"].empty())
      o << ", load average " << Fmt(f.context["load_avg"][0].get<double>(), 2) << " when " << stem
        << " started";
    break;
  }
  o << "; " << run.value("date_utc", std::string("?")) << "; commit `" << run.value("commit", std::string("?"))
    << "`; " << (run.value("quick", false) ? "**quick** run" : "full run") << " (`"
    << run.value("benchmark_args", std::string()) << "`)";
  return o.str();
}

void ScaleSection(std::ostream& md, const json& scale, const std::string& chart) {
  md << "## Scale: " << scale.value("scene", std::string("3M-Gaussian scene")) << " (`bench/scale`)\n\n";
  if (scale.contains("machine")) md << "Machine: " << scale["machine"].get<std::string>() << ".\n";
  md << "Scene file: " << Fmt(scale.value("scene_file_mib", NAN)) << " MiB (`"
     << scale.value("synth_command", std::string()) << "`).\n\n";
  md << "| command | exit | wall s | peak RSS MiB | RSS / file | seconds per stage (report.json timings_s) | "
        "highest sampled RSS per stage, MiB |\n"
     << "|---|---|---|---|---|---|---|\n";
  const double file_mib = scale.value("scene_file_mib", NAN);
  for (const json& r : scale.value("runs", json::array())) {
    std::string label = r.value("stage", std::string("?"));
    if (r.contains("solver")) label += " (" + r["solver"].get<std::string>() + ")";
    std::string stages;
    const json ts = r.value("timings_s", json::object());
    for (const auto& [k, v] : ts.items())
      if (v.is_number()) stages += (stages.empty() ? "" : ", ") + k + " " + Fmt(v.get<double>());
    // [[stage, MiB], ...] in pipeline order (bench_scale_collect; only sequential commands).
    std::string by_stage;
    for (const json& p : r.value("rss_by_stage_mib", json::array()))
      if (p.is_array() && p.size() == 2 && p[1].is_number())
        by_stage += (by_stage.empty() ? "" : ", ") + p[0].get<std::string>() + " " + Fmt(p[1].get<double>());
    const double rss = r.value("peak_rss_mib", NAN);
    md << "| " << label << " | " << r.value("exit_code", -1) << " | " << Fmt(r.value("wall_s", NAN)) << " | "
       << Fmt(rss) << " | " << Fmt(rss / file_mib) << " | " << (stages.empty() ? "–" : stages) << " | "
       << (by_stage.empty() ? "–" : by_stage) << " |\n";
  }
  for (const json& note : scale.value("notes", json::array())) md << "\n- " << note.get<std::string>();
  md << "\n\n";
  if (!chart.empty()) md << "![scale](" << chart << ")\n\n";
}

// Feature rendering (render_bench BM_RenderFeature/w:W/d:D): ms per view against the RGB-only
// render of the same size in the same run (d:0), and the one-off per-scene preparation.
void FeatureSection(std::ostream& md, const Files& files) {
  auto it = files.find("render_bench");
  if (it == files.end()) return;
  std::vector<const Case*> rows;
  for (const Case& c : it->second.cases)
    if (!c.error && c.name.rfind("BM_RenderFeature/", 0) == 0) rows.push_back(&c);
  if (rows.empty()) return;
  md << "## Feature rendering (render_bench)\n\n"
     << "Per-Gaussian semantic features composited with the RGB blend weights in the same pass\n"
     << "(`RenderOptions::features`, docs/rendering.md), 1M-Gaussian scene, 2 threads. D > 64 is projected\n"
     << "on its 64 leading principal axes once per scene (\"prepare\", not per view). Baseline: the\n"
     << "RGB-only render of the same size in the same run.\n\n"
     << "| size | D (rendered) | ms per view | RGB only, ms | ratio | composite s (RGB only) | prepare s (once) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const Case* c : rows) {
    const double dim = c->Counter("input_dim").value_or(0);
    if (dim == 0) continue;
    const std::string size = Fmt(c->Counter("width").value_or(NAN)) + "×" + Fmt(c->Counter("height").value_or(NAN));
    const std::string w = c->name.substr(0, c->name.find("/d:"));
    const Case* base = Lookup(files, "render_bench", w + "/d:0");
    md << "| " << size << " | " << Fmt(dim) << " (" << Fmt(c->Counter("rendered_channels").value_or(NAN)) << ") | "
       << Fmt(c->MedianMs()) << " | " << (base ? Fmt(base->MedianMs()) : "–") << " | "
       << (base ? Fmt(c->MedianMs() / base->MedianMs()) + "×" : "–") << " | "
       << Fmt(c->Counter("seconds_composite").value_or(NAN))
       << (base ? " (" + Fmt(base->Counter("seconds_composite").value_or(NAN)) + ")" : "") << " | "
       << Fmt(c->Counter("prepare_seconds").value_or(NAN)) << " |\n";
  }
  if (const Case* inc = Lookup(files, "render_bench", "BM_RenderIncrementalFeature/d:16"))
    if (const Case* plain = Lookup(files, "render_bench", "BM_RenderIncremental/2"))
      md << "\nIncremental \"after\" render, 1280×720, D = 16: " << Fmt(inc->MedianMs()) << " ms (RGB only "
         << Fmt(plain->MedianMs()) << " ms, " << Fmt(inc->MedianMs() / plain->MedianMs()) << "×).\n";
  md << "\n";
}

int Main(int argc, char** argv) {
  fs::path results = "bench/results", out = "docs/benchmarks.md", charts = "docs/benchmarks";
  std::string gnuplot = "gnuplot";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw al::Error("bench_report: " + a + " needs a value", al::ExitCode::kUsage);
      return argv[++i];
    };
    if (a == "--results") results = value();
    else if (a == "--out") out = value();
    else if (a == "--charts") charts = value();
    else if (a == "--gnuplot") gnuplot = value();
    else if (a == "-h" || a == "--help") {
      std::cout << "bench_report --results DIR --out FILE.md --charts DIR [--gnuplot PATH]\n";
      return 0;
    } else {
      throw al::Error("bench_report: unknown argument '" + a + "'", al::ExitCode::kUsage);
    }
  }
  const json run = ReadJson(results / "run.json");
  Files files;
  std::vector<std::string> order;
  for (const json& r : run.value("runs", json::array())) {
    const std::string stem = r.value("name", std::string());
    const fs::path p = results / (stem + ".json");
    if (r.value("exit_code", 1) == 0 && fs::exists(p)) {
      files[stem] = ReadBenchFile(p);
      order.push_back(stem);
    }
  }
  json scale;
  if (fs::exists(results / "scale_3m.json")) scale = ReadJson(results / "scale_3m.json");

  const std::vector<Target> targets = ComputeTargets(files, scale);
  al::EnsureDirectory(charts);
  const std::string rel = charts.filename().string();
  const bool have_targets_png = TargetsChart(gnuplot, charts / "targets.png", targets);
  const bool have_timings_png = TimingsChart(gnuplot, charts / "timings.png", files, order);
  const bool have_scale_png = ScaleChart(gnuplot, charts / "scale_3m.png", scale);

  std::ostringstream md;
  md << "# Benchmarks\n\n"
     << "Generated by `bench/run` (tool: `bench/report_tool.cpp`) from `bench/results/*.json`; do not\n"
     << "edit by hand. Re-run with `./al bench` (or `bench/run [--quick]`). Medians over repetitions;\n"
     << "every ratio is against a baseline measured in the same run. The machine is shared and noisy:\n"
     << "treat single-digit-percent differences as noise.\n\n"
     << "**Machine:** " << MachineLine(run, files) << ".\n\n";

  md << "## Targets (SPEC §8)\n\n"
     << "| what | measured (median) | baseline (same run) | ratio | target | status |\n"
     << "|---|---|---|---|---|---|\n";
  for (const Target& t : targets)
    md << "| " << t.what << " | " << t.measured << " | " << (t.baseline.empty() ? "–" : t.baseline) << " | "
       << (t.ratio.empty() ? "–" : t.ratio) << " | " << t.target << " | " << MetText(t.met) << " |\n";
  md << "\n";
  if (have_targets_png) md << "![targets](" << rel << "/targets.png)\n\n";
  FeatureSection(md, files);

  md << "## Per benchmark\n\n"
     << "Times in ms. min/max are over the repetitions; \"–\" where the benchmark keeps only\n"
     << "aggregates (`ReportAggregatesOnly`), then cv (stddev/mean) shows the spread. Counters are medians.\n\n";
  for (const json& r : run.value("runs", json::array())) {
    const std::string stem = r.value("name", std::string());
    md << "### " << stem << "\n\n";
    auto it = files.find(stem);
    if (it == files.end()) {
      md << "**Failed** in this run (exit code " << r.value("exit_code", -1) << "); no results.\n\n";
      continue;
    }
    std::string load;
    if (const json& ctx = it->second.context; ctx.contains("load_avg") && ctx["load_avg"].is_array() &&
                                              !ctx["load_avg"].empty() && ctx["load_avg"][0].is_number())
      load = " (load average " + Fmt(ctx["load_avg"][0].get<double>(), 2) + " at its start)";
    md << "Run time " << r.value("seconds", 0) << " s" << load << ". Source: `bench/" << stem << ".cpp`, results: `bench/results/"
       << stem << ".json`.\n\n"
       << "| case | median | min | max | cv | reps | counters (median) |\n|---|---|---|---|---|---|---|\n";
    for (const Case& c : it->second.cases) {
      if (c.error) {
        md << "| " << c.name << " | **error**: " << c.error_message << " | | | | | |\n";
        continue;
      }
      md << "| " << c.name << " | " << Fmt(c.MedianMs()) << " | " << FmtOpt(c.MinMs()) << " | " << FmtOpt(c.MaxMs())
         << " | " << (c.CvPercent() ? Fmt(*c.CvPercent(), 2) + " %" : "–") << " | " << c.Repetitions() << " | "
         << CounterList(c) << " |\n";
    }
    md << "\n";
  }
  if (have_timings_png) md << "![timings](" << rel << "/timings.png)\n\n";

  if (scale.is_object() && !scale.empty()) ScaleSection(md, scale, have_scale_png ? rel + "/scale_3m.png" : "");
  else md << "## Scale\n\nNo `bench/results/scale_3m.json` yet: run `bench/scale`.\n\n";
  if (!have_targets_png && !have_timings_png)
    md << "(Charts not drawn: gnuplot unavailable or failed, see the bench/run output.)\n";

  al::WriteFileAtomically(out, md.str());
  std::cout << "bench_report: wrote " << out.string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return al::bench::RunTool("bench_report", [&] { return Main(argc, argv); });
}
