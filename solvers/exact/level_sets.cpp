// The exact two-label solver (CUT_PURSUIT.md §11): the relaxed problem is a 1-D total-variation
// problem in p_v, solved by recursive level cuts. A group of vertices known to share the interval
// [lo, hi] is cut at a level t (its plateau value, or the interval's middle); the sink side goes
// above t, the source side below, until every group is a plateau or narrower than epsilon.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "al/graph/loss.hpp"
#include "solvers/exact/exact_solver.hpp"
#include "solvers/level_sets/level_set_partition.hpp"

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

}  // namespace

std::vector<double> SolveExactTwoLabel(const RefineProblem& pb, const ExactOptions& opt, ExactStats* stats) {
  ValidateTwoLabelProblem(pb);
  opt.Check();
  const std::size_t V = pb.num_nodes();
  std::vector<double> y(2 * V);
  for (std::size_t v = 0; v < V; ++v) {
    y[2 * v] = pb.y_remove[v];
    y[2 * v + 1] = 1.0 - pb.y_remove[v];
  }
  levelset::TwoLabelTv tv{pb.first_edge, pb.adj_vertices, pb.edge_weights, y, pb.node_weights, 2.0,
                          Loss{pb.kl_smoothing, 2}};
  levelset::Options lopt;
  lopt.epsilon = opt.epsilon;
  lopt.bisection = opt.pivot == "bisection";
  lopt.num_threads = opt.num_threads > 0 ? opt.num_threads : omp_get_max_threads();
  lopt.max_flow = opt.max_flow;
  const levelset::Partition part = levelset::SolveLevelSets(tv, lopt);
  if (stats) {
    stats->max_flows = part.max_flows;
    stats->plateaus = static_cast<long long>(part.value.size());
    stats->max_depth = part.max_depth;
  }
  std::vector<double> p(V);
  for (std::size_t v = 0; v < V; ++v) p[v] = part.value[part.piece[v]];
  return p;
}

}  // namespace al
