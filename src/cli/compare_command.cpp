// `al-refine compare`: every solver (and a grid of cut-pursuit tolerances) on the same graph, with
// seconds, objective, gap to exact and F1; writes compare.csv/.json, tradeoff.png, report.json.
#include <algorithm>
#include <iostream>
#include <sstream>

#include "al/core/error.hpp"
#include "al/refine/compare.hpp"
#include "al/refine/refine.hpp"
#include "src/cli/command.hpp"
#include "src/cli/refine_flags.hpp"

namespace al::cli {
namespace {

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

nlohmann::json ParseJsonFlag(const std::string& flag, const std::string& text) {
  try {
    return nlohmann::json::parse(text);
  } catch (const std::exception&) {
    throw Error(flag + ": not valid JSON", ExitCode::kUsage);
  }
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
    RefineOptions o = ToRefineOptions(flags_);
    CompareOptions co;
    co.solvers = SplitCommaList(solvers_);
    const bool has_cp = std::find(co.solvers.begin(), co.solvers.end(), "cp") != co.solvers.end();
    if (grid_.empty())
      co.grid = has_cp ? DefaultSolverGrid() : SolverGrid{};
    else if (grid_ != "none")
      co.grid = ParseSolverGrid(grid_);
    if (!solver_options_.empty()) co.solver_options = ParseJsonFlag("--solver-options", solver_options_);
    co.reference = reference_ == "exact";
    co.decision = o.decision;
    if (!quiet_) {
      o.on_stage = [](const std::string& stage, double s) {
        if (s > 1.0) std::cerr << "compare  " << stage << "  " << Short(s) << " s\n";
      };
      co.on_run = PrintRun;
    }
    const CompareRunResult r = RunCompare(o, co);
    (r.exit_code == 0 ? std::cout : std::cerr) << r.BriefReport();
    return r.exit_code;
  }

 private:
  static void PrintRun(const SolverRun& run, std::size_t i, std::size_t n, const nlohmann::json* row) {
    std::cerr << "compare  [" << i + 1 << "/" << n << "] " << run.id;
    if (!row) {
      std::cerr << " (" << run.solver << " " << run.options.dump() << ") ...\n";
      return;
    }
    std::cerr << "  F = " << (*row)["objective"].get<double>() << "  " << Short((*row)["seconds"].get<double>())
              << " s  added " << (*row)["added"];
    if (row->contains("gt")) std::cerr << "  F1 " << Short((*row)["gt"]["f1"].get<double>());
    std::cerr << "\n";
  }

  RefineFlags flags_;
  std::string solvers_ = "bk,cp,exact", grid_, solver_options_, reference_ = "exact";
  bool quiet_ = false;
};

AL_REGISTER_COMMAND(CompareCommand);

}  // namespace al::cli
