// results.csv and the sweep charts (al/refine/sweep.hpp): pareto.png (run time against error,
// Pareto front) and heatmap_f1_<solver>.png (F1 over k × δ, one panel per λ), drawn by gnuplot
// from data files kept beside them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "al/core/atomic_file.hpp"
#include "al/core/chart.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

std::string Fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

bool HasF1(const nlohmann::json& r) { return r.contains("gt") && r["gt"]["after"].contains("f1"); }
double F1(const nlohmann::json& r) { return r["gt"]["after"]["f1"].get<double>(); }
double RunSeconds(const nlohmann::json& r) {
  // What the setting costs run on its own: its graph build plus its solve.
  const auto& s = r.value("seconds", nlohmann::json::object());
  return s.value("graph", 0.0) + s.value("solve", 0.0);
}

// A setting: the parameters without the scene (records of many scenes are averaged).
using Setting = std::tuple<int, double, int, double, double, std::string, std::string, double>;
Setting SettingOf(const nlohmann::json& r) {
  const auto& p = r["params"];
  return {p["k"].get<int>(), p["delta"].get<double>(), p["hops"].get<int>(), p["radius_scale"].get<double>(),
          p["lambda"].get<double>(), p["solver"].get<std::string>(), p["threshold"].get<std::string>(),
          p.value("segment_share", 0.0)};
}

std::string Label(const Setting& s) {
  return "k=" + std::to_string(std::get<0>(s)) + " d=" + Fmt(std::get<1>(s)) +
         (std::get<2>(s) != 1 ? " h=" + std::to_string(std::get<2>(s)) : "") + " l=" + Fmt(std::get<4>(s));
}

// pareto.png: each setting's mean run time (graph + solve) against its mean error 1 − F1 over the
// scenes, one point style per solver, and the Pareto front (no other setting is both faster and
// more accurate).
void Pareto(const fs::path& dir, const std::vector<ParetoPoint>& points, nlohmann::json& out) {
  if (points.empty()) {
    out["skipped_charts"].push_back({{"name", "pareto.png"}, {"reason", "no record has ground-truth F1 (give --labels)"}});
    return;
  }
  std::vector<std::string> solvers;
  for (const auto& p : points)
    if (std::find(solvers.begin(), solvers.end(), p.solver) == solvers.end()) solvers.push_back(p.solver);
  std::ostringstream data;
  data << "# seconds(mean graph+solve) error(mean 1-F1) solver_index label\n";
  for (std::size_t si = 0; si < solvers.size(); ++si) {
    data << "# solver " << solvers[si] << "\n";
    for (const auto& p : points)
      if (p.solver == solvers[si]) data << Fmt(p.seconds) << " " << Fmt(p.error) << " " << si << " \"" << p.label << "\"\n";
    data << "\n\n";
  }
  std::vector<const ParetoPoint*> front;
  for (const auto& p : points)
    if (p.on_front) front.push_back(&p);
  std::sort(front.begin(), front.end(), [](const auto* a, const auto* b) { return a->seconds < b->seconds; });
  std::ostringstream front_data;
  front_data << "# Pareto front: seconds error\n";
  for (const auto* p : front) front_data << Fmt(p->seconds) << " " << Fmt(p->error) << "\n";
  WriteFileAtomically(dir / "pareto.dat", data.str());
  WriteFileAtomically(dir / "pareto_front.dat", front_data.str());
  std::ostringstream gp;
  gp << "set terminal png size 900,600\nset output 'pareto.png'\n"
     << "set title 'Run time against error (mean over scenes; graph build + solve)'\n"
     << "set xlabel 'seconds (graph + solve)'\nset ylabel 'error = 1 - F1 vs ground truth'\n"
     << "set logscale x\nset grid\nset key outside right\n"
     << "plot ";
  for (std::size_t si = 0; si < solvers.size(); ++si)
    gp << "'pareto.dat' index " << si << " using 1:2 with points pt " << (5 + 2 * si) << " ps 1.5 title "
       << GnuplotQuote(solvers[si]) << ", ";
  gp << "'pareto_front.dat' using 1:2 with steps lw 2 lc rgb 'black' title 'Pareto front'\n";
  const ChartResult c = DrawChart(dir / "pareto.png", gp.str());
  if (c.drawn) out["charts"].push_back("pareto.png");
  else out["skipped_charts"].push_back({{"name", "pareto.png"}, {"reason", c.message}});
}

