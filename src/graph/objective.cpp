#include <algorithm>
#include <cmath>

#include "al/core/block_sum.hpp"
#include "al/graph/loss.hpp"
#include "al/graph/problem.hpp"

namespace al {

double DataTerm2(double y_remove, double x_remove, double s) {
  const Loss loss{s, 2};
  const double value = loss.Value(y_remove, x_remove) + loss.Value(1.0 - y_remove, 1.0 - x_remove);
  // Smoothed KL >= 0 (Gibbs); for y close to x the two terms cancel and rounding can leave
  // -1e-17, which a max-flow capacity must not be. (The linear loss is negative by design.)
  return loss.linear() || loss.quadratic() ? value : std::max(0.0, value);
}

// On all threads, the same double for any thread count (BlockSum2; a serial pass was 0.02 s at
// 685k nodes, once per solve).
double Objective(const RefineProblem& problem, const std::vector<double>& p) {
  return BlockSum2(static_cast<std::int64_t>(problem.num_nodes()), [&](std::int64_t u, double& data, double& tv) {
    const double w = problem.node_weights.empty() ? 1.0 : problem.node_weights[u];
    data += w * DataTerm2(problem.y_remove[u], p[u], problem.kl_smoothing);
    for (std::int64_t e = problem.first_edge[u]; e < problem.first_edge[u + 1]; ++e)
      tv += problem.edge_weights[e] * 2.0 * std::fabs(p[u] - p[problem.adj_vertices[e]]);
  });
}

}  // namespace al
