// The exact two-label solver (CUT_PURSUIT.md §11): the relaxed problem is a 1-D total-variation
// problem in p_v, solved by recursive level cuts. A group of vertices known to share the interval
// [lo, hi] is cut at a level t (its plateau value, or the interval's middle); the sink side goes
// above t, the source side below, until every group is a plateau or narrower than epsilon.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "al/graph/loss.hpp"
#include "solvers/exact/exact_solver.hpp"

namespace al {
namespace {

void ValidateTwoLabelProblem(const RefineProblem& pb) {
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

struct Group {
  std::vector<std::int32_t> members;
  double lo, hi;
  int depth;
};

class LevelSetSolver {
 public:
  LevelSetSolver(const RefineProblem& pb, const ExactOptions& opt)
      : pb_(pb), opt_(opt), loss_{pb.kl_smoothing, 2}, V_(static_cast<std::int32_t>(pb.num_nodes())),
        nw_(pb.node_weights.empty() ? std::vector<double>(V_, 1.0) : pb.node_weights),
        lo_(V_, 0.0), hi_(V_, 1.0), p_(V_, 0.0), stamp_(V_, -1), local_(V_) {
    BuildAdjacency();
    mf_.set_algorithm(opt.max_flow);
  }

  std::vector<double> Solve(ExactStats* stats);

 private:
  // phi'_v(t) and phi''_v(t) of the 1-D problem (§11).
  double Dphi(std::int32_t v, double t) const {
    return nw_[v] * (loss_.Grad(pb_.y_remove[v], t) - loss_.Grad(1.0 - pb_.y_remove[v], 1.0 - t));
  }
  double Ddphi(std::int32_t v, double t) const {
    return nw_[v] * (loss_.Hess(pb_.y_remove[v], t) + loss_.Hess(1.0 - pb_.y_remove[v], 1.0 - t));
  }
  void BuildAdjacency();
  void Boundary(const Group& g);
  double PlateauLevel(const Group& g) const;
  bool LevelCut(const Group& g, double t, Group& up, Group& down);
  void Finalize(const Group& g, double t);

  const RefineProblem& pb_;
  const ExactOptions& opt_;
  const Loss loss_;
  const std::int32_t V_;
  const std::vector<double> nw_;
  // Symmetric adjacency without zero-weight edges and self-loops; om = 2 w_e for the unit metric.
  std::vector<std::int64_t> ff_;
  std::vector<std::int32_t> nbr_;
  std::vector<double> om_;
  std::vector<double> lo_, hi_, p_;
  std::vector<std::int64_t> stamp_;   // = serial_ for the members of the group being cut
  std::vector<std::int32_t> local_;   // position of a vertex in its group
  std::int64_t serial_ = 0;
  std::vector<double> bnd_, a_;       // per member: boundary term, unary of the level cut
  ExactStats st_;
  MaxFlow mf_;                        // buffers reused by every level cut
};

void LevelSetSolver::BuildAdjacency() {
  ff_.assign(V_ + 1, 0);
  for (std::int32_t u = 0; u < V_; ++u)
    for (std::int64_t e = pb_.first_edge[u]; e < pb_.first_edge[u + 1]; ++e)
      if (pb_.edge_weights[e] > 0.0 && pb_.adj_vertices[e] != u) { ++ff_[u + 1]; ++ff_[pb_.adj_vertices[e] + 1]; }
  for (std::int32_t v = 0; v < V_; ++v) ff_[v + 1] += ff_[v];
  nbr_.resize(ff_[V_]);
  om_.resize(ff_[V_]);
  std::vector<std::int64_t> pos(ff_.begin(), ff_.end() - 1);
  for (std::int32_t u = 0; u < V_; ++u)
    for (std::int64_t e = pb_.first_edge[u]; e < pb_.first_edge[u + 1]; ++e) {
      const std::int32_t v = pb_.adj_vertices[e];
      if (!(pb_.edge_weights[e] > 0.0) || v == u) continue;
      nbr_[pos[u]] = v; om_[pos[u]++] = 2.0 * pb_.edge_weights[e];
      nbr_[pos[v]] = u; om_[pos[v]++] = 2.0 * pb_.edge_weights[e];
    }
}

// Stamps the group and sums each member's boundary term: neighbours outside the group lie entirely
// above (lo_u >= hi) or below it.
void LevelSetSolver::Boundary(const Group& g) {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  ++serial_;
  for (std::int32_t i = 0; i < n; ++i) { stamp_[g.members[i]] = serial_; local_[g.members[i]] = i; }
  bnd_.assign(n, 0.0);
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t v = g.members[i];
    for (std::int64_t k = ff_[v]; k < ff_[v + 1]; ++k) {
      const std::int32_t u = nbr_[k];
      if (stamp_[u] == serial_) continue;
      bnd_[i] += lo_[u] >= g.hi ? -om_[k] : om_[k];
    }
  }
}

// The level where the group's summed derivative crosses zero (safeguarded Newton), clamped to [lo, hi].
double LevelSetSolver::PlateauLevel(const Group& g) const {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  auto f = [&](double x, double* df) {
    double s = 0.0, ds = 0.0;
    for (std::int32_t i = 0; i < n; ++i) {
      s += Dphi(g.members[i], x) + bnd_[i];
      if (df) ds += Ddphi(g.members[i], x);
    }
    if (df) *df = ds;
    return s;
  };
  if (f(g.lo, nullptr) >= 0.0) return g.lo;
  if (f(g.hi, nullptr) <= 0.0) return g.hi;
  double a0 = g.lo, b0 = g.hi;
  double t = 0.5 * (a0 + b0);
  for (int iter = 0; iter < 200; ++iter) {
    double df;
    const double ft = f(t, &df);
    if (ft == 0.0) break;
    if (ft < 0.0) a0 = t; else b0 = t;
    double next = df > 0.0 ? t - ft / df : 0.5 * (a0 + b0);
    if (!(next > a0 && next < b0)) next = 0.5 * (a0 + b0);
    if (std::fabs(next - t) <= 1e-16 * std::max(1.0, std::fabs(t)) || b0 - a0 <= 1e-16) return next;
    t = next;
  }
  return t;
}

// Level cut at t: the sink side ("above") pays a_v = phi'_v(t) + boundary. Fills up / down;
// returns true when the cut gains nothing (min cut energy = flow - sum of negative unaries >= 0 up
// to rounding: no strict split).
bool LevelSetSolver::LevelCut(const Group& g, double t, Group& up, Group& down) {
  const std::int32_t n = static_cast<std::int32_t>(g.members.size());
  mf_.Reset(n);
  a_.assign(n, 0.0);
  double neg = 0.0, scale = 0.0;
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t v = g.members[i];
    a_[i] = Dphi(v, t) + bnd_[i];
    mf_.AddUnary(i, a_[i]);
    if (a_[i] < 0.0) neg -= a_[i];
    scale += std::fabs(a_[i]);
    for (std::int64_t k = ff_[v]; k < ff_[v + 1]; ++k) {
      const std::int32_t u = nbr_[k];
      if (stamp_[u] == serial_ && u > v) mf_.AddEdge(i, local_[u], om_[k], om_[k]);
    }
  }
  const double flow = mf_.Solve();
  ++st_.max_flows;
  up = Group{{}, t, g.hi, g.depth + 1};
  down = Group{{}, g.lo, t, g.depth + 1};
  for (std::int32_t i = 0; i < n; ++i) (mf_.SourceSide(i) ? down : up).members.push_back(g.members[i]);
  return flow - neg >= -1e-12 * std::max(scale, 1e-300);
}

void LevelSetSolver::Finalize(const Group& g, double t) {
  for (std::int32_t v : g.members) { p_[v] = t; lo_[v] = hi_[v] = t; }
  ++st_.plateaus;
}

std::vector<double> LevelSetSolver::Solve(ExactStats* stats) {
  std::vector<Group> stack;
  if (V_ > 0) {
    Group g{std::vector<std::int32_t>(V_), 0.0, 1.0, 0};
    for (std::int32_t v = 0; v < V_; ++v) g.members[v] = v;
    stack.push_back(std::move(g));
  }
  const bool plateau = opt_.pivot == "plateau";
  while (!stack.empty()) {
    Group g = std::move(stack.back());
    stack.pop_back();
    st_.max_depth = std::max(st_.max_depth, g.depth);
    Boundary(g);
    const bool final = g.hi - g.lo <= opt_.epsilon;
    const double t = plateau ? PlateauLevel(g) : 0.5 * (g.lo + g.hi);
    if (final) { Finalize(g, t); continue; }
    Group up, down;
    const bool no_gain = LevelCut(g, t, up, down);
    if (plateau && (up.members.empty() || down.members.empty() || no_gain)) { Finalize(g, t); continue; }
    for (std::int32_t v : up.members) { lo_[v] = t; hi_[v] = g.hi; }
    for (std::int32_t v : down.members) { lo_[v] = g.lo; hi_[v] = t; }
    if (!down.members.empty()) stack.push_back(std::move(down));
    if (!up.members.empty()) stack.push_back(std::move(up));
  }
  if (stats) *stats = st_;
  return std::move(p_);
}

}  // namespace

std::vector<double> SolveExactTwoLabel(const RefineProblem& pb, const ExactOptions& opt, ExactStats* stats) {
  ValidateTwoLabelProblem(pb);
  opt.Check();
  return LevelSetSolver(pb, opt).Solve(stats);
}

}  // namespace al
