// `al-refine compare`: every solver (and a grid of cut-pursuit tolerances) on the same graph, with
// seconds, objective, gap to exact and F1; writes compare.csv/.json, tradeoff.png, report.json.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/graph/problem_io.hpp"
#include "al/io/npy.hpp"
#include "al/refine/compare.hpp"
#include "al/refine/refine.hpp"
#include "al/refine/stages.hpp"
#include "src/cli/command.hpp"
#include "src/cli/refine_flags.hpp"

namespace al::cli {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitCommaList(const std::string& s) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(' ');
    const auto e = item.find_last_not_of(' ');
    if (b == std::string::npos) throw Error("--solvers: empty name in '" + s + "'", ExitCode::kUsage);
    out.push_back(item.substr(b, e - b + 1));
  }
  if (!s.empty() && s.back() == ',') throw Error("--solvers: empty name in '" + s + "'", ExitCode::kUsage);
  return out;
}

std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

class CompareCommand : public Command {
 public:
  std::string Name() const override { return "compare"; }
  std::string Description() const override {
    return "Compare solvers (bk, cp over a tolerance grid, exact) on the same refine graph: seconds, "
           "objective, gap to exact, F1; writes compare.csv/.json, tradeoff.png, report.json";
  }
  void Setup(CLI::App& app) override {
    AddInputFlags(app, flags_);
    AddGraphFlags(app, flags_);
    AddDecisionFlags(app, flags_);
    app.add_option("--solvers", solvers_, "Comma-separated solvers to compare")->default_val("bk,cp,exact");
    app.add_option("--grid", grid_,
                   "Cut-pursuit option grid, KEY=V1,V2;KEY2=... (Cartesian product; default "
                   "\"" + SolverGridToString(DefaultSolverGrid()) + "\", \"none\" = one cp run with "
                   "its defaults)");
    app.add_option("--solver-options", solver_options_,
                   "Per-solver base options as JSON keyed by solver, e.g. {\"exact\":{\"pivot\":\"bisection\"}}");
    app.add_option("--reference", reference_,
                   "exact: run exact for the objective gap even if not in --solvers; none: gaps are null")
        ->check(CLI::IsMember({"exact", "none"}))->default_val("exact");
    app.add_option("--out", flags_.options.out_dir, "Output directory")->required();
    app.add_option("--export-problem", flags_.options.export_problem_dir,
                   "Also write the graph's problem as .npy files (as refine) plus p_<run id>.npy per "
                   "solver run and solutions.json into this directory");
    app.add_flag("--quiet", quiet_, "No progress lines");
  }

