#include "solvers/exact/exact_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "al/core/error.hpp"
#include "al/graph/loss.hpp"

namespace al {
namespace {

void ValidateTwoLabel(const RefineProblem& pb) {
  const std::size_t V = pb.num_nodes();
  if (pb.first_edge.size() != V + 1 || pb.first_edge[0] != 0 ||
      pb.first_edge[V] != static_cast<std::int64_t>(pb.adj_vertices.size()) ||
      pb.edge_weights.size() != pb.adj_vertices.size())
    throw Error("refine problem: inconsistent CSR graph");
  for (std::size_t v = 0; v < V; ++v)
    if (pb.first_edge[v + 1] < pb.first_edge[v]) throw Error("refine problem: first_edge is not monotone");
  for (std::size_t e = 0; e < pb.adj_vertices.size(); ++e) {
    if (pb.adj_vertices[e] < 0 || static_cast<std::size_t>(pb.adj_vertices[e]) >= V)
      throw Error("refine problem: edge endpoint out of range");
    if (!std::isfinite(pb.edge_weights[e]) || pb.edge_weights[e] < 0.0)
      throw Error("refine problem: edge weights must be finite and >= 0");
  }
  for (double y : pb.y_remove)
    if (!std::isfinite(y) || y < 0.0 || y > 1.0) throw Error("refine problem: y_remove must lie in [0, 1]");
  if (!pb.node_weights.empty() && pb.node_weights.size() != V)
    throw Error("refine problem: node_weights must hold V entries");
  for (double w : pb.node_weights)
    if (!std::isfinite(w) || w < 0.0) throw Error("refine problem: node weights must be finite and >= 0");
  if (!(pb.kl_smoothing >= 0.0 && pb.kl_smoothing <= 1.0))
    throw Error("refine problem: kl_smoothing must lie in [0, 1]");
}

class ExactSolver final : public Solver {
 public:
  explicit ExactSolver(ExactOptions o) : options_(std::move(o)) {}
  std::string name() const override { return "exact"; }
  SolverResult Solve(const RefineProblem& problem) const override {
    const auto start = std::chrono::steady_clock::now();
    ExactStats st;
    SolverResult out;
    out.solver = "exact";
    out.p = SolveExactTwoLabel(problem, options_, &st);
    out.objective = TwoLabelObjective(problem, out.p);
    out.iterations = static_cast<int>(st.max_flows);
    out.converged = true;
    out.objective_history = {out.objective};
    out.stats["max_flows"] = st.max_flows;
    out.stats["plateaus"] = st.plateaus;
    out.stats["max_depth"] = st.max_depth;
    out.stats["pivot"] = options_.pivot;
    out.stats["epsilon"] = options_.epsilon;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  ExactOptions options_;
};

}  // namespace

ExactOptions ParseExactOptions(const nlohmann::json& options) {
  ExactOptions o;
  if (options.is_null()) return o;
  if (!options.is_object()) throw Error("exact solver: options must be a JSON object", ExitCode::kUsage);
  for (const auto& [key, v] : options.items()) {
    if (key == "epsilon") {
      if (!v.is_number() || !(v.get<double>() > 0.0) || !(v.get<double>() < 1.0))
        throw Error("exact solver: 'epsilon' must be a number in (0, 1)", ExitCode::kUsage);
      o.epsilon = v.get<double>();
    } else if (key == "pivot") {
      if (!v.is_string() || (v.get<std::string>() != "plateau" && v.get<std::string>() != "bisection"))
        throw Error("exact solver: 'pivot' must be \"plateau\" or \"bisection\"", ExitCode::kUsage);
      o.pivot = v.get<std::string>();
    } else if (key == "max_flow") {
      const auto algorithm = v.is_string() ? MaxFlow::AlgorithmFromName(v.get<std::string>()) : std::nullopt;
      if (!algorithm)
        throw Error("exact solver: 'max_flow' must be \"hybrid\", \"pseudoflow\" or \"bk\"",
                    ExitCode::kUsage);
      o.max_flow = *algorithm;
    } else {
      throw Error("exact solver: unknown option '" + key + "'", ExitCode::kUsage);
    }
  }
  return o;
}

double TwoLabelObjective(const RefineProblem& pb, const std::vector<double>& p) {
  const Loss loss{pb.kl_smoothing, 2};
  double data = 0.0, tv = 0.0;
  const std::size_t V = pb.num_nodes();
  for (std::size_t v = 0; v < V; ++v) {
    const double w = pb.node_weights.empty() ? 1.0 : pb.node_weights[v];
    data += w * (loss.Value(pb.y_remove[v], p[v]) + loss.Value(1.0 - pb.y_remove[v], 1.0 - p[v]));
  }
  for (std::size_t u = 0; u < V; ++u)
    for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e)
      tv += pb.edge_weights[e] * 2.0 * std::fabs(p[u] - p[pb.adj_vertices[e]]);
  return data + tv;
}

std::vector<double> SolveExactTwoLabel(const RefineProblem& pb, const ExactOptions& opt, ExactStats* stats) {
  ValidateTwoLabel(pb);
  const std::int32_t V = static_cast<std::int32_t>(pb.num_nodes());
  const Loss loss{pb.kl_smoothing, 2};
  std::vector<double> nw = pb.node_weights.empty() ? std::vector<double>(V, 1.0) : pb.node_weights;
  // phi'_v(p) and phi''_v(p) of the 1-D problem (§11), omega_e = 2 w_e for the unit metric.
  auto dphi = [&](std::int32_t v, double t) {
    return nw[v] * (loss.Grad(pb.y_remove[v], t) - loss.Grad(1.0 - pb.y_remove[v], 1.0 - t));
  };
  auto ddphi = [&](std::int32_t v, double t) {
    return nw[v] * (loss.Hess(pb.y_remove[v], t) + loss.Hess(1.0 - pb.y_remove[v], 1.0 - t));
  };
  std::vector<std::int64_t> ff(V + 1, 0);
  for (std::int32_t u = 0; u < V; ++u)
    for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e)
      if (pb.edge_weights[e] > 0.0 && pb.adj_vertices[e] != u) { ++ff[u + 1]; ++ff[pb.adj_vertices[e] + 1]; }
  for (std::int32_t v = 0; v < V; ++v) ff[v + 1] += ff[v];
  std::vector<std::int32_t> nbr(ff[V]);
  std::vector<double> om(ff[V]);
  {
    std::vector<std::int64_t> pos(ff.begin(), ff.end() - 1);
    for (std::int32_t u = 0; u < V; ++u)
      for (std::int64_t e = pb.first_edge[u]; e < pb.first_edge[u + 1]; ++e) {
        const std::int32_t v = pb.adj_vertices[e];
        if (!(pb.edge_weights[e] > 0.0) || v == u) continue;
        nbr[pos[u]] = v; om[pos[u]++] = 2.0 * pb.edge_weights[e];
        nbr[pos[v]] = u; om[pos[v]++] = 2.0 * pb.edge_weights[e];
      }
  }
  std::vector<double> lo(V, 0.0), hi(V, 1.0), p(V, 0.0);
  std::vector<std::int64_t> stamp(V, -1);
  std::vector<std::int32_t> local(V);
  struct Group {
    std::vector<std::int32_t> members;
    double lo, hi;
    int depth;
  };
  std::vector<Group> stack;
  if (V > 0) {
    Group g{std::vector<std::int32_t>(V), 0.0, 1.0, 0};
    for (std::int32_t v = 0; v < V; ++v) g.members[v] = v;
    stack.push_back(std::move(g));
  }
  const bool plateau = opt.pivot == "plateau";
  std::int64_t serial = 0;
  ExactStats st;
  std::vector<double> bnd, a;
  MaxFlow mf;  // buffers reused by every level cut
  mf.set_algorithm(opt.max_flow);
  while (!stack.empty()) {
    Group g = std::move(stack.back());
    stack.pop_back();
    const std::int32_t n = static_cast<std::int32_t>(g.members.size());
    st.max_depth = std::max(st.max_depth, g.depth);
    ++serial;
    for (std::int32_t i = 0; i < n; ++i) { stamp[g.members[i]] = serial; local[g.members[i]] = i; }
    // Boundary: neighbours outside U lie entirely above (lo_u >= hi) or below.
    bnd.assign(n, 0.0);
    for (std::int32_t i = 0; i < n; ++i) {
      const std::int32_t v = g.members[i];
      for (std::int64_t k = ff[v]; k < ff[v + 1]; ++k) {
        const std::int32_t u = nbr[k];
        if (stamp[u] == serial) continue;
        bnd[i] += lo[u] >= g.hi ? -om[k] : om[k];
      }
    }
    auto finalize = [&](double t) {
      for (std::int32_t v : g.members) { p[v] = t; lo[v] = hi[v] = t; }
      ++st.plateaus;
    };
    double t;
    if (plateau) {
      auto f = [&](double x, double* df) {
        double s = 0.0, ds = 0.0;
        for (std::int32_t i = 0; i < n; ++i) {
          s += dphi(g.members[i], x) + bnd[i];
          if (df) ds += ddphi(g.members[i], x);
        }
        if (df) *df = ds;
        return s;
      };
      const double flo = f(g.lo, nullptr), fhi = f(g.hi, nullptr);
      if (flo >= 0.0) t = g.lo;
      else if (fhi <= 0.0) t = g.hi;
      else {
        double a0 = g.lo, b0 = g.hi;
        t = 0.5 * (a0 + b0);
        for (int iter = 0; iter < 200; ++iter) {
          double df;
          const double ft = f(t, &df);
          if (ft == 0.0) break;
          if (ft < 0.0) a0 = t; else b0 = t;
          double next = df > 0.0 ? t - ft / df : 0.5 * (a0 + b0);
          if (!(next > a0 && next < b0)) next = 0.5 * (a0 + b0);
          if (std::fabs(next - t) <= 1e-16 * std::max(1.0, std::fabs(t)) || b0 - a0 <= 1e-16) { t = next; break; }
          t = next;
        }
      }
      if (g.hi - g.lo <= opt.epsilon) { finalize(t); continue; }
    } else {
      if (g.hi - g.lo <= opt.epsilon) { finalize(0.5 * (g.lo + g.hi)); continue; }
      t = 0.5 * (g.lo + g.hi);
    }
    // Level cut at t: the sink side ("above") pays a_v = phi'_v(t) + boundary.
    mf.Reset(n);
    a.assign(n, 0.0);
    double neg = 0.0, scale = 0.0;
    for (std::int32_t i = 0; i < n; ++i) {
      const std::int32_t v = g.members[i];
      a[i] = dphi(v, t) + bnd[i];
      mf.AddUnary(i, a[i]);
      if (a[i] < 0.0) neg -= a[i];
      scale += std::fabs(a[i]);
      for (std::int64_t k = ff[v]; k < ff[v + 1]; ++k) {
        const std::int32_t u = nbr[k];
        if (stamp[u] == serial && u > v) mf.AddEdge(i, local[u], om[k], om[k]);
      }
    }
    const double flow = mf.Solve();
    ++st.max_flows;
    Group up{{}, t, g.hi, g.depth + 1}, down{{}, g.lo, t, g.depth + 1};
    for (std::int32_t i = 0; i < n; ++i) (mf.SourceSide(i) ? down : up).members.push_back(g.members[i]);
    // Min cut energy = flow - sum of negative unaries; >= 0 (up to rounding) means no strict split.
    const bool no_gain = flow - neg >= -1e-12 * std::max(scale, 1e-300);
    if (plateau && (up.members.empty() || down.members.empty() || no_gain)) { finalize(t); continue; }
    for (std::int32_t v : up.members) { lo[v] = t; hi[v] = g.hi; }
    for (std::int32_t v : down.members) { lo[v] = g.lo; hi[v] = t; }
    if (!down.members.empty()) stack.push_back(std::move(down));
    if (!up.members.empty()) stack.push_back(std::move(up));
  }
  if (stats) *stats = st;
  return p;
}

std::unique_ptr<Solver> MakeExactSolver(const nlohmann::json& options) {
  return std::make_unique<ExactSolver>(ParseExactOptions(options));
}

}  // namespace al
