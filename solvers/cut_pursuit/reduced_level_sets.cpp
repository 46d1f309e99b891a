// The reduced problem for D = 2 solved exactly (CUT_PURSUIT.md §6.2 allows §11 on the reduced graph):
// with X_C = (p_C, 1 - p_C) it is 1-D total variation with the separable convex loss
// W_C [l(Ybar_C0, p) + l(Ybar_C1, 1 - p)] and edge weights (m_0 + m_1) omega, so the level-set
// solver gives its optimum to rounding, usually in a fraction of PFDR's time, and adjacent
// components on one plateau come out with bit-identical values (the merge then joins them).
#include "solvers/cut_pursuit/pfdr.hpp"
#include "solvers/level_sets/level_set_partition.hpp"

namespace al::cp {

std::int64_t SolveReducedLevelSets(const ReducedProblem& rp, const ReducedLevelSetOptions& options,
                                   std::vector<MaxFlow>& networks, std::vector<double>& X) {
  const std::int32_t rV = rp.rV;
  // Reduced edges are sorted by (ea, eb): their CSR rows are ranges of ea.
  std::vector<std::int64_t> first(static_cast<std::size_t>(rV) + 1, 0);
  for (std::int32_t a : rp.ea) ++first[a + 1];
  for (std::int32_t c = 0; c < rV; ++c) first[c + 1] += first[c];
  levelset::TwoLabelTv tv{first, rp.eb, rp.omega, rp.Ybar, rp.W, rp.metric[0] + rp.metric[1], rp.loss};
  levelset::Options lopt;
  lopt.epsilon = options.epsilon;
  lopt.num_threads = options.num_threads;
  lopt.max_flow = options.max_flow;
  const levelset::Partition part = levelset::SolveLevelSets(tv, lopt, &networks);
  X.resize(2 * static_cast<std::size_t>(rV));
  for (std::int32_t c = 0; c < rV; ++c) {
    const double p = part.value[part.piece[c]];
    X[2 * c] = p;
    X[2 * c + 1] = 1.0 - p;
  }
  return part.max_flows;
}

}  // namespace al::cp
