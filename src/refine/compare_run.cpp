// RunCompare (al/refine/compare.hpp): the `compare` subcommand as one library call.
#include <cstdio>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/graph/problem_io.hpp"
#include "al/io/npy.hpp"
#include "al/refine/compare.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

OutputSetOptions CompareSetOptions(const RefineOptions& o) {
  OutputSetOptions so = RefineOutputSetOptions(o);
  so.command = "compare";
  so.planned = {"compare.csv", "compare.json", "tradeoff.png", "tradeoff.dat", "report.json"};
  return so;
}

OutputSetOptions CompareExportSetOptions(const RefineOptions& o) {
  OutputSetOptions so("export-problem", RefineOutputSetOptions(o).inputs);
  so.flag = "--export-problem";
  return so;
}

// The problem once, then one p per run (p_<id>.npy) and solutions.json naming them.
void ExportAll(const RefineOptions& o, const GraphResult& graph, const CompareResult& r) {
  OutputSet set(o.export_problem_dir, CompareExportSetOptions(o));
  const fs::path dir = set.dir();
  ExportProblem(graph.problem, nullptr, dir.string(), graph.stats.lambda);
  nlohmann::json sol = nlohmann::json::array();
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const std::string file = "p_" + r.runs[i].id + ".npy";
    WriteNpy((dir / file).string(), r.p[i], {static_cast<std::int64_t>(r.p[i].size())});
    sol.push_back({{"id", r.runs[i].id}, {"solver", r.runs[i].solver}, {"options", r.runs[i].options},
                   {"objective", r.rows[i]["objective"]}, {"file", file}});
  }
  WriteFileAtomically(dir / "solutions.json", sol.dump(2) + "\n");
  set.Commit(NewReport("compare --export-problem"));
}

