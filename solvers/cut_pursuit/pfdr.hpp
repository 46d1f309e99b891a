// Preconditioned forward-Douglas-Rachford for the reduced problem of cut pursuit (CUT_PURSUIT.md §6):
//   min sum_C W_C l_s(Ybar_C, X_C) + sum_e omega_e ||X_a - X_b||_{1,m} + i_simplex.
#pragma once
#include <cstdint>
#include <vector>

#include "al/graph/loss.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al::cp {

struct ReducedProblem {
  std::int32_t rV = 0;
  int D = 2;
  std::vector<double> W;             // rV
  std::vector<double> Ybar;          // rV x D
  std::vector<std::int32_t> ea, eb;  // reduced edges (ea < eb, sorted)
  std::vector<double> omega;         // reduced edge weights
  std::vector<double> metric;        // D
  Loss loss;
};

struct PfdrOptions {
  double rho = 1.0, cond_min = 1e-2, dif_rcd = 0.0, dif_tol = 1e-5, eps = 2.220446049250313e-16;
  int it_max = 10000;
  int num_threads = 0;
};

// Closed-form minimiser for one isolated component (§6.1).
void ClosedFormValue(const Loss& loss, int D, const double* ybar, double* x);

// Solves the reduced problem from X = Ybar; isolated components get their closed form.
// Returns the number of PFDR iterations.
int SolveReduced(const ReducedProblem& rp, const PfdrOptions& options, std::vector<double>& X);

struct ReducedLevelSetOptions {
  double epsilon = 1e-10;  // interval width at which a piece is final (the exact solver's)
  int num_threads = 1;     // never changes X
  MaxFlow::Algorithm max_flow = MaxFlow::Algorithm::kHybrid;
};

// D = 2 only: the reduced problem's optimum by level cuts (reduced_level_sets.cpp), with the
// callers' max-flow networks (one per thread). Returns the number of max-flows.
std::int64_t SolveReducedLevelSets(const ReducedProblem& rp, const ReducedLevelSetOptions& options,
                                   std::vector<MaxFlow>& networks, std::vector<double>& X);

}  // namespace al::cp
