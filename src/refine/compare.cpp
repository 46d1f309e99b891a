// Solver comparison on one graph (al/refine/compare.hpp): grid parsing, run planning, the runs.
#include "al/refine/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "al/core/error.hpp"
#include "al/core/text.hpp"
#include "al/core/timer.hpp"
#include "al/solver.hpp"

namespace al {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

bool Contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Integer-valued cp options (iteration counts) must reach the solver as JSON integers.
nlohmann::json GridValue(double v) {
  if (v == std::floor(v) && std::fabs(v) >= 1.0 && std::fabs(v) < 9.0e15)
    return static_cast<long long>(v);
  return v;
}

}  // namespace

SolverGrid ParseSolverGrid(const std::string& text) {
  SolverGrid grid;
  if (Trim(text).empty()) return grid;
  std::set<std::string> seen;
  for (const std::string& item : SplitTrimmed(text, ';')) {
    if (item.empty()) continue;  // tolerate "a=1;" and "a=1;;b=2"
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw Error("--grid: '" + item + "' is not KEY=V1,V2,... (e.g. cp_dif_tol=1e-2,1e-3)",
                  ExitCode::kUsage);
    const std::string key = Trim(item.substr(0, eq));
    if (key.empty()) throw Error("--grid: missing key before '=' in '" + item + "'", ExitCode::kUsage);
    if (!seen.insert(key).second) throw Error("--grid: key '" + key + "' given twice", ExitCode::kUsage);
    std::vector<double> values;
    for (const std::string& v : SplitTrimmed(item.substr(eq + 1), ',')) values.push_back(ParseGridNumber(key, v));
    if (values.empty()) throw Error("--grid: key '" + key + "' has no values", ExitCode::kUsage);
    grid.emplace_back(key, std::move(values));
  }
  return grid;
}

std::string SolverGridToString(const SolverGrid& grid) {
  std::string s;
  for (const auto& [key, values] : grid) {
    if (!s.empty()) s += ";";
    s += key + "=";
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i) s += ',';
      s += Num(values[i]);
    }
  }
  return s;
}

SolverGrid DefaultSolverGrid() { return {{"cp_dif_tol", {1e-2, 1e-3, 1e-4}}}; }

std::vector<SolverRun> PlanSolverRuns(const CompareOptions& o) {
  if (o.solvers.empty()) throw Error("--solvers: no solver given", ExitCode::kUsage);
  const std::vector<std::string> known = SolverNames();
  std::string known_list;
  for (const auto& n : known) known_list += (known_list.empty() ? "" : ", ") + n;
  std::set<std::string> seen;
  for (const auto& s : o.solvers) {
    if (!Contains(known, s))
      throw Error("--solvers: unknown solver '" + s + "' (registered: " + known_list + ")", ExitCode::kUsage);
    if (!seen.insert(s).second) throw Error("--solvers: '" + s + "' given twice", ExitCode::kUsage);
  }
  if (!o.grid.empty() && !seen.count("cp"))
    throw Error("--grid sets cut-pursuit options, but cp is not in --solvers", ExitCode::kUsage);
  if (!o.solver_options.is_object())
    throw Error("--solver-options: expected a JSON object keyed by solver name", ExitCode::kUsage);
  for (const auto& [name, value] : o.solver_options.items()) {
    if (!seen.count(name) && !(name == "exact" && o.reference))
      throw Error("--solver-options: '" + name + "' is not a solver of this comparison", ExitCode::kUsage);
    if (!value.is_object())
      throw Error("--solver-options: options of '" + name + "' must be a JSON object", ExitCode::kUsage);
  }
  auto base = [&](const std::string& name) {
    return o.solver_options.contains(name) ? o.solver_options[name] : nlohmann::json::object();
  };

  std::vector<SolverRun> runs;
  for (const auto& s : o.solvers) {
    if (s != "cp" || o.grid.empty()) {
      runs.push_back({s, s, base(s), false});
      continue;
    }
    // Cartesian product, last key fastest.
    std::vector<std::size_t> at(o.grid.size(), 0);
    for (int n = 1;; ++n) {
      SolverRun r{"cp_" + std::to_string(n), "cp", base("cp"), false};
      for (std::size_t g = 0; g < o.grid.size(); ++g) r.options[o.grid[g].first] = GridValue(o.grid[g].second[at[g]]);
      runs.push_back(std::move(r));
      std::size_t g = o.grid.size();
      while (g > 0 && ++at[g - 1] == o.grid[g - 1].second.size()) at[--g] = 0;
      if (g == 0) break;
    }
  }
  if (o.reference && !seen.count("exact")) runs.push_back({"exact", "exact", base("exact"), true});
  for (const auto& r : runs) {
    try {
      MakeSolver(r.solver, r.options);  // validates option keys and types before any work
    } catch (const Error& e) {
      throw Error("solver run '" + r.id + "' (" + r.options.dump() + "): " + e.what(), ExitCode::kUsage);
    }
  }
  return runs;
}

