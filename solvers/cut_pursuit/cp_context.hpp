// What every step of one cut-pursuit run reads (problem, options, loss, weights, the symmetric
// adjacency), shared by the outer loop (cut_pursuit.cpp) and the split (cp_split.cpp). Internal.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "al/graph/loss.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/level_sets/level_set_partition.hpp"
#include "solvers/max_flow/max_flow.hpp"

namespace al::cp {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Context {
  const SimplexProblemView& pb;
  const CutPursuitOptions& opt;
  int D;
  std::int64_t V;
  Loss loss;
  double eps;
  std::vector<double> nw, m;  // node weights and metric, defaults filled in
  // Symmetric adjacency (neighbour, edge id) for gradients, BFS and the level-set cold start.
  levelset::SymmetricAdjacency adj;
};

// Splits one component c (vertices `verts`, ascending; `local` maps a vertex to its position in
// its component) along two descent directions by a min cut (§4); writes the labels of its vertices
// to `label` and returns true when they differ.
bool SplitComponent(const Context& cx, std::int32_t c, const std::vector<std::int32_t>& comp,
                    const std::vector<double>& rX, const std::vector<std::int32_t>& verts,
                    const std::vector<std::int32_t>& local, std::vector<char>& label, MaxFlow& mf);

}  // namespace al::cp
