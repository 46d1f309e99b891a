// Output files of a solver comparison (al/refine/compare.hpp): compare.csv, compare.json and the
// run-time/error chart tradeoff.png (gnuplot; script and data kept beside it).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/chart.hpp"
#include "al/refine/compare.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

// The chart's log axes need a positive error; gaps at or below this (exact itself, rounding) sit on
// the floor line, which the chart labels.
constexpr double kGapFloor = 1e-12;

std::string Fmt(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_float()) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.12g", v.get<double>());
    return buf;
  }
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

std::string CsvQuote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

nlohmann::json Get(const nlohmann::json& j, const char* a, const char* b = nullptr) {
  if (!j.contains(a)) return nullptr;
  if (!b) return j[a];
  return j[a].contains(b) ? j[a][b] : nlohmann::json();
}

bool HasGt(const CompareResult& r) {
  return !r.rows.empty() && r.rows.front().contains("gt");
}

}  // namespace

void WriteCompareTables(const fs::path& dir, const CompareResult& r) {
  static const char* kGt[] = {"f1", "f1_w", "precision", "recall", "iou"};
  std::ostringstream csv;
  csv << "id,solver,options,reference_only,seconds,wall_seconds,objective,gap,iterations,converged,"
         "components,rule,threshold,added,restored,held_back,refined_count,f1,f1_w,precision,recall,iou\n";
  for (const auto& row : r.rows) {
    csv << row["id"].get<std::string>() << ',' << row["solver"].get<std::string>() << ','
        << CsvQuote(row["options"].dump()) << ',' << Fmt(row["reference_only"]) << ','
        << Fmt(row["seconds"]) << ',' << Fmt(row["wall_seconds"]) << ',' << Fmt(row["objective"]) << ','
        << Fmt(row["gap"]) << ',' << Fmt(row["iterations"]) << ',' << Fmt(row["converged"]) << ','
        << Fmt(Get(row, "components")) << ',' << CsvQuote(Fmt(Get(row, "decision", "rule"))) << ','
        << Fmt(Get(row, "decision", "threshold")) << ',' << Fmt(row["added"]) << ','
        << Fmt(row["restored"]) << ',' << Fmt(Get(row, "decision", "held_back")) << ','
        << Fmt(row["refined_count"]);
    for (const char* k : kGt) csv << ',' << Fmt(row.contains("gt") ? Get(row["gt"], k) : nlohmann::json());
    csv << '\n';
  }
  WriteFileAtomically(dir / "compare.csv", csv.str());
  nlohmann::json j = {{"rows", r.rows},
                      {"reference_objective", r.reference_objective ? nlohmann::json(*r.reference_objective)
                                                                    : nlohmann::json()},
                      {"gap_reason", r.gap_reason.empty() ? nlohmann::json() : nlohmann::json(r.gap_reason)},
                      {"gt_before", r.gt_before}};
  WriteFileAtomically(dir / "compare.json", j.dump(2) + "\n");
}

nlohmann::json WriteCompareChart(const fs::path& dir, const CompareResult& r) {
  const bool gaps = r.reference_objective.has_value();
  const bool f1 = HasGt(r);
  if (r.rows.empty() || (!gaps && !f1))
    return {{"drawn", false}, {"message", r.rows.empty() ? "no solver ran"
                                                         : "nothing to plot: no gap (no exact reference) "
                                                           "and no F1 (no --labels)"}};
  // One data block per solver (gnuplot `index`), in order of first appearance; columns:
  // id seconds gap_for_log_axis error(1 − F1).
  std::vector<std::string> solvers;
  for (const auto& row : r.rows)
    if (std::find(solvers.begin(), solvers.end(), row["solver"]) == solvers.end())
      solvers.push_back(row["solver"]);
  std::ostringstream dat;
  dat << "# id seconds gap(floored at " << kGapFloor << ") 1-F1\n";
  for (std::size_t s = 0; s < solvers.size(); ++s) {
    if (s) dat << "\n\n";
    dat << "# solver " << solvers[s] << "\n";
    for (const auto& row : r.rows) {
      if (row["solver"] != solvers[s]) continue;
      const double gap = gaps ? std::max(std::fabs(row["gap"].get<double>()), kGapFloor) : NAN;
      const double err = f1 ? 1.0 - row["gt"]["f1"].get<double>() : NAN;
      char line[256];
      std::snprintf(line, sizeof line, "%s %.9g %.9g %.9g\n", row["id"].get<std::string>().c_str(),
                    std::max(row["seconds"].get<double>(), 1e-6), gap, err);
      dat << line;
    }
  }
  WriteFileAtomically(dir / "tradeoff.dat", dat.str());

  std::string names;
  for (const auto& s : solvers) names += (names.empty() ? "" : " ") + s;
  const int panels = int(gaps) + int(f1);
  std::ostringstream gp;
  gp << "set terminal png size " << 560 * panels << ",440 noenhanced\n"
     << "set output 'tradeoff.png'\n"
     << "set datafile missing 'nan'\n"
     << "names = " << GnuplotQuote(names) << "\n"
     << "set logscale x\nset grid\nset key top right\nset xlabel 'solver seconds (log)'\n"
     << "set multiplot layout 1," << panels << " title "
     << GnuplotQuote("run time against error on one graph (labels = run id, see compare.csv)") << "\n";
  if (gaps)
    gp << "set logscale y\nset ylabel 'relative objective gap to exact (log, floor " << kGapFloor << ")'\n"
       << "set title 'objective gap'\n"
       << "plot for [i=0:" << solvers.size() - 1 << "] 'tradeoff.dat' index i using 2:3 with points pt 7 ps 1.5 "
       << "title word(names, i+1), 'tradeoff.dat' using 2:3:1 with labels offset 0,1 notitle\n";
  if (f1)
    gp << "unset logscale y\nset ylabel '1 - F1 against ground truth'\nset title 'decision error'\n"
       << "plot for [i=0:" << solvers.size() - 1 << "] 'tradeoff.dat' index i using 2:4 with points pt 7 ps 1.5 "
       << "title word(names, i+1), 'tradeoff.dat' using 2:4:1 with labels offset 0,1 notitle\n";
  gp << "unset multiplot\n";
  const ChartResult c = DrawChart(dir / "tradeoff.png", gp.str());
  return {{"drawn", c.drawn}, {"message", c.message}, {"file", "tradeoff.png"}};
}

}  // namespace al