CompareResult CompareSolvers(const RefineInputs& inputs, const GraphResult& graph,
                             const GraphOptions& graph_options, const CompareOptions& o) {
  CompareResult result;
  result.runs = PlanSolverRuns(o);
  if (inputs.ground_truth)
    result.gt_before =
        ScoreAgainstGroundTruth(*inputs.ground_truth, inputs.removal.removed, inputs.removal.removed)["before"];
  if (graph.stats.edges == 0) {
    auto solver = MakeSolver(result.runs.front().solver, result.runs.front().options);
    const SolveOutcome out = SolveAndDecide(inputs, graph, graph_options, *solver, o.decision);
    result.empty_graph = true;
    result.message = out.message;
    result.warnings = out.warnings;
    result.gap_reason = "empty graph: no solver ran";
    return result;
  }

  const std::size_t total = result.runs.size();
  for (std::size_t i = 0; i < total; ++i) {
    const SolverRun& run = result.runs[i];
    if (o.on_run) o.on_run(run, i, total, nullptr);
    auto solver = MakeSolver(run.solver, run.options);
    Timer wall;
    SolveOutcome out = SolveAndDecide(inputs, graph, graph_options, *solver, o.decision);
    const double wall_s = wall.Seconds();
    for (const auto& w : out.warnings) result.warnings.push_back(run.id + ": " + w);
    nlohmann::json row = {{"id", run.id},
                          {"solver", run.solver},
                          {"options", run.options},
                          {"reference_only", run.reference},
                          {"seconds", out.solver.value("seconds", 0.0)},
                          {"wall_seconds", wall_s},
                          {"objective", out.solver["objective"]},
                          {"iterations", out.solver["iterations"]},
                          {"converged", out.solver["converged"]},
                          {"gap", nullptr},
                          {"decision", out.decision},
                          {"added", out.added},
                          {"restored", out.restored},
                          {"refined_count", std::count(out.refined.begin(), out.refined.end(), true)}};
    if (out.solver["stats"].contains("components")) row["components"] = out.solver["stats"]["components"];
    if (inputs.ground_truth)
      row["gt"] = ScoreAgainstGroundTruth(*inputs.ground_truth, inputs.removal.removed, out.refined)["after"];
    if (run.solver == "exact") result.reference_objective = out.solver["objective"].get<double>();
    result.p.push_back(std::move(out.p));
    result.rows.push_back(std::move(row));
    if (o.on_run) o.on_run(run, i, total, &result.rows.back());
  }

  if (result.reference_objective) {
    // Relative to |F*| (F* > 0 for s > 0 unless the problem is trivial; guard a zero anyway).
    const double ref = *result.reference_objective;
    const double scale = std::max(std::fabs(ref), 1e-300);
    for (auto& row : result.rows) row["gap"] = (row["objective"].get<double>() - ref) / scale;
  } else {
    result.gap_reason = "exact is not in --solvers and the reference run was switched off (--reference none)";
  }
  std::ostringstream msg;
  msg << total << " solver runs on " << graph.stats.nodes << " nodes, " << graph.stats.edges << " edges";
  result.message = msg.str();
  return result;
}

}  // namespace al
