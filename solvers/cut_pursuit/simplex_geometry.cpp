// Direction projection onto the simplex tangent cone (CUT_PURSUIT.md §4.2, the CORRECT version) and
// the metric simplex projection used by PFDR.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "solvers/cut_pursuit/cut_pursuit.hpp"

namespace al::cp {

void ProjectDirection(const double* X, const double* r, int D, double eps, bool emulate_bug, double* z) {
  // 0 = free, 1 = at zero, 2 = at one.
  thread_local std::vector<char> state;
  thread_local std::vector<int> zeros;
  state.assign(D, 0);
  zeros.clear();
  int at_one = -1;
  for (int d = 0; d < D; ++d) {
    if (X[d] <= eps) state[d] = 1;
    else if (X[d] >= 1.0 - eps && at_one < 0) { state[d] = 2; at_one = d; }
  }
  for (int d = 0; d < D; ++d) z[d] = 0.0;
  if (at_one >= 0) {
    int best = -1;
    for (int d = 0; d < D; ++d)
      if (state[d] == 1 && (best < 0 || r[d] > r[best])) best = d;
    if (best < 0 || r[at_one] >= r[best]) return;  // a vertex of the simplex with no descent
    state[at_one] = 0;
    state[best] = 0;
  }
  // The bug of upstream pcp averages the component values X instead of the direction r.
  const double* avg_src = emulate_bug ? X : r;
  double sum = 0.0;
  int count = 0;
  for (int d = 0; d < D; ++d)
    if (state[d] == 0) { sum += avg_src[d]; ++count; }
  if (count == 0) return;
  double mu = sum / count;
  for (int d = 0; d < D; ++d)
    if (state[d] == 1) zeros.push_back(d);
  std::stable_sort(zeros.begin(), zeros.end(), [&](int a, int b) { return r[a] > r[b]; });
  for (int d : zeros) {
    if (!(r[d] > mu)) break;
    state[d] = 0;
    sum += avg_src[d];
    ++count;
    mu = sum / count;
  }
  double norm2 = 0.0;
  for (int d = 0; d < D; ++d)
    if (state[d] == 0) {
      z[d] = r[d] - mu;
      norm2 += z[d] * z[d];
    }
  if (norm2 < eps || !std::isfinite(norm2)) {
    for (int d = 0; d < D; ++d) z[d] = 0.0;
    return;
  }
  const double inv = 1.0 / std::sqrt(norm2);
  for (int d = 0; d < D; ++d) z[d] *= inv;
}

void ProjectSimplexMetric(double* x, const double* gamma, int D) {
  // x_d = max(0, x_d - lambda gamma_d) with sum 1; breakpoints x_d / gamma_d visited downwards.
  auto before = [&](int a, int b) {
    return x[a] / gamma[a] > x[b] / gamma[b] || (x[a] / gamma[a] == x[b] / gamma[b] && a < b);
  };
  // PFDR calls this once per component and iteration: D = 2 (the product) needs one comparison, not
  // a sort of a thread_local buffer; the order, hence every result bit, is the same.
  int pair[2];
  thread_local std::vector<int> buffer;
  int* order = pair;
  if (D == 2) {
    pair[0] = before(1, 0) ? 1 : 0;
    pair[1] = 1 - pair[0];
  } else {
    buffer.resize(D);
    std::iota(buffer.begin(), buffer.end(), 0);
    std::sort(buffer.begin(), buffer.end(), before);
    order = buffer.data();
  }
  double sx = 0.0, sg = 0.0, lambda = 0.0;
  for (int k = 0; k < D; ++k) {
    sx += x[order[k]];
    sg += gamma[order[k]];
    lambda = (sx - 1.0) / sg;
    if (k + 1 == D || lambda >= x[order[k + 1]] / gamma[order[k + 1]]) break;
  }
  double total = 0.0;
  for (int d = 0; d < D; ++d) {
    x[d] = std::max(0.0, x[d] - lambda * gamma[d]);
    total += x[d];
  }
  // Rounding repair so the simplex constraint holds to the last bits.
  if (total > 0.0 && total != 1.0) {
    int big = 0;
    for (int d = 1; d < D; ++d)
      if (x[d] > x[big]) big = d;
    double rest = 0.0;
    for (int d = 0; d < D; ++d)
      if (d != big) rest += x[d];
    x[big] = std::max(0.0, 1.0 - rest);
  }
}

}  // namespace al::cp
