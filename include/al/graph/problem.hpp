// The refinement problem every solver sees (SPEC §4-5): an undirected graph over the candidate
// nodes in CSR form (each undirected edge stored once, at its smaller endpoint), two-label
// observations y_v = (y_remove, 1 - y_remove), node and edge weights. Solvers minimise
//   F(x) = sum_v w_v KL_s(y_v || x_v) + sum_uv w_uv sum_d |x_ud - x_vd|
// over x_v on the 2-simplex; p_v = x_v,remove.
#pragma once
#include <cstdint>
#include <vector>

namespace al {

struct RefineProblem {
  std::size_t num_nodes() const { return y_remove.size(); }
  std::size_t num_edges() const { return adj_vertices.size(); }

  std::vector<std::int64_t> first_edge;   // V + 1
  std::vector<std::int32_t> adj_vertices; // E: other endpoint (always > the owning node)
  std::vector<double> edge_weights;       // E, lambda included
  std::vector<double> y_remove;           // V: 1 if in the removed set R, else 0
  std::vector<double> node_weights;       // V (1 by default)
  std::vector<std::int64_t> node_ids;     // V: scene index of each node
  double kl_smoothing = 0.1;              // s of the smoothed KL (CUT_PURSUIT.md)
};

// The energy every solver minimises, defined here once (SPEC §5; the per-coordinate loss is
// al::Loss, al/graph/loss.hpp, shared with cut pursuit's D-label iterations):
//   F(p) = sum_v w_v [l_s(y_v, p_v) + l_s(1 - y_v, 1 - p_v)] + sum_uv w_uv 2 |p_u - p_v|,
// p_v = x_v,remove. For 0 < s < 1, l_s is the smoothed KL: KL(s u + (1-s) y || s u + (1-s) x), u
// uniform; s = 0 is linear and s = 1 quadratic (CUT_PURSUIT.md §1.1). Every solver reports
// Objective(problem, p) of the p it returns, so reports, compare and sweep compare like with like.

// The data term of one node (unweighted), two labels (remove, keep).
double DataTerm2(double y_remove, double x_remove, double s);

// F(p), summed in a fixed order (independent of the thread count). Empty node_weights = all 1.
double Objective(const RefineProblem& problem, const std::vector<double>& p);

}  // namespace al