// report.json's params: the inputs, the graph and decision tables' fields, the comparison's own.
nlohmann::json CompareParams(const RefineOptions& o, const RefineInputs& in, const CompareOptions& co) {
  nlohmann::json params = {
      {"scene", o.scene}, {"removed", o.removed},
      {"removed_is", in.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
      {"method", o.method}, {"preset", in.preset.ToJson()}, {"features", in.feature_spec},
      {"feature_source", in.feature_source}, {"colour_fallback", in.colour_fallback},
      {"decoder", o.decoder}, {"solvers", co.solvers}, {"grid", SolverGridToString(co.grid)},
      {"solver_options", co.solver_options}, {"reference", co.reference ? "exact" : "none"},
      {"labels", o.labels}, {"max_unmatched", o.max_unmatched}, {"match_tol", o.match_tol},
      {"prompt_embeddings", o.prompt_embeddings}, {"positive", o.positives},
      {"fgs_threshold", o.fgs_threshold}, {"out", o.out_dir}, {"export_problem", o.export_problem_dir}};
  params.update(GraphOptions::Table().ToJson(o.graph));
  params.update(DecisionOptions::Table().ToJson(o.decision));
  return params;
}

void FillCompareReport(const RefineOptions& o, const RefineInputs& in, const CompareOptions& co,
                       const GraphResult& graph, const CompareResult& r, nlohmann::json& report) {
  report["status"] = r.empty_graph ? "empty_graph" : "ok";
  report["params"] = CompareParams(o, in, co);
  report["grid"] = nlohmann::json::object();
  for (const auto& [key, values] : co.grid) report["grid"][key] = values;
  report["runs"] = nlohmann::json::array();
  for (const auto& run : r.runs)
    report["runs"].push_back({{"id", run.id}, {"solver", run.solver}, {"options", run.options},
                              {"reference_only", run.reference}});
  report["counts"] = {{"num_gaussians", in.scene->size()}, {"removed_input", in.removal.num_removed},
                      {"candidates", graph.stats.nodes},   {"edges", graph.stats.edges},
                      {"solver_runs", r.rows.size()},      {"excluded_nonfinite", graph.stats.excluded_nonfinite}};
  report["removed_set"] = in.removal.stats;
  report["graph"] = graph.stats.ToJson();
  report["rows"] = r.rows;
  report["reference_objective"] = r.reference_objective ? nlohmann::json(*r.reference_objective) : nlohmann::json();
  report["gap_reason"] = r.gap_reason.empty() ? nlohmann::json() : nlohmann::json(r.gap_reason);
  if (!r.gt_before.is_null()) report["gt_before"] = r.gt_before;
  report["message"] = r.message;
}

std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

void CompareOptions::Check() const { PlanSolverRuns(*this); }

CompareRunResult RunCompare(const RefineOptions& o, const CompareOptions& co) {
  Timer total;
  if (o.out_dir.empty()) throw Error("--out is required", ExitCode::kUsage);
  o.Check();
  co.Check();  // usage errors before loading anything
  OutputSet set(o.out_dir, CompareSetOptions(o));
  if (!o.export_problem_dir.empty()) OutputSet preflight(o.export_problem_dir, CompareExportSetOptions(o));
  CompareRunResult out;
  nlohmann::json& report = out.report;
  report = NewReport("compare");
  RefineInputs in = LoadRefineInputs(o, report);
  Timer t;
  const GraphResult graph = BuildGraphFor(in, o.graph);
  report["timings_s"]["graph"] = t.Seconds();
  if (o.on_stage) o.on_stage("graph", t.Seconds());
  for (const auto& w : graph.warnings) report["warnings"].push_back(w);
  t.Reset();
  out.compare = CompareSolvers(in, graph, o.graph, co);
  const CompareResult& r = out.compare;
  report["timings_s"]["solvers"] = t.Seconds();
  for (const auto& w : r.warnings) report["warnings"].push_back(w);
  t.Reset();
  WriteCompareTables(set.dir(), r);
  const nlohmann::json chart =
      r.empty_graph ? nlohmann::json{{"drawn", false}, {"message", "empty graph"}} : WriteCompareChart(set.dir(), r);
  out.chart_drawn = chart["drawn"].get<bool>();
  if (!out.chart_drawn) report["warnings"].push_back("tradeoff.png not drawn: " + chart["message"].get<std::string>());
  if (!o.export_problem_dir.empty()) ExportAll(o, graph, r);
  report["timings_s"]["write"] = t.Seconds();
  FillCompareReport(o, in, co, graph, r, report);
  report["chart"] = chart;
  report["timings_s"]["total"] = total.Seconds();
  set.Commit(report);
  out.out_dir = set.out().string();
  out.exit_code = r.empty_graph ? static_cast<int>(ExitCode::kEmptyGraph) : 0;
  return out;
}

std::string CompareRunResult::BriefReport() const {
  if (compare.empty_graph) return compare.message + "\n";
  std::string text;
  char line[256];
  std::snprintf(line, sizeof line, "%-8s %-6s %10s %18s %10s %8s %8s\n", "run", "solver", "seconds", "objective",
                "gap", "added", "F1");
  text += line;
  for (const auto& row : compare.rows) {
    const std::string gap = row["gap"].is_null() ? "-" : Short(row["gap"].get<double>());
    const std::string f1 = row.contains("gt") ? Short(row["gt"]["f1"].get<double>()) : "-";
    std::snprintf(line, sizeof line, "%-8s %-6s %10.3f %18.9g %10s %8zu %8s\n", row["id"].get<std::string>().c_str(),
                  row["solver"].get<std::string>().c_str(), row["seconds"].get<double>(),
                  row["objective"].get<double>(), gap.c_str(), row["added"].get<std::size_t>(), f1.c_str());
    text += line;
  }
  return text + "wrote " + (fs::path(out_dir) / "compare.csv").string() + ", compare.json, " +
         (chart_drawn ? "tradeoff.png, " : "") + "report.json\n";
}

}  // namespace al
