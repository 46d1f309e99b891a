#include <algorithm>
#include <cmath>

#include "al/graph/problem.hpp"

namespace al {

double SmoothedKl2(double y_remove, double x_remove, double s) {
  const double q = s / 2.0, c = 1.0 - s;
  const double y[2] = {q + c * y_remove, q + c * (1.0 - y_remove)};
  const double x[2] = {q + c * x_remove, q + c * (1.0 - x_remove)};
  double kl = 0.0;
  for (int d = 0; d < 2; ++d)
    if (y[d] > 0.0) kl += y[d] * std::log(y[d] / x[d]);
  // KL >= 0 (Gibbs); for y close to x the two terms cancel and rounding can leave -1e-17, which
  // a max-flow capacity must not be.
  return std::max(0.0, kl);
}

double Objective(const RefineProblem& problem, const std::vector<double>& p) {
  // Sequential sums: the objective must not depend on the thread count.
  double data = 0.0, tv = 0.0;
  const std::size_t V = problem.num_nodes();
  for (std::size_t v = 0; v < V; ++v)
    data += problem.node_weights[v] * SmoothedKl2(problem.y_remove[v], p[v], problem.kl_smoothing);
  for (std::size_t u = 0; u < V; ++u)
    for (std::int64_t e = problem.first_edge[u]; e < problem.first_edge[u + 1]; ++e)
      tv += problem.edge_weights[e] * 2.0 * std::fabs(p[u] - p[problem.adj_vertices[e]]);
  return data + tv;
}

}  // namespace al
