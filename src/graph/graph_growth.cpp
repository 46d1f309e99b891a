// GrowRefineGraph (al/graph/graph.hpp): a later round of candidate growth from the state the
// previous build kept (graph_internal.hpp). Only the new candidates are searched for, queried for
// their kNN and compared feature by feature; the steps over the whole graph that depend on every
// node (σ_x, the removed set's parts, the feature prior, the weights) run again on cached inputs,
// so the result is the one BuildRefineGraph would return.
#include <algorithm>
#include <cmath>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"
#include "al/graph/candidates.hpp"
#include "al/graph/graph.hpp"
#include "src/graph/graph_internal.hpp"

namespace al {
namespace {

// Seeds the previous build did not grow from.
std::vector<std::uint8_t> FreshSeeds(const graph_internal::SceneNodes& s, const std::vector<std::uint8_t>& extra) {
  std::vector<std::uint8_t> fresh(s.seeds.size(), 0);
  for (std::size_t i = 0; i < fresh.size(); ++i) fresh[i] = extra[i] && s.active[i] && !s.seeds[i];
  return fresh;
}

// The candidates that growing from extra adds to the state's.
std::vector<std::int64_t> AddedRows(const GraphGrowthState& state, const std::vector<std::uint8_t>& extra) {
  const std::vector<std::uint8_t> fresh = FreshSeeds(state.scene, extra);
  const std::vector<std::uint8_t> hit = GrowCandidates(state.scene.xyz, state.scene.radii, state.scene.active, fresh, 1);
  std::vector<std::int64_t> rows;
  for (std::size_t i = 0; i < hit.size(); ++i)
    if (hit[i] && !state.candidate[i]) rows.push_back(std::int64_t(i));
  return rows;
}

// The candidate statistics BuildRefineGraph would report for the grown seed set (hops = 1).
void CandidateCounts(const graph_internal::SceneNodes& s, std::size_t nodes, GraphStats& st) {
  std::vector<double> r;
  std::size_t seeds = 0;
  for (std::size_t i = 0; i < s.seeds.size(); ++i)
    if (s.seeds[i] && s.active[i]) ++seeds, r.push_back(s.radii[i]);
  st.added_per_hop = {nodes - seeds};
  st.huge_spheres = 0;
  if (r.empty()) return;
  std::nth_element(r.begin(), r.begin() + std::ptrdiff_t(r.size() / 2), r.end());
  const double huge = 8.0 * r[r.size() / 2];
  for (double x : r) st.huge_spheres += x > huge;
}

// The merged node list (ascending scene rows), each old node's new index and each node's old one.
struct NodeMerge {
  std::vector<std::int64_t> ids;
  std::vector<std::int32_t> new_of_old, old_of, added;
};
NodeMerge MergeNodes(const std::vector<std::int64_t>& old_ids, const std::vector<std::int64_t>& new_rows) {
  NodeMerge m;
  m.ids.resize(old_ids.size() + new_rows.size());
  std::merge(old_ids.begin(), old_ids.end(), new_rows.begin(), new_rows.end(), m.ids.begin());
  m.old_of.assign(m.ids.size(), -1);
  m.new_of_old.resize(old_ids.size());
  std::size_t o = 0;
  for (std::size_t v = 0; v < m.ids.size(); ++v) {
    if (o < old_ids.size() && old_ids[o] == m.ids[v]) {
      m.old_of[v] = std::int32_t(o);
      m.new_of_old[o++] = std::int32_t(v);
    } else {
      m.added.push_back(std::int32_t(v));
    }
  }
  return m;
}

// Node positions and observations (the mask) of the merged node list; returns its feature rows,
// mapped again through the previous build's feature map (the same rows as before for old nodes).
RowMatXf FillNodes(const NodeMerge& m, const std::vector<bool>& removed, const SceneFeatureMap& map,
                   GraphGrowthState& state, GraphResult& out) {
  RefineProblem& P = out.problem;
  const std::size_t V = m.ids.size();
  P.node_ids = m.ids;
  P.y_remove.resize(V);
  P.node_weights.assign(V, 1.0);
  std::vector<float> xyz(3 * V);
  const auto vv = static_cast<std::int64_t>(V);
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < vv; ++v) {
    const std::size_t i = std::size_t(m.ids[std::size_t(v)]);
    P.y_remove[std::size_t(v)] = removed[i] ? 1.0 : 0.0;
    for (int a = 0; a < 3; ++a) xyz[3 * std::size_t(v) + a] = state.scene.xyz[3 * i + a];
  }
  state.node_xyz = std::move(xyz);
  return graph_internal::NodeFeatures(map, P.node_ids, out.zero_norm);
}

// The state to grow: the previous build's own when nothing else shares it, else a copy.
std::shared_ptr<GraphGrowthState> OwnState(GraphResult& previous) {
  if (previous.growth.use_count() == 1) return std::move(previous.growth);
  return std::make_shared<GraphGrowthState>(*previous.growth);
}

}  // namespace

