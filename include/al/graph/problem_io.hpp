// Export / import of a RefineProblem as .npy files (for comparisons with external solvers such as
// pycut-pursuit): first_edge (int64 V+1), adj_vertices (int64 E), edge_weights (float64 E),
// y (float64 V x 2, columns remove/keep), node_weights (float64 V), node_ids (int64 V),
// params.json ({"s", "metric": "d1", "lambda" when known}) and p.npy (float64 V) when p is given.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "al/graph/problem.hpp"

namespace al {

// Writes the files into dir (created if needed), each atomically. lambda: recorded when known.
void ExportProblem(const RefineProblem& problem, const std::vector<double>* p, const std::string& dir,
                   std::optional<double> lambda = std::nullopt);

// Reads a directory written by ExportProblem; validates shapes, ranges and the CSR invariants.
// Throws al::Error naming the file on any problem.
RefineProblem ImportProblem(const std::string& dir);

}  // namespace al
