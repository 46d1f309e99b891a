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

// kD > 0 fixes the number of labels at compile time (the product's D = 2: the per-coordinate loops
// unroll); kD = 0 reads it from the problem. Both run the same arithmetic in the same order.
template <int kD>
int SolveReducedImpl(const ReducedProblem& rp, const PfdrOptions& opt, std::vector<double>& X) {
  const int D = kD > 0 ? kD : rp.D;
  const Loss loss = rp.loss;  // a local copy: stores to the iterates cannot alias it, so its
                              // constants are hoisted out of the loops
  const std::int32_t rV = rp.rV;
  const std::size_t nE = rp.ea.size();
  X.assign(rp.Ybar.begin(), rp.Ybar.end());
  // Isolated components are independent problems with a closed form.
  std::vector<std::int32_t> degree(rV, 0);
  for (std::size_t e = 0; e < nE; ++e) { ++degree[rp.ea[e]]; ++degree[rp.eb[e]]; }
  for (std::int32_t c = 0; c < rV; ++c)
    if (degree[c] == 0) ClosedFormValue(loss, D, &rp.Ybar[c * D], &X[c * D]);
  if (nE == 0) return 0;
  // Ends of each component in edge order (CSR), for the fixed-order averaging of Z.
  std::vector<std::int64_t> end_first(rV + 1, 0);
  for (std::int32_t c = 0; c < rV; ++c) end_first[c + 1] = end_first[c] + degree[c];
  std::vector<std::int64_t> end_list(2 * nE);
  {
    std::vector<std::int64_t> pos(end_first.begin(), end_first.end() - 1);
    for (std::size_t e = 0; e < nE; ++e) {
      end_list[pos[rp.ea[e]]++] = 2 * e;
      end_list[pos[rp.eb[e]]++] = 2 * e + 1;
    }
  }
  auto comp_of_end = [&](std::int64_t i) { return (i & 1) ? rp.eb[i >> 1] : rp.ea[i >> 1]; };

  std::vector<double> Gamma(rV * D), wend(2 * nE), th(nE * D), au(nE * D), av(nE * D), Z(2 * nE * D);
  std::vector<double> grad_scale(rV * D), P(rV * D), Xprev(rV * D);
  const double tiny = std::numeric_limits<double>::min();

  auto precondition = [&]() {
    std::vector<double> H(rV * D), L(rV * D);
    for (std::int32_t c = 0; c < rV; ++c)
      for (int d = 0; d < D; ++d) {
        L[c * D + d] = rp.W[c] * loss.Lipschitz(rp.Ybar[c * D + d]);
        H[c * D + d] = rp.W[c] * loss.Hess(rp.Ybar[c * D + d], X[c * D + d]);
      }
    for (std::size_t e = 0; e < nE; ++e) {
      const double* xa = &X[rp.ea[e] * D];
      const double* xb = &X[rp.eb[e] * D];
      const double delta = std::max({DistM(xa, xb, rp.metric, D),
                                     opt.cond_min * std::max(NormM(xa, rp.metric, D), NormM(xb, rp.metric, D)),
                                     opt.eps});
      double kappa = rp.omega[e] / delta;
      for (int d = 0; d < D; ++d) {
        H[rp.ea[e] * D + d] += rp.metric[d] * kappa;
        H[rp.eb[e] * D + d] += rp.metric[d] * kappa;
      }
      if (!(kappa > 0.0)) kappa = tiny;
      wend[2 * e] = wend[2 * e + 1] = kappa;
    }
    for (std::int32_t c = 0; c < rV; ++c)
      for (int d = 0; d < D; ++d) {
        const std::size_t i = c * D + d;
        double g = H[i] > 0.0 ? 1.0 / H[i] : std::numeric_limits<double>::max();
        if (L[i] > 0.0) {
          const double gmax = 1.9 * (2.0 - opt.rho) / L[i];
          g = std::clamp(g, opt.cond_min * gmax, gmax);
        }
        Gamma[i] = g;
      }
    std::vector<double> wsum(rV, 0.0);
    for (std::int32_t c = 0; c < rV; ++c)
      for (std::int64_t k = end_first[c]; k < end_first[c + 1]; ++k) wsum[c] += wend[end_list[k]];
    for (std::size_t i = 0; i < 2 * nE; ++i) wend[i] /= wsum[comp_of_end(i)];
    for (std::size_t e = 0; e < nE; ++e)
      for (int d = 0; d < D; ++d) {
        const double bu = wend[2 * e] / Gamma[rp.ea[e] * D + d];
        const double bv = wend[2 * e + 1] / Gamma[rp.eb[e] * D + d];
        th[e * D + d] = rp.omega[e] * rp.metric[d] * (1.0 / bu + 1.0 / bv);
        const double sum = bu + bv;
        au[e * D + d] = sum > 0.0 ? bu / sum : 0.5;
        av[e * D + d] = sum > 0.0 ? bv / sum : 0.5;
      }
    for (std::size_t i = 0; i < 2 * nE; ++i) {
      const std::int32_t c = comp_of_end(i);
      for (int d = 0; d < D; ++d) Z[i * D + d] = X[c * D + d];
    }
  };

  precondition();
  double dif_rcd = opt.dif_rcd;
  const int check = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(opt.it_max))));
  const int threads = opt.num_threads > 0 ? opt.num_threads : omp_get_max_threads();
  // Three barriers per iteration: a few microseconds each on an idle machine, but up to a time
  // slice each when another process holds a core (docs/reliability.md, bench/contention). Below
  // ~50k unknowns (~0.3 ms of work per iteration) running serially costs less than the barriers.
  const bool par = rV * D + static_cast<std::int64_t>(nE) > 50000;
  Xprev = X;
  int it = 0;
  while (it < opt.it_max) {
#pragma omp parallel num_threads(threads) if (par)
    {
#pragma omp for schedule(static)
      for (std::int32_t c = 0; c < rV; ++c)
        for (int d = 0; d < D; ++d) {
          const std::size_t i = c * D + d;
          P[i] = 2.0 * X[i] - Gamma[i] * rp.W[c] * loss.Grad(rp.Ybar[i], X[i]);
        }
#pragma omp for schedule(static)
      for (std::int64_t e = 0; e < static_cast<std::int64_t>(nE); ++e) {
        const std::int32_t a = rp.ea[e], b = rp.eb[e];
        for (int d = 0; d < D; ++d) {
          double& zu = Z[(2 * e) * D + d];
          double& zv = Z[(2 * e + 1) * D + d];
          const double gu = P[a * D + d] - zu, gv = P[b * D + d] - zv;
          const double wa = au[e * D + d], wb = av[e * D + d], t = th[e * D + d];
          const double avg = wa * gu + wb * gv;
          const double diff = gu - gv;
          const double delta = diff > t ? diff - t : (diff < -t ? diff + t : 0.0);
          zu += opt.rho * (avg + wb * delta - X[a * D + d]);
          zv += opt.rho * (avg - wa * delta - X[b * D + d]);
        }
      }
#pragma omp for schedule(static)
      for (std::int32_t c = 0; c < rV; ++c) {
        if (end_first[c] == end_first[c + 1]) continue;
        double* x = &X[c * D];
        for (int d = 0; d < D; ++d) x[d] = 0.0;
        for (std::int64_t k = end_first[c]; k < end_first[c + 1]; ++k) {
          const std::int64_t i = end_list[k];
          for (int d = 0; d < D; ++d) x[d] += wend[i] * Z[i * D + d];
        }
        ProjectSimplexMetric(x, &Gamma[c * D], D);
      }
    }
    ++it;
    if (it % check == 0) {
      double num = 0.0, den = 0.0;
      for (std::int32_t c = 0; c < rV; ++c) {
        double s = 0.0;
        for (int d = 0; d < D; ++d) s += std::fabs(X[c * D + d] - Xprev[c * D + d]);
        num += rp.W[c] * s;
        den += rp.W[c];
      }
      const double evo = den > 0.0 ? num / den : 0.0;
      Xprev = X;
      if (evo < opt.dif_tol) break;
      if (evo < dif_rcd) {
        precondition();  // restarts the splitting from the current X
        dif_rcd /= 10.0;
      }
    }
  }
  return it;
}

}  // namespace

int SolveReduced(const ReducedProblem& rp, const PfdrOptions& opt, std::vector<double>& X) {
  return rp.D == 2 ? SolveReducedImpl<2>(rp, opt, X) : SolveReducedImpl<0>(rp, opt, X);
}

}  // namespace al::cp