// heatmap_f1_<solver>.png: per λ a panel of F1 over k × δ; each cell is the mean over scenes of
// the best F1 over the remaining axes (hops, radius_scale, threshold, segment_share).
void Heatmaps(const fs::path& dir, const std::vector<nlohmann::json>& records, nlohmann::json& out) {
  // (solver, λ, k, δ) -> scene -> best F1
  std::map<std::tuple<std::string, double, int, double>, std::map<std::string, double>> cells;
  for (const auto& r : records) {
    if (!HasF1(r)) continue;
    const auto& p = r["params"];
    auto& best = cells[{p["solver"].get<std::string>(), p["lambda"].get<double>(), p["k"].get<int>(),
                        p["delta"].get<double>()}];
    const std::string scene = r.value("scene", "");
    auto it = best.find(scene);
    if (it == best.end()) best[scene] = F1(r);
    else it->second = std::max(it->second, F1(r));
  }
  if (cells.empty()) {
    out["skipped_charts"].push_back({{"name", "heatmap_f1_*.png"}, {"reason", "no record has ground-truth F1 (give --labels)"}});
    return;
  }
  std::set<std::string> solvers;
  for (const auto& [key, v] : cells) solvers.insert(std::get<0>(key));
  for (const std::string& solver : solvers) {
    std::set<double> lambdas, deltas;
    std::set<int> ks;
    for (const auto& [key, v] : cells)
      if (std::get<0>(key) == solver) {
        lambdas.insert(std::get<1>(key));
        ks.insert(std::get<2>(key));
        deltas.insert(std::get<3>(key));
      }
    const std::vector<int> kv(ks.begin(), ks.end());
    const std::vector<double> dv(deltas.begin(), deltas.end());
    auto index_of = [](const auto& v, const auto& x) { return std::find(v.begin(), v.end(), x) - v.begin(); };
    const std::string stem = "heatmap_f1_" + solver;
    std::ostringstream data;
    data << "# per lambda block: k_index delta_index f1(mean over scenes of the best over other axes) k delta\n";
    for (double l : lambdas) {
      data << "# lambda " << Fmt(l) << "\n";
      for (const auto& [key, by_scene] : cells) {
        if (std::get<0>(key) != solver || std::get<1>(key) != l) continue;
        double sum = 0;
        for (const auto& [scene, f1] : by_scene) sum += f1;
        data << index_of(kv, std::get<2>(key)) << " " << index_of(dv, std::get<3>(key)) << " "
             << Fmt(sum / by_scene.size()) << " " << std::get<2>(key) << " " << Fmt(std::get<3>(key)) << "\n";
      }
      data << "\n\n";
    }
    WriteFileAtomically(dir / (stem + ".dat"), data.str());
    std::ostringstream gp;
    gp << "set terminal png size " << std::max<std::size_t>(420, 380 * lambdas.size()) << ",400\n"
       << "set output '" << stem << ".png'\n"
       << "set multiplot layout 1," << lambdas.size() << " title "
       << GnuplotQuote("F1 after refinement (" + solver + "), mean over scenes, best over other axes") << "\n"
       << "set palette defined (0 '#b2182b', 0.5 '#f7f7f7', 1 '#1a9850')\nset cbrange [0:1]\n"
       << "set xrange [-0.5:" << kv.size() - 0.5 << "]\nset yrange [-0.5:" << dv.size() - 0.5 << "]\n"
       << "set xlabel 'k'\nset ylabel 'delta'\nunset key\n";
    gp << "set xtics (";
    for (std::size_t i = 0; i < kv.size(); ++i) gp << (i ? ", " : "") << "'" << kv[i] << "' " << i;
    gp << ")\nset ytics (";
    for (std::size_t i = 0; i < dv.size(); ++i) gp << (i ? ", " : "") << "'" << Fmt(dv[i]) << "' " << i;
    gp << ")\n";
    std::size_t block = 0;
    for (double l : lambdas) {
      gp << "set title " << GnuplotQuote("lambda = " + Fmt(l)) << "\n"
         << "plot '" << stem << ".dat' index " << block << " using 1:2:(0.5):(0.5):3 with boxxyerror fs solid "
         << "fc palette, '' index " << block << " using 1:2:(sprintf('%.3f', $3)) with labels\n";
      ++block;
    }
    gp << "unset multiplot\n";
    const ChartResult c = DrawChart(dir / (stem + ".png"), gp.str());
    if (c.drawn) out["charts"].push_back(stem + ".png");
    else out["skipped_charts"].push_back({{"name", stem + ".png"}, {"reason", c.message}});
  }
}

}  // namespace

std::vector<ParetoPoint> ParetoPoints(const std::vector<nlohmann::json>& records) {
  struct Acc { double seconds = 0, error = 0; int n = 0; nlohmann::json params; };
  std::map<Setting, Acc> acc;
  for (const auto& r : records) {
    if (!HasF1(r)) continue;
    Acc& a = acc[SettingOf(r)];
    a.seconds += RunSeconds(r);
    a.error += 1.0 - F1(r);
    ++a.n;
    a.params = r["params"];
  }
  std::vector<ParetoPoint> points;
  for (const auto& [s, a] : acc)
    points.push_back({std::get<5>(s), Label(s), a.params, std::max(a.seconds / a.n, 1e-6), a.error / a.n, a.n, false});
  // On the front: no other setting is at least as fast and strictly more accurate, or faster and as accurate.
  for (auto& p : points)
    p.on_front = std::none_of(points.begin(), points.end(), [&](const ParetoPoint& q) {
      return (q.seconds <= p.seconds && q.error < p.error) || (q.seconds < p.seconds && q.error <= p.error);
    });
  return points;
}

nlohmann::json WriteSweepSummaries(const std::string& dir_text, const std::vector<nlohmann::json>& records,
                                   bool charts) {
  const fs::path dir(dir_text);
  nlohmann::json out = {{"csv", "results.csv"}, {"charts", nlohmann::json::array()},
                        {"skipped_charts", nlohmann::json::array()}};
  WriteFileAtomically(dir / "results.csv", ResultsCsv(records));
  if (charts) {
    Pareto(dir, ParetoPoints(records), out);
    Heatmaps(dir, records, out);
  }
  WriteFileAtomically(dir / "report.html", SweepReportHtml(records, out));
  out["html"] = "report.html";
  return out;
}

}  // namespace al
