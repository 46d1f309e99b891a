// PFDR on the reduced graph (CUT_PURSUIT.md §6.2). Parallel loops only over independent units
// (components, edges); every sum runs in a fixed order so results do not depend on the thread count.
#include "solvers/cut_pursuit/pfdr.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "solvers/cut_pursuit/cut_pursuit.hpp"

namespace al::cp {

void ClosedFormValue(const Loss& loss, int D, const double* ybar, double* x) {
  if (loss.linear()) {
    int best = 0;
    for (int d = 1; d < D; ++d)
      if (ybar[d] > ybar[best]) best = d;
    for (int d = 0; d < D; ++d) x[d] = d == best ? 1.0 : 0.0;
    return;
  }
  for (int d = 0; d < D; ++d) x[d] = ybar[d];
}

namespace {

double NormM(const double* a, const std::vector<double>& m, int D) {
  double s = 0.0;
  for (int d = 0; d < D; ++d) s += m[d] * std::fabs(a[d]);
  return s;
}

double DistM(const double* a, const double* b, const std::vector<double>& m, int D) {
  double s = 0.0;
  for (int d = 0; d < D; ++d) s += m[d] * std::fabs(a[d] - b[d]);
  return s;
}

// Ends of the reduced edges grouped by component (CSR, edge order): end 2e is ea[e], 2e + 1 is eb[e].
struct EndIndex {
  std::vector<std::int64_t> first, list;
  std::int32_t CompOf(const ReducedProblem& rp, std::int64_t i) const { return (i & 1) ? rp.eb[i >> 1] : rp.ea[i >> 1]; }
};

EndIndex IndexEnds(const ReducedProblem& rp, const std::vector<std::int32_t>& degree) {
  const std::size_t nE = rp.ea.size();
  EndIndex ends;
  ends.first.assign(rp.rV + 1, 0);
  for (std::int32_t c = 0; c < rp.rV; ++c) ends.first[c + 1] = ends.first[c] + degree[c];
  ends.list.resize(2 * nE);
  std::vector<std::int64_t> pos(ends.first.begin(), ends.first.end() - 1);
  for (std::size_t e = 0; e < nE; ++e) {
    ends.list[pos[rp.ea[e]]++] = 2 * e;
    ends.list[pos[rp.eb[e]]++] = 2 * e + 1;
  }
  return ends;
}

// The splitting's state: metric step sizes Gamma, end weights, thresholds th and averaging weights
// au/av per edge and label, auxiliary variables Z per end and label.
struct PfdrState {
  std::vector<double> Gamma, wend, th, au, av, Z, P, Xprev;
};

// Gamma from the curvature of the loss and of the smoothed TV at X, clamped by the Lipschitz bound;
// wend[i] = kappa of edge i >> 1 (TV curvature) before normalisation.
void StepSizes(const ReducedProblem& rp, const PfdrOptions& opt, const Loss& loss, int D,
               const std::vector<double>& X, PfdrState& st) {
  const std::int32_t rV = rp.rV;
  std::vector<double> H(rV * D), L(rV * D);
  for (std::int32_t c = 0; c < rV; ++c)
    for (int d = 0; d < D; ++d) {
      L[c * D + d] = rp.W[c] * loss.Lipschitz(rp.Ybar[c * D + d]);
      H[c * D + d] = rp.W[c] * loss.Hess(rp.Ybar[c * D + d], X[c * D + d]);
    }
  for (std::size_t e = 0; e < rp.ea.size(); ++e) {
    const double* xa = &X[rp.ea[e] * D];
    const double* xb = &X[rp.eb[e] * D];
    const double delta = std::max({DistM(xa, xb, rp.metric, D),
                                   opt.cond_min * std::max(NormM(xa, rp.metric, D), NormM(xb, rp.metric, D)), opt.eps});
    double kappa = rp.omega[e] / delta;
    for (int d = 0; d < D; ++d) {
      H[rp.ea[e] * D + d] += rp.metric[d] * kappa;
      H[rp.eb[e] * D + d] += rp.metric[d] * kappa;
    }
    if (!(kappa > 0.0)) kappa = std::numeric_limits<double>::min();
    st.wend[2 * e] = st.wend[2 * e + 1] = kappa;
  }
  for (std::int32_t c = 0; c < rV; ++c)
    for (int d = 0; d < D; ++d) {
      const std::size_t i = c * D + d;
      double g = H[i] > 0.0 ? 1.0 / H[i] : std::numeric_limits<double>::max();
      if (L[i] > 0.0) {
        const double gmax = 1.9 * (2.0 - opt.rho) / L[i];
        g = std::clamp(g, opt.cond_min * gmax, gmax);
      }
      st.Gamma[i] = g;
    }
}

// Preconditioning (§6.2): step sizes, end weights normalised per component, the per-edge
// thresholds and averaging weights, and Z restarted from X.
void Precondition(const ReducedProblem& rp, const PfdrOptions& opt, const Loss& loss, int D, const EndIndex& ends,
                  const std::vector<double>& X, PfdrState& st) {
  const std::size_t nE = rp.ea.size();
  StepSizes(rp, opt, loss, D, X, st);
  std::vector<double> wsum(rp.rV, 0.0);
  for (std::int32_t c = 0; c < rp.rV; ++c)
    for (std::int64_t k = ends.first[c]; k < ends.first[c + 1]; ++k) wsum[c] += st.wend[ends.list[k]];
  for (std::size_t i = 0; i < 2 * nE; ++i) st.wend[i] /= wsum[ends.CompOf(rp, i)];
  for (std::size_t e = 0; e < nE; ++e)
    for (int d = 0; d < D; ++d) {
      const double bu = st.wend[2 * e] / st.Gamma[rp.ea[e] * D + d];
      const double bv = st.wend[2 * e + 1] / st.Gamma[rp.eb[e] * D + d];
      st.th[e * D + d] = rp.omega[e] * rp.metric[d] * (1.0 / bu + 1.0 / bv);
      const double sum = bu + bv;
      st.au[e * D + d] = sum > 0.0 ? bu / sum : 0.5;
      st.av[e * D + d] = sum > 0.0 ? bv / sum : 0.5;
    }
  for (std::size_t i = 0; i < 2 * nE; ++i) {
    const std::int32_t c = ends.CompOf(rp, i);
    for (int d = 0; d < D; ++d) st.Z[i * D + d] = X[c * D + d];
  }
}

// One PFDR iteration: forward step P, proximal update of every edge's Z pair, then X as the
// weighted average of its ends' Z projected on the simplex. kD > 0 fixes the number of labels at
// compile time (the product's D = 2: the per-coordinate loops unroll); kD = 0 reads it from rp.
// `loss` is a copy on purpose: stores to the iterates cannot alias it, so its constants are hoisted.
template <int kD>
void PfdrIteration(const ReducedProblem& rp, const PfdrOptions& opt, const Loss loss, const EndIndex& ends,
                   PfdrState& st, std::vector<double>& X, int threads, bool par) {
  const int D = kD > 0 ? kD : rp.D;
  const std::int32_t rV = rp.rV;
  const std::int64_t nE = static_cast<std::int64_t>(rp.ea.size());
#pragma omp parallel num_threads(threads) if (par)
  {
#pragma omp for schedule(static)
    for (std::int32_t c = 0; c < rV; ++c)
      for (int d = 0; d < D; ++d) {
        const std::size_t i = c * D + d;
        st.P[i] = 2.0 * X[i] - st.Gamma[i] * rp.W[c] * loss.Grad(rp.Ybar[i], X[i]);
      }
#pragma omp for schedule(static)
    for (std::int64_t e = 0; e < nE; ++e) {
      const std::int32_t a = rp.ea[e], b = rp.eb[e];
      for (int d = 0; d < D; ++d) {
        double& zu = st.Z[(2 * e) * D + d];
        double& zv = st.Z[(2 * e + 1) * D + d];
        const double gu = st.P[a * D + d] - zu, gv = st.P[b * D + d] - zv;
        const double wa = st.au[e * D + d], wb = st.av[e * D + d], t = st.th[e * D + d];
        const double avg = wa * gu + wb * gv;
        const double diff = gu - gv;
        const double delta = diff > t ? diff - t : (diff < -t ? diff + t : 0.0);
        zu += opt.rho * (avg + wb * delta - X[a * D + d]);
        zv += opt.rho * (avg - wa * delta - X[b * D + d]);
      }
    }
#pragma omp for schedule(static)
    for (std::int32_t c = 0; c < rV; ++c) {
      if (ends.first[c] == ends.first[c + 1]) continue;
      double* x = &X[c * D];
      for (int d = 0; d < D; ++d) x[d] = 0.0;
      for (std::int64_t k = ends.first[c]; k < ends.first[c + 1]; ++k) {
        const std::int64_t i = ends.list[k];
        for (int d = 0; d < D; ++d) x[d] += st.wend[i] * st.Z[i * D + d];
      }
      ProjectSimplexMetric(x, &st.Gamma[c * D], D);
    }
  }
}

// Weighted mean l1 change of X since the last check (fixed-order sums).
double WeightedEvolution(const ReducedProblem& rp, int D, const std::vector<double>& X, const std::vector<double>& Xprev) {
  double num = 0.0, den = 0.0;
  for (std::int32_t c = 0; c < rp.rV; ++c) {
    double s = 0.0;
    for (int d = 0; d < D; ++d) s += std::fabs(X[c * D + d] - Xprev[c * D + d]);
    num += rp.W[c] * s;
    den += rp.W[c];
  }
  return den > 0.0 ? num / den : 0.0;
}

template <int kD>
int SolveReducedImpl(const ReducedProblem& rp, const PfdrOptions& opt, std::vector<double>& X) {
  const int D = kD > 0 ? kD : rp.D;
  const std::int32_t rV = rp.rV;
  const std::size_t nE = rp.ea.size();
  X.assign(rp.Ybar.begin(), rp.Ybar.end());
  // Isolated components are independent problems with a closed form.
  std::vector<std::int32_t> degree(rV, 0);
  for (std::size_t e = 0; e < nE; ++e) { ++degree[rp.ea[e]]; ++degree[rp.eb[e]]; }
  for (std::int32_t c = 0; c < rV; ++c)
    if (degree[c] == 0) ClosedFormValue(rp.loss, D, &rp.Ybar[c * D], &X[c * D]);
  if (nE == 0) return 0;
  const EndIndex ends = IndexEnds(rp, degree);
  PfdrState st{std::vector<double>(rV * D), std::vector<double>(2 * nE), std::vector<double>(nE * D),
               std::vector<double>(nE * D), std::vector<double>(nE * D), std::vector<double>(2 * nE * D),
               std::vector<double>(rV * D), X};
  Precondition(rp, opt, rp.loss, D, ends, X, st);
  double dif_rcd = opt.dif_rcd;
  const int check = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(opt.it_max))));
  const int threads = opt.num_threads > 0 ? opt.num_threads : omp_get_max_threads();
  // Three barriers per iteration: a few microseconds each on an idle machine, but up to a time
  // slice each when another process holds a core (docs/reliability.md, bench/contention). Below
  // ~50k unknowns (~0.3 ms of work per iteration) running serially costs less than the barriers.
  const bool par = rV * D + static_cast<std::int64_t>(nE) > 50000;
  int it = 0;
  while (it < opt.it_max) {
    PfdrIteration<kD>(rp, opt, rp.loss, ends, st, X, threads, par);
    if (++it % check != 0) continue;
    const double evo = WeightedEvolution(rp, D, X, st.Xprev);
    st.Xprev = X;
    if (evo < opt.dif_tol) break;
    if (evo < dif_rcd) {
      Precondition(rp, opt, rp.loss, D, ends, X, st);  // restarts the splitting from the current X
      dif_rcd /= 10.0;
    }
  }
  return it;
}

}  // namespace

int SolveReduced(const ReducedProblem& rp, const PfdrOptions& opt, std::vector<double>& X) {
  return rp.D == 2 ? SolveReducedImpl<2>(rp, opt, X) : SolveReducedImpl<0>(rp, opt, X);
}

}  // namespace al::cp