std::optional<std::vector<std::int64_t>> NewCandidateRows(const GraphResult& previous,
                                                          const std::vector<std::uint8_t>& extra_seeds) {
  const GraphGrowthState* state = previous.growth.get();
  if (!state || extra_seeds.size() != state->candidate.size()) return std::nullopt;
  return AddedRows(*state, extra_seeds);
}

GraphResult GrowRefineGraph(const Scene& scene, Eigen::Ref<const RowMatXf> features, const std::vector<bool>& removed,
                            const GraphOptions& options, GraphResult previous,
                            const std::vector<std::uint8_t>& extra_seeds, const std::vector<std::int64_t>* known_rows) {
  if (!previous.growth || options.hops != 1 || options.knn_checks != 0 || extra_seeds.size() != scene.size() ||
      previous.growth->candidate.size() != scene.size())
    return BuildRefineGraph(scene, features, removed, options, &extra_seeds);
  options.Check();
  Timer total, stage;
  std::shared_ptr<GraphGrowthState> state = OwnState(previous);
  const std::vector<std::int64_t> new_rows = known_rows ? *known_rows : AddedRows(*state, extra_seeds);
  for (std::size_t i = 0; i < extra_seeds.size(); ++i) state->scene.seeds[i] = state->scene.seeds[i] || extra_seeds[i];
  for (std::int64_t i : new_rows) state->candidate[std::size_t(i)] = 1;
  const NodeMerge merge = MergeNodes(previous.problem.node_ids, new_rows);
  GraphResult out = graph_internal::NewGraphResult(scene, features, options, state->gate);
  GraphStats& st = out.stats;
  const GraphStats& before = previous.stats;
  st.excluded_nonfinite = before.excluded_nonfinite;
  st.removed_nodes = before.removed_nodes;
  st.centred = before.centred;
  st.common_component = before.common_component;
  st.nodes = merge.ids.size();
  CandidateCounts(state->scene, st.nodes, st);
  out.excluded = std::move(previous.excluded);
  out.feature_mean = previous.feature_mean;
  out.problem.kl_smoothing = options.kl_smoothing;
  const SceneFeatureMap map{features, options.normalize_features, before.centred, previous.feature_mean};
  const RowMatXf node_features = FillNodes(merge, removed, map, *state, out);
  st.seconds_candidates = stage.Seconds();
  stage.Reset();
  KnnOptions ko;
  ko.k = options.k;
  state->knn = KnnWithAddedPoints(state->node_xyz, state->knn, merge.new_of_old, merge.added, ko);
  st.knn_tie_retries = state->knn.tie_retries;
  st.seconds_knn = stage.Seconds();
  stage.Reset();
  graph_internal::PairCache pairs = graph_internal::UniquePairs(state->knn, st.nodes);
  graph_internal::PairDistances(pairs, node_features, out.zero_norm, &state->pairs, &merge.old_of);
  state->pairs = std::move(pairs);
  graph_internal::FinishGraph(*state, node_features, features, options, out);
  st.seconds_edges = stage.Seconds();
  st.seconds_total = total.Seconds();
  out.growth = std::move(state);
  return out;
}

}  // namespace al
