// bench_problem: solves a problem written by `refine --export-problem` with one or more solvers and
// prints one JSON line per run: solver, options, seconds (wall, median of --repeat runs), process
// CPU seconds, objective, iterations and, with exact among the runs, the relative gap to it. This is
// how docs/solvers.md's time-objective table is measured; an outside solver (the fixed upstream
// parallel-cut-pursuit) reads the same files.
//   bench_problem --problem DIR [--run SOLVER[:JSON]]... [--repeat 3] [--threads N]
// Default runs: cp, bk, exact. Exit codes: 0 ok, 1 usage, 2 bad input (al::ExitCode).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <string>
#include <vector>

#include <omp.h>

#include <nlohmann/json.hpp>

#include "bench/tool_main.hpp"
#include "al/core/error.hpp"
#include "al/graph/problem_io.hpp"
#include "al/solver.hpp"

namespace {

using nlohmann::json;

struct RunSpec {
  std::string solver;
  json options = json::object();
};

RunSpec ParseRun(const std::string& text) {
  const auto colon = text.find(':');
  RunSpec r{text.substr(0, colon)};
  if (colon == std::string::npos) return r;
  try {
    r.options = json::parse(text.substr(colon + 1));
  } catch (const std::exception&) {
    throw al::Error("bench_problem: --run " + text + ": options are not JSON", al::ExitCode::kUsage);
  }
  return r;
}

struct Args {
  std::string problem;
  std::vector<RunSpec> runs;
  int repeat = 3;
  int threads = 0;
};

Args ParseArgs(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw al::Error("bench_problem: " + flag + " needs a value", al::ExitCode::kUsage);
    const std::string value = argv[++i];
    if (flag == "--problem") a.problem = value;
    else if (flag == "--run") a.runs.push_back(ParseRun(value));
    else if (flag == "--repeat") a.repeat = std::max(1, std::stoi(value));
    else if (flag == "--threads") a.threads = std::stoi(value);
    else throw al::Error("bench_problem: unknown flag " + flag, al::ExitCode::kUsage);
  }
  if (a.problem.empty()) throw al::Error("bench_problem: --problem DIR is required", al::ExitCode::kUsage);
  if (a.runs.empty()) a.runs = {{"cp"}, {"bk"}, {"exact"}};
  return a;
}

double ProcessCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Median wall seconds over `repeat` solves; the last result is kept.
json Measure(const al::RefineProblem& problem, const RunSpec& run, int repeat) {
  const auto solver = al::MakeSolver(run.solver, run.options);
  std::vector<double> wall, cpu;
  al::SolverResult r;
  for (int k = 0; k < repeat; ++k) {
    const double c0 = ProcessCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    r = solver->Solve(problem);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpu.push_back(ProcessCpuSeconds() - c0);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {{"solver", run.solver}, {"options", run.options}, {"seconds", wall[wall.size() / 2]},
          {"seconds_all", wall}, {"cpu_seconds", cpu[cpu.size() / 2]}, {"objective", r.objective},
          {"iterations", r.iterations}, {"converged", r.converged}, {"stats", r.stats}};
}

int Main(int argc, char** argv) {
  const Args args = ParseArgs(argc, argv);
  if (args.threads > 0) omp_set_num_threads(args.threads);
  const al::RefineProblem problem = al::ImportProblem(args.problem);
  std::vector<json> rows;
  for (const RunSpec& run : args.runs) rows.push_back(Measure(problem, run, args.repeat));
  double exact = 0.0;
  for (const json& r : rows)
    if (r["solver"] == "exact") exact = r["objective"].get<double>();
  for (json& r : rows) {
    r["nodes"] = problem.num_nodes();
    r["edges"] = problem.num_edges();
    if (exact != 0.0) r["rel_gap_to_exact"] = (r["objective"].get<double>() - exact) / std::abs(exact);
    std::cout << r.dump() << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return al::bench::RunTool("bench_problem", [&] { return Main(argc, argv); });
}