  int Run() override {
    Timer total;
    RefineOptions o = ToRefineOptions(flags_);
    CompareOptions co;
    co.solvers = SplitCommaList(solvers_);
    const bool has_cp = std::find(co.solvers.begin(), co.solvers.end(), "cp") != co.solvers.end();
    if (grid_.empty())
      co.grid = has_cp ? DefaultSolverGrid() : SolverGrid{};
    else if (grid_ != "none")
      co.grid = ParseSolverGrid(grid_);
    if (!solver_options_.empty()) {
      try {
        co.solver_options = nlohmann::json::parse(solver_options_);
      } catch (const std::exception&) {
        throw Error("--solver-options: not valid JSON", ExitCode::kUsage);
      }
    }
    co.reference = reference_ == "exact";
    co.decision = o.decision;
    PlanSolverRuns(co);  // usage errors before loading anything
    if (!quiet_) {
      o.on_stage = [](const std::string& stage, double s) {
        if (s > 1.0) std::cerr << "compare  " << stage << "  " << Short(s) << " s\n";
      };
      co.on_run = [](const SolverRun& run, std::size_t i, std::size_t n, const nlohmann::json* row) {
        std::cerr << "compare  [" << i + 1 << "/" << n << "] " << run.id;
        if (!row) {
          std::cerr << " (" << run.solver << " " << run.options.dump() << ") ...\n";
          return;
        }
        std::cerr << "  F = " << (*row)["objective"].get<double>() << "  " << Short((*row)["seconds"].get<double>())
                  << " s  added " << (*row)["added"];
        if (row->contains("gt")) std::cerr << "  F1 " << Short((*row)["gt"]["f1"].get<double>());
        std::cerr << "\n";
      };
    }

    OutputSetOptions so = RefineOutputSetOptions(o);
    so.command = "compare";
    so.planned = {"compare.csv", "compare.json", "tradeoff.png", "tradeoff.dat", "report.json"};
    OutputSet set(o.out_dir, so);
    OutputSetOptions export_options("export-problem", so.inputs);
    export_options.flag = "--export-problem";
    if (!o.export_problem_dir.empty()) OutputSet preflight(o.export_problem_dir, export_options);
    nlohmann::json report = NewReport("compare");
    RefineInputs in = LoadRefineInputs(o, report);
    Timer t;
    const GraphResult graph = BuildGraphFor(in, o.graph);
    report["timings_s"]["graph"] = t.Seconds();
    if (o.on_stage) o.on_stage("graph", t.Seconds());
    for (const auto& w : graph.warnings) report["warnings"].push_back(w);
    if (!quiet_)
      std::cerr << "compare  graph: " << graph.stats.nodes << " nodes, " << graph.stats.edges << " edges\n";

    t.Reset();
    const CompareResult r = CompareSolvers(in, graph, o.graph, co);
    report["timings_s"]["solvers"] = t.Seconds();
    for (const auto& w : r.warnings) report["warnings"].push_back(w);

    const fs::path out = set.dir();
    t.Reset();
    WriteCompareTables(out, r);
    const nlohmann::json chart = r.empty_graph ? nlohmann::json{{"drawn", false}, {"message", "empty graph"}}
                                               : WriteCompareChart(out, r);
    if (!chart["drawn"].get<bool>()) report["warnings"].push_back("tradeoff.png not drawn: " + chart["message"].get<std::string>());
    if (!o.export_problem_dir.empty()) ExportAll(o, graph, r);
    report["timings_s"]["write"] = t.Seconds();

    const GraphOptions& go = o.graph;
    report["status"] = r.empty_graph ? "empty_graph" : "ok";
    report["params"] = {
        {"scene", o.scene}, {"removed", o.removed},
        {"removed_is", in.removed_is == RemovedIs::kRemaining ? "remaining" : "removed"},
        {"method", o.method}, {"preset", in.preset}, {"features", in.feature_spec},
        {"feature_source", in.feature_source}, {"colour_fallback", in.colour_fallback},
        {"decoder", o.decoder}, {"k", go.k}, {"delta", go.delta},
        {"delta_mode", go.delta_mode == DeltaMode::kCosine ? "cosine" : "distance"},
        {"lambda", go.lambda}, {"spatial", go.spatial}, {"hops", go.hops},
        {"radius_scale", go.radius_scale}, {"knn_checks", go.knn_checks},
        {"kl_smoothing", go.kl_smoothing}, {"solvers", co.solvers},
        {"grid", SolverGridToString(co.grid)}, {"solver_options", co.solver_options},
        {"reference", reference_}, {"threshold", o.decision.rule.ToString()},
        {"restore", o.decision.restore}, {"min_segment_share", o.decision.min_segment_share},
        {"labels", o.labels}, {"max_unmatched", o.max_unmatched},
        {"match_tol", o.match_tol}, {"prompt_embeddings", o.prompt_embeddings},
        {"positive", o.positives}, {"fgs_threshold", o.fgs_threshold}, {"out", o.out_dir},
        {"export_problem", o.export_problem_dir}};
    report["grid"] = nlohmann::json::object();
    for (const auto& [key, values] : co.grid) report["grid"][key] = values;
    report["runs"] = nlohmann::json::array();
    for (const auto& run : r.runs)
      report["runs"].push_back({{"id", run.id}, {"solver", run.solver}, {"options", run.options},
                                {"reference_only", run.reference}});
    report["counts"] = {{"num_gaussians", in.scene->size()}, {"removed_input", in.removal.num_removed},
                        {"candidates", graph.stats.nodes}, {"edges", graph.stats.edges},
                        {"solver_runs", r.rows.size()}, {"excluded_nonfinite", graph.stats.excluded_nonfinite}};
    report["removed_set"] = in.removal.stats;
    report["graph"] = GraphStatsToJson(graph.stats);
    report["rows"] = r.rows;
    report["reference_objective"] = r.reference_objective ? nlohmann::json(*r.reference_objective) : nlohmann::json();
    report["gap_reason"] = r.gap_reason.empty() ? nlohmann::json() : nlohmann::json(r.gap_reason);
    if (!r.gt_before.is_null()) report["gt_before"] = r.gt_before;
    report["chart"] = chart;
    report["message"] = r.message;
    report["timings_s"]["total"] = total.Seconds();
    set.Commit(report);

    if (r.empty_graph) {
      std::cerr << r.message << "\n";
      return static_cast<int>(ExitCode::kEmptyGraph);
    }
    PrintTable(r);
    std::cout << "wrote " << (set.out() / "compare.csv").string() << ", compare.json, "
              << (chart["drawn"].get<bool>() ? "tradeoff.png, " : "") << "report.json\n";
    return 0;
  }

 private:
  // The problem once, then one p per run (p_<id>.npy) and solutions.json naming them.
  static void ExportAll(const RefineOptions& o, const GraphResult& graph, const CompareResult& r) {
    OutputSetOptions so("export-problem", RefineOutputSetOptions(o).inputs);
    so.flag = "--export-problem";
    OutputSet set(o.export_problem_dir, so);
    const fs::path dir = set.dir();
    ExportProblem(graph.problem, nullptr, dir.string(), o.graph.lambda);
    nlohmann::json sol = nlohmann::json::array();
    for (std::size_t i = 0; i < r.rows.size(); ++i) {
      const std::string file = "p_" + r.runs[i].id + ".npy";
      WriteNpy((dir / file).string(), r.p[i],
               {static_cast<std::int64_t>(r.p[i].size())});
      sol.push_back({{"id", r.runs[i].id}, {"solver", r.runs[i].solver}, {"options", r.runs[i].options},
                     {"objective", r.rows[i]["objective"]}, {"file", file}});
    }
    WriteFileAtomically(dir / "solutions.json", sol.dump(2) + "\n");
    set.Commit(NewReport("compare --export-problem"));
  }

  static void PrintTable(const CompareResult& r) {
    std::printf("%-8s %-6s %10s %18s %10s %8s %8s\n", "run", "solver", "seconds", "objective", "gap", "added", "F1");
    for (const auto& row : r.rows) {
      const std::string gap = row["gap"].is_null() ? "-" : Short(row["gap"].get<double>());
      const std::string f1 = row.contains("gt") ? Short(row["gt"]["f1"].get<double>()) : "-";
      std::printf("%-8s %-6s %10.3f %18.9g %10s %8zu %8s\n", row["id"].get<std::string>().c_str(),
                  row["solver"].get<std::string>().c_str(), row["seconds"].get<double>(),
                  row["objective"].get<double>(), gap.c_str(), row["added"].get<std::size_t>(), f1.c_str());
    }
  }

  RefineFlags flags_;
  std::string solvers_ = "bk,cp,exact", grid_, solver_options_, reference_ = "exact";
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(CompareCommand);

}  // namespace al::cli
