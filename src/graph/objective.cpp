#include <algorithm>
#include <cmath>

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

// Sums over fixed blocks of nodes, added block by block in order: the same double for any thread
// count, on all threads (a serial pass was 0.02 s at 685k nodes, once per solve).
double Objective(const RefineProblem& problem, const std::vector<double>& p) {
  const auto V = static_cast<std::int64_t>(problem.num_nodes());
  constexpr std::int64_t kBlock = std::int64_t{1} << 14;
  const std::int64_t blocks = (V + kBlock - 1) / kBlock;
  std::vector<double> data(static_cast<std::size_t>(blocks), 0.0), tv(static_cast<std::size_t>(blocks), 0.0);
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (std::int64_t b = 0; b < blocks; ++b) {
    double sd = 0.0, st = 0.0;
    for (std::int64_t u = b * kBlock; u < std::min(V, (b + 1) * kBlock); ++u) {
      const double w = problem.node_weights.empty() ? 1.0 : problem.node_weights[u];
      sd += w * DataTerm2(problem.y_remove[u], p[u], problem.kl_smoothing);
      for (std::int64_t e = problem.first_edge[u]; e < problem.first_edge[u + 1]; ++e)
        st += problem.edge_weights[e] * 2.0 * std::fabs(p[u] - p[problem.adj_vertices[e]]);
    }
    data[static_cast<std::size_t>(b)] = sd;
    tv[static_cast<std::size_t>(b)] = st;
  }
  double total_data = 0.0, total_tv = 0.0;
  for (std::int64_t b = 0; b < blocks; ++b) total_data += data[static_cast<std::size_t>(b)], total_tv += tv[static_cast<std::size_t>(b)];
  return total_data + total_tv;
}

}  // namespace al
