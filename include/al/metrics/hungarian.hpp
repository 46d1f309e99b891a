// Maximum-weight one-to-one assignment on a rectangular matrix (Hungarian method with potentials,
// shortest augmenting paths, O(min(n,m)²·max(n,m))). Used by sim_SAM (METRICS.md §3).
#pragma once
#include <vector>

namespace al::metrics {

struct Assignment {
  std::vector<int> row_to_col;  // size rows; -1 = unassigned (only when rows > cols)
  double total = 0;             // Σ weight of the assigned pairs, summed in row order
};

// weights: rows × cols, row-major. Assigns min(rows, cols) pairs maximising the total weight.
// Weights must be finite (the caller's IoUs are in [0, 1]).
Assignment MaxWeightAssignment(const std::vector<double>& weights, int rows, int cols);

// Reference by enumeration of all injections of the smaller side (tests only; ≤ ~9 each side).
double MaxWeightAssignmentBruteForce(const std::vector<double>& weights, int rows, int cols);

}  // namespace al::metrics
