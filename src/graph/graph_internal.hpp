// The pieces of BuildRefineGraph (graph.cpp) that a later round of candidate growth reuses
// (graph_growth.cpp): what the first build learnt about the scene, the candidates' kNN lists, their
// feature rows and the squared feature distance of every kNN pair. Internal to src/graph.
#pragma once
#include <cstdint>
#include <vector>

#include "al/graph/graph.hpp"
#include "al/graph/knn.hpp"
#include "al/graph/taken_whole.hpp"

namespace al {

struct GraphGrowthState;  // below

namespace graph_internal {

// Step 1 of the build: which Gaussians take part (every parameter and feature finite, a finite
// sphere), their positions, sphere radii and whether the candidate set grows from them.
struct SceneNodes {
  std::vector<std::uint8_t> active, seeds;
  std::vector<double> radii;
  std::vector<float> xyz;
};

// The kNN pairs stored once at their smaller node (CSR over nodes, each row ascending, no
// repeats) with the squared distance of their feature rows; -1 where an end has a zero-norm
// feature (no edge whatever the gate).
struct PairCache {
  std::vector<std::int64_t> row_start;
  std::vector<std::int32_t> other;
  std::vector<double> df2;
};

// Squared distance of points u and v of a 3n position array, in double.
inline double SquaredDistance(const std::vector<float>& xyz, std::size_t u, std::size_t v) {
  double s = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = double(xyz[3 * u + a]) - xyz[3 * v + a];
    s += d * d;
  }
  return s;
}

// The unique pairs of a kNN result (no distances yet).
PairCache UniquePairs(const KnnResult& knn, std::size_t num_nodes);

// Fills pairs.df2. With `previous` (the pair cache of the round before) and old_of (per node, its
// index in that round or -1 for a new node), a pair of two old nodes takes its distance from there
// instead of recomputing it: node rows do not change between rounds.
void PairDistances(PairCache& pairs, const RowMatXf& node_features, const std::vector<std::uint8_t>& zero_norm,
                   const PairCache* previous = nullptr, const std::vector<std::int32_t>* old_of = nullptr);

// The semantic gate and the weights λ exp(-d_f²/σ_f²) [exp(-d_x²/σ_x²)] of the cached pairs, compacted
// into the problem's CSR (edges_knn and edges counted in st).
void GateAndWeigh(const PairCache& pairs, const std::vector<float>& node_xyz, double gate,
                  const GraphOptions& options, RefineProblem& problem, GraphStats& stats);

GraphResult NewGraphResult(const Scene& scene, Eigen::Ref<const RowMatXf> features, const GraphOptions& options,
                           double gate);
// The steps after the kNN lists, node features and pair distances, for the first build and the
// growth rounds alike: σ_x, the removed set's parts, the feature prior, the gate and weights, the
// components and the warnings. out.problem holds the nodes with the mask as y_remove.
void FinishGraph(const al::GraphGrowthState& state, const RowMatXf& node_features, Eigen::Ref<const RowMatXf> features,
                 const GraphOptions& options, GraphResult& out);

// The nodes' feature rows as the gate compares them (zero rows for zero norm, flagged). Not kept
// between growth rounds (a round maps them again: 88 MB fewer held through the solve at 3M).
RowMatXf NodeFeatures(const SceneFeatureMap& map, const std::vector<std::int64_t>& node_ids,
                      std::vector<std::uint8_t>& zero_norm);

}  // namespace graph_internal

// What a graph build keeps for the next round of candidate growth (GraphResult::growth).
struct GraphGrowthState {
  graph_internal::SceneNodes scene;
  std::vector<std::uint8_t> candidate;  // N: in the candidate set
  std::vector<float> node_xyz;          // 3V node positions
  KnnResult knn;                        // among the nodes
  graph_internal::PairCache pairs;
  double gate = 0.0;
};

}  // namespace al
