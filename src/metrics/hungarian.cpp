#include "al/metrics/hungarian.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>

#include "al/core/error.hpp"

namespace al::metrics {

namespace {

// Minimum-cost assignment of every row (n ≤ m) to a distinct column; cost(i, j) 0-based.
// Returns col_of_row. Classical potentials formulation: each row is added by a Dijkstra-like
// search for the cheapest augmenting path in reduced costs.
std::vector<int> MinCostRowsToCols(int n, int m, const std::function<double(int, int)>& cost) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> row_of_col(m + 1, 0), way(m + 1, 0);  // 1-based rows, column 0 is virtual
  for (int i = 1; i <= n; ++i) {
    row_of_col[0] = i;
    int j0 = 0;
    std::vector<double> min_reduced(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = row_of_col[j0];
      double delta = inf;
      int j1 = -1;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double reduced = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < min_reduced[j]) min_reduced[j] = reduced, way[j] = j0;
        if (min_reduced[j] < delta) delta = min_reduced[j], j1 = j;
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[row_of_col[j]] += delta;
          v[j] -= delta;
        } else {
          min_reduced[j] -= delta;
        }
      }
      j0 = j1;
    } while (row_of_col[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      row_of_col[j0] = row_of_col[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col_of_row(n, -1);
  for (int j = 1; j <= m; ++j)
    if (row_of_col[j] > 0) col_of_row[row_of_col[j] - 1] = j - 1;
  return col_of_row;
}

void CheckShape(const std::vector<double>& weights, int rows, int cols) {
  if (rows < 0 || cols < 0 || weights.size() != std::size_t(rows) * std::size_t(cols))
    throw Error("assignment: weight matrix does not match its shape");
}

}  // namespace

Assignment MaxWeightAssignment(const std::vector<double>& weights, int rows, int cols) {
  CheckShape(weights, rows, cols);
  Assignment a;
  a.row_to_col.assign(rows, -1);
  if (rows == 0 || cols == 0) return a;
  if (rows <= cols) {
    a.row_to_col = MinCostRowsToCols(rows, cols, [&](int i, int j) { return -weights[std::size_t(i) * cols + j]; });
  } else {  // transpose so that the smaller side is the one fully assigned
    const auto row_of_col =
        MinCostRowsToCols(cols, rows, [&](int j, int i) { return -weights[std::size_t(i) * cols + j]; });
    for (int j = 0; j < cols; ++j) a.row_to_col[row_of_col[j]] = j;
  }
  for (int i = 0; i < rows; ++i)
    if (a.row_to_col[i] >= 0) a.total += weights[std::size_t(i) * cols + a.row_to_col[i]];
  return a;
}

double MaxWeightAssignmentBruteForce(const std::vector<double>& weights, int rows, int cols) {
  CheckShape(weights, rows, cols);
  const bool transpose = rows > cols;
  const int small = transpose ? cols : rows, large = transpose ? rows : cols;
  auto w = [&](int s, int l) {
    return transpose ? weights[std::size_t(l) * cols + s] : weights[std::size_t(s) * cols + l];
  };
  double best = 0;
  std::vector<char> taken(large, 0);
  std::function<void(int, double)> recurse = [&](int s, double sum) {
    if (s == small) {
      best = std::max(best, sum);
      return;
    }
    for (int l = 0; l < large; ++l) {
      if (taken[l]) continue;
      taken[l] = 1;
      recurse(s + 1, sum + w(s, l));
      taken[l] = 0;
    }
  };
  if (small > 0) {
    best = -std::numeric_limits<double>::infinity();
    recurse(0, 0.0);
  }
  return best;
}

}  // namespace al::metrics
