// BuildRefineGraph: SPEC §4 end to end (see graph.hpp). Every parallel loop writes per-item
// results and every reduction runs sequentially, so the graph does not depend on the thread count.
#include "al/graph/graph.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <type_traits>
#include <utility>

#include "al/core/error.hpp"
#include "al/core/first_touch.hpp"
#include "al/core/memory_limit.hpp"
#include "al/core/timer.hpp"
#include "al/graph/candidates.hpp"
#include "al/graph/disjoint_sets.hpp"
#include "al/graph/knn.hpp"
#include "al/graph/prior.hpp"
#include "src/graph/graph_internal.hpp"
#include "src/graph/robust_stats.hpp"

namespace al {

using graph_internal::SceneNodes;
using graph_internal::SquaredDistance;

namespace {

// x·0 is ±0 for a finite x and NaN for ±inf or NaN, so the row is finite iff the sum is 0: one
// branch per row instead of one per value (3M rows of 32 features at 3M).
bool RowFinite(const auto& m, Eigen::Index i) {
  using Scalar = std::remove_cvref_t<decltype(m(i, 0))>;
  Scalar zero_if_finite = 0;
  for (Eigen::Index c = 0; c < m.cols(); ++c) zero_if_finite += m(i, c) * Scalar(0);
  return zero_if_finite == Scalar(0);
}

// Mean of the L2-normalised feature rows of the active Gaussians: a strided sample of at most
// 65,536 rows (a common component is a property of the whole field, so a sample finds it, and
// the cost stays bounded on million-Gaussian scenes). Sequential sum: thread-count independent.
Eigen::VectorXd SceneFeatureMean(Eigen::Ref<const RowMatXf> features, const std::vector<std::uint8_t>& active) {
  const Eigen::Index N = features.rows(), D = features.cols();
  const Eigen::Index stride = std::max<Eigen::Index>(1, (N + 65535) / 65536);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(D);
  std::size_t n = 0;
  // The sampled rows are pages apart: each would wait for its own miss, so rows a few steps
  // ahead are fetched while this one is summed (3M rows: 0.03 -> 0.00x s; same sums).
  constexpr Eigen::Index kAhead = 16;
  for (Eigen::Index i = 0; i < N; i += stride) {
    if (const Eigen::Index next = i + kAhead * stride; next < N) {
      const char* row = reinterpret_cast<const char*>(features.row(next).data());
      for (Eigen::Index b = 0; b < D * Eigen::Index(sizeof(float)); b += 64) __builtin_prefetch(row + b);
      __builtin_prefetch(&active[std::size_t(next)]);
    }
    if (!active[std::size_t(i)]) continue;
    // Plain loops: with Eigen temporaries this was a sixth of a refine's time on a 512-D field.
    const float* f = features.row(i).data();
    double ss = double(features.row(i).squaredNorm());  // vectorised (float, reassociated)
    if (!(ss > 0) || !std::isfinite(ss)) ss = features.row(i).cast<double>().squaredNorm();  // float's range left
    if (!(ss > 0) || !std::isfinite(ss)) continue;
    const double inv = 1.0 / std::sqrt(ss);
    for (Eigen::Index d = 0; d < D; ++d) sum[d] += double(f[d]) * inv;
    ++n;
  }
  return n ? Eigen::VectorXd(sum / double(n)) : sum;
}

// Whether to centre, given the options and the scene's mean unit feature (graph.hpp, Centring).
bool ShouldCentre(const GraphOptions& o, const Eigen::VectorXd& mean) {
  if (!o.normalize_features || o.centre == Centring::kOff) return false;
  // All features parallel: centring would leave nothing (and there is nothing to centre away).
  if (mean.norm() >= 1.0 - 1e-6) return false;
  return o.centre != Centring::kShared || mean.norm() >= kSharedComponentNorm;
}

SceneFeatureMap FeatureMapFor(Eigen::Ref<const RowMatXf> features, const std::vector<std::uint8_t>& active,
                              const GraphOptions& o, GraphStats& stats) {
  SceneFeatureMap map{features, o.normalize_features, false, Eigen::VectorXd::Zero(features.cols())};
  if (o.normalize_features && o.centre != Centring::kOff) map.mean = SceneFeatureMean(features, active);
  map.centre = ShouldCentre(o, map.mean);
  stats.common_component = map.mean.norm();
  stats.centred = map.centre;
  return map;
}

}  // namespace

namespace graph_internal {

RowMatXf NodeFeatures(const SceneFeatureMap& map, const std::vector<std::int64_t>& node_ids,
                      std::vector<std::uint8_t>& zero_norm) {
  const std::size_t V = node_ids.size();
  RowMatXf out(Eigen::Index(V), map.features.cols());
  FirstTouchMatrix(out);  // the static split below would leave the heap's fresh end to one thread
  zero_norm.assign(V, 0);
  const auto vv = static_cast<std::int64_t>(V);
#pragma omp parallel
  {
    // Each row is mapped in an aligned buffer: Eigen's vectorised norms start where the data is
    // aligned, so a row's last bits must not depend on where in the matrix it lands (a growth round
    // maps the same row again at another index).
    Eigen::VectorXf row(map.features.cols());
#pragma omp for schedule(static)
    for (std::int64_t v = 0; v < vv; ++v) {
      zero_norm[std::size_t(v)] = !map.Row(node_ids[std::size_t(v)], row.data()) && map.normalize;
      out.row(v) = row.transpose();
    }
  }
  return out;
}

}  // namespace graph_internal

RowMatXf ColourFeatures(const Scene& scene) {
  if (scene.sh.rows() != static_cast<Eigen::Index>(scene.size()) || scene.sh.cols() < 3)
    throw Error(scene.source_path + ": no f_dc colour columns for the colour fallback", ExitCode::kBadInput);
  constexpr float kC0 = 0.28209479177387814f;
  RowMatXf rgb(scene.size(), 3);
  for (std::size_t i = 0; i < scene.size(); ++i)
    for (int c = 0; c < 3; ++c) rgb(i, c) = 0.5f + kC0 * scene.sh(i, c);
  return rgb;
}

namespace {

// Size checks of the data and the options' ranges (the table's words); returns the gate distance.
double CheckGraphInputs(const Scene& scene, Eigen::Ref<const RowMatXf> features, const std::vector<bool>& removed,
                        const GraphOptions& options, const std::vector<std::uint8_t>* extra_seeds) {
  const std::size_t N = scene.size();
  const auto n_rows = static_cast<Eigen::Index>(N);
  if (extra_seeds && extra_seeds->size() != N) throw Error("extra candidate seeds: wrong size", ExitCode::kInternal);
  if (removed.size() != N)
    throw Error("removal mask has " + std::to_string(removed.size()) + " entries, scene has " + std::to_string(N),
                ExitCode::kBadInput);
  if (features.rows() != n_rows || features.cols() == 0)
    throw Error("features: expected " + std::to_string(N) + " rows with D > 0, got " + std::to_string(features.rows()) +
                    "x" + std::to_string(features.cols()),
                ExitCode::kBadInput);
  if (scene.log_scales.rows() != n_rows) throw Error(scene.source_path + ": scale columns missing", ExitCode::kBadInput);
  options.Check();
  if (options.delta_mode != DeltaMode::kCosine) return options.delta;
  if (!options.normalize_features)
    throw Error("graph option 'delta_mode' = cosine needs normalised semantic features (not the colour fallback)",
                ExitCode::kUsage);
  return std::sqrt(2.0 * (1.0 - options.delta));
}

// Step 1 (graph_internal.hpp, SceneNodes).
SceneNodes ActiveGaussians(const Scene& scene, Eigen::Ref<const RowMatXf> features, const std::vector<bool>& removed,
                           const GraphOptions& options, const std::vector<std::uint8_t>* extra_seeds) {
  const std::size_t N = scene.size();
  const auto n_rows = static_cast<Eigen::Index>(N);
  SceneNodes s;
  ReserveFirstTouched(s.radii, N);
  ReserveFirstTouched(s.xyz, 3 * N);
  s.active.resize(N);
  s.seeds.resize(N);
  s.radii.resize(N);
  s.xyz.resize(3 * N);
  const bool has_rot = scene.rotations.rows() == n_rows;
  const bool has_op = scene.opacity_logits.size() == n_rows;
  const bool has_sh = scene.sh.rows() == n_rows;
  const bool has_undecoded = scene.nonfinite_undecoded.size() == N;
  const auto nn = static_cast<std::int64_t>(N);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < nn; ++i) {
    bool ok = RowFinite(scene.means, i) && RowFinite(scene.log_scales, i) && RowFinite(features, i) &&
              (!has_rot || RowFinite(scene.rotations, i)) && (!has_op || std::isfinite(scene.opacity_logits[i])) &&
              (!has_sh || RowFinite(scene.sh, i)) && (!has_undecoded || !scene.nonfinite_undecoded[std::size_t(i)]);
    // exp is monotone: the exponential of the largest log-scale is the largest scale (one call, not three).
    float largest = scene.log_scales(i, 0);
    for (int a = 0; a < 3; ++a) {
      s.xyz[3 * i + a] = scene.means(i, a);
      largest = std::max(largest, scene.log_scales(i, a));
    }
    double r = std::exp(double(largest));
    r *= options.radius_scale;
    if (!std::isfinite(r)) ok = false;  // exp overflow: no usable sphere
    s.active[i] = ok;
    s.radii[i] = r;
    s.seeds[i] = removed[i] || (extra_seeds && (*extra_seeds)[i]) ? 1 : 0;
  }
  return s;
}

// Step 2: the candidate nodes (ascending scene index), their observations y and positions.
std::vector<float> SelectCandidates(const SceneNodes& s, const std::vector<bool>& removed, const GraphOptions& options,
                                    GraphResult& out, std::vector<std::uint8_t>& in_c) {
  GraphStats& st = out.stats;
  const std::size_t N = removed.size();
  CandidateStats cst;
  in_c = GrowCandidates(s.xyz, s.radii, s.active, s.seeds, options.hops, &cst);
  for (std::size_t i = 0; i < N; ++i) st.removed_nodes += removed[i] && s.active[i];
  st.added_per_hop = cst.added_per_hop;
  st.huge_spheres = cst.huge_spheres;
  RefineProblem& P = out.problem;
  P.kl_smoothing = options.kl_smoothing;
  for (std::size_t i = 0; i < N; ++i)
    if (in_c[i]) P.node_ids.push_back(static_cast<std::int64_t>(i));
  const std::size_t V = P.node_ids.size();
  st.nodes = V;
  // kNN lists, both CSR directions with weights, the solvers' copies (cut pursuit keeps a flow
  // network and per-edge iterates): ~100 B per (node, neighbour) plus ~300 B per node.
  CheckMemoryEstimate("the refinement graph of " + std::to_string(V) + " nodes with k = " + std::to_string(options.k),
                      double(V) * (100.0 * std::max(1, options.k) + 300.0));
  P.y_remove.resize(V);
  P.node_weights.assign(V, 1.0);
  std::vector<float> node_xyz(3 * V);
  for (std::size_t v = 0; v < V; ++v) {
    const std::size_t i = static_cast<std::size_t>(P.node_ids[v]);
    P.y_remove[v] = removed[i] ? 1.0 : 0.0;
    for (int a = 0; a < 3; ++a) node_xyz[3 * v + a] = s.xyz[3 * i + a];
  }
  return node_xyz;
}

// σ_x: median non-zero kNN distance (unit-free), else the median candidate radius.
void SpatialScale(double median_edge, const SceneNodes& s, const RefineProblem& P, const GraphOptions& options,
                  GraphStats& st) {
  if (!options.spatial) {
    st.sigma_x_source = "off";
    return;
  }
  if (median_edge > 0) {
    st.sigma_x = median_edge;
    st.sigma_x_source = "median_knn_distance";
    return;
  }
  const std::size_t V = P.node_ids.size();
  std::vector<double> r(V);
  for (std::size_t v = 0; v < V; ++v) r[v] = s.radii[P.node_ids[v]];
  st.sigma_x = MedianOf(std::move(r));
  st.sigma_x_source = "median_radius";
}

// Step 5: connected components (singletons included) and isolated nodes.
void CountComponents(const RefineProblem& P, GraphStats& st) {
  const auto V = static_cast<std::int64_t>(P.node_ids.size());
  ConcurrentDisjointSets sets{static_cast<std::size_t>(V)};
  std::vector<std::uint8_t> has_edge(std::size_t(V), 0);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t u = 0; u < V; ++u)
    for (auto e = P.first_edge[u]; e < P.first_edge[u + 1]; ++e) {
      const std::int32_t v = P.adj_vertices[e];
      // Byte stores of the same value 1 from two threads: no other value is ever written.
      std::atomic_ref(has_edge[std::size_t(u)]).store(1, std::memory_order_relaxed);
      std::atomic_ref(has_edge[std::size_t(v)]).store(1, std::memory_order_relaxed);
      sets.Unite(static_cast<std::int32_t>(u), v);
    }
  std::size_t components = 0, isolated = 0;
#pragma omp parallel for schedule(static) reduction(+ : components, isolated)
  for (std::int64_t v = 0; v < V; ++v) {
    components += sets.Find(static_cast<std::int32_t>(v)) == static_cast<std::int32_t>(v);
    isolated += !has_edge[std::size_t(v)];
  }
  st.components += components;
  st.isolated += isolated;
}

void AddGraphWarnings(GraphResult& out) {
  const GraphStats& st = out.stats;
  if (st.excluded_nonfinite > 0)
    out.warnings.push_back(std::to_string(st.excluded_nonfinite) +
                           " Gaussians with non-finite parameters or features were excluded from the graph");
  if (st.zero_norm_features > 0)
    out.warnings.push_back(std::to_string(st.zero_norm_features) +
                           " candidate nodes have zero-norm features and get no semantic edges");
  if (st.second_object.Found()) {
    const SecondObject& so = st.second_object;
    char cosine[16];
    std::snprintf(cosine, sizeof cosine, "%.2f", so.cosine);
    out.warnings.push_back("the removed set holds a second object: a separate part of " + std::to_string(so.rows) +
                           " Gaussians beside one of " + std::to_string(so.largest_rows) +
                           ", mean features at cosine " + cosine + (st.prior.kept_credit ? "" :
                           "; kept Gaussians get no feature credit (either may be the target; "
                           "--no-second-object-guard credits them)"));
  }
}

}  // namespace

namespace {

// The kNN edges' squared lengths (0 for a missing neighbour), visited row by row in parallel.
class EdgeLengths {
 public:
  EdgeLengths(const KnnResult& knn, const std::vector<float>& xyz)
      : knn_(knn), xyz_(xyz), k_(std::size_t(std::max(knn.k, 0))), rows_(k_ > 0 ? knn.neighbors.size() / k_ : 0) {}
  double operator()(std::size_t u, std::size_t c) const {
    const std::int32_t v = knn_.neighbors[u * k_ + c];
    return v < 0 ? 0.0 : SquaredDistance(xyz_, u, std::size_t(v));
  }
  std::size_t k() const { return k_; }
  std::int64_t rows() const { return static_cast<std::int64_t>(rows_); }

 private:
  const KnnResult& knn_;
  const std::vector<float>& xyz_;
  std::size_t k_, rows_;
};

// Positive doubles order like their bit patterns; the top 16 bits (exponent and 4 mantissa bits)
// split the lengths into buckets.
std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }
constexpr int kBucketShift = 48;

// How many non-zero squared lengths fall in each bucket (per-thread histograms, then summed).
std::vector<std::int64_t> BucketCounts(const EdgeLengths& len) {
  std::vector<std::int64_t> count(std::size_t{1} << 16, 0);
#pragma omp parallel
  {
    std::vector<std::int64_t> mine(count.size(), 0);
#pragma omp for schedule(static)
    for (std::int64_t u = 0; u < len.rows(); ++u)
      for (std::size_t c = 0; c < len.k(); ++c)
        if (const double x2 = len(std::size_t(u), c); x2 > 0) ++mine[Bits(x2) >> kBucketShift];
#pragma omp critical(al_median_buckets)
    for (std::size_t b = 0; b < count.size(); ++b) count[b] += mine[b];
  }
  return count;
}

// The rank-th and (rank+1)-th smallest non-zero squared lengths (0-based; the second only when
// want_next), exactly: their buckets from the counts, then only those buckets' values gathered (one
// pass) and selected.
std::pair<double, double> RankedLength2(const EdgeLengths& len, const std::vector<std::int64_t>& count,
                                        std::int64_t rank, bool want_next) {
  std::uint64_t first = 0;
  while (rank >= count[first]) rank -= count[first++];
  std::uint64_t last = first;  // the next rank's bucket: the first non-empty one after, if rank ends it
  if (want_next && rank + 1 == count[first])
    for (last = first + 1; count[last] == 0; ++last) {}
  std::vector<double> in_buckets;
  in_buckets.reserve(std::size_t(count[first] + (last != first ? count[last] : 0)));
#pragma omp parallel
  {
    std::vector<double> mine;
#pragma omp for schedule(static) nowait
    for (std::int64_t u = 0; u < len.rows(); ++u)
      for (std::size_t c = 0; c < len.k(); ++c)
        if (const double x2 = len(std::size_t(u), c); x2 > 0) {
          const std::uint64_t b = Bits(x2) >> kBucketShift;
          if (b == first || b == last) mine.push_back(x2);
        }
#pragma omp critical(al_median_gather)
    in_buckets.insert(in_buckets.end(), mine.begin(), mine.end());
  }
  // Every value of `last` is above every value of `first`: the ranks hold within the union.
  const auto at = in_buckets.begin() + rank;
  std::nth_element(in_buckets.begin(), at, in_buckets.end());
  const double next = want_next ? *std::min_element(at + 1, in_buckets.end()) : 0.0;
  return {*at, next};
}

}  // namespace

// Exact median without a copy of all lengths (8M doubles at 3M Gaussians): a radix select over
// the lengths' bit patterns, recomputing them per pass (3M room scene: 0.19 s -> 0.05 s).
double MedianKnnEdgeLength(const KnnResult& knn, const std::vector<float>& xyz) {
  const EdgeLengths len(knn, xyz);
  if (len.k() == 0) return 0.0;
  const std::vector<std::int64_t> count = BucketCounts(len);
  const std::int64_t total = std::accumulate(count.begin(), count.end(), std::int64_t{0});
  if (total == 0) return 0.0;
  const std::int64_t h = total / 2;
  // sqrt is monotone: the median length is the root of the median squared length.
  if (total % 2) return std::sqrt(RankedLength2(len, count, h, false).first);
  const auto [below, above] = RankedLength2(len, count, h - 1, true);
  return 0.5 * (std::sqrt(above) + std::sqrt(below));
}

namespace graph_internal {

GraphResult NewGraphResult(const Scene& scene, Eigen::Ref<const RowMatXf> features, const GraphOptions& options,
                           double gate) {
  GraphResult out;
  GraphStats& st = out.stats;
  st.num_gaussians = scene.size();
  st.feature_dim = static_cast<std::size_t>(features.cols());
  st.gate_distance = gate;
  st.sigma_f = gate * options.FeatureWidth();
  st.lambda = options.Lambda();
  return out;
}

void FinishGraph(const GraphGrowthState& state, const RowMatXf& node_features, Eigen::Ref<const RowMatXf> features,
                 const GraphOptions& options, GraphResult& out) {
  RefineProblem& P = out.problem;
  GraphStats& st = out.stats;
  const double median_edge = MedianKnnEdgeLength(state.knn, state.node_xyz);  // σ_x and the removed parts' links
  st.zero_norm_features = static_cast<std::size_t>(std::count(out.zero_norm.begin(), out.zero_norm.end(), 1));
  if (options.normalize_features) {
    st.second_object = FindSecondObject(state.knn, median_edge, P.y_remove, features, P.node_ids);
    const bool guard = options.prior.second_object_guard != PriorSwitch::kOff;
    const KeptCredit credit = guard && st.second_object.Found() ? KeptCredit::kWithheld : KeptCredit::kAllowed;
    std::vector<double> upper;
    const std::vector<double> mask = std::move(P.y_remove);  // the mask before the prior, for the groups
    P.y_remove = FeaturePrior(node_features, mask, options.prior, &st.prior, credit, &upper);
    if (!st.second_object.Found()) st.whole_object_group = FindWholeObjectGroup(st.prior, upper, mask, P.node_ids);
  }
  SpatialScale(median_edge, state.scene, P, options, st);
  GateAndWeigh(state.pairs, state.node_xyz, state.gate, options, P, st);
  CountComponents(P, st);
  AddGraphWarnings(out);
}

}  // namespace graph_internal

// Candidates → kNN → features and prior → gate and weights → components (SPEC §4). What a later
// round of candidate growth can reuse stays in out.growth (GrowRefineGraph, graph_growth.cpp).
GraphResult BuildRefineGraph(const Scene& scene, Eigen::Ref<const RowMatXf> features,
                             const std::vector<bool>& removed, const GraphOptions& options,
                             const std::vector<std::uint8_t>* extra_seeds) {
  Timer total;
  auto state = std::make_shared<GraphGrowthState>();
  state->gate = CheckGraphInputs(scene, features, removed, options, extra_seeds);
  GraphResult out = graph_internal::NewGraphResult(scene, features, options, state->gate);
  GraphStats& st = out.stats;
  Timer stage;
  state->scene = ActiveGaussians(scene, features, removed, options, extra_seeds);
  out.excluded.resize(scene.size());
  for (std::size_t i = 0; i < scene.size(); ++i) {
    out.excluded[i] = !state->scene.active[i];
    st.excluded_nonfinite += !state->scene.active[i];
  }
  RefineProblem& P = out.problem;
  state->node_xyz = SelectCandidates(state->scene, removed, options, out, state->candidate);
  st.seconds_candidates = stage.Seconds();
  stage.Reset();
  KnnOptions ko;
  ko.k = options.k;
  ko.checks = options.knn_checks;
  state->knn = KnnAmongPoints(state->node_xyz, ko);
  st.knn_tie_retries = state->knn.tie_retries;
  st.seconds_knn = stage.Seconds();
  stage.Reset();
  const SceneFeatureMap feature_map = FeatureMapFor(features, state->scene.active, options, st);
  out.feature_mean = feature_map.mean;
  const RowMatXf node_features = graph_internal::NodeFeatures(feature_map, P.node_ids, out.zero_norm);
  state->pairs = graph_internal::UniquePairs(state->knn, P.node_ids.size());
  graph_internal::PairDistances(state->pairs, node_features, out.zero_norm);
  graph_internal::FinishGraph(*state, node_features, features, options, out);
  st.seconds_edges = stage.Seconds();
  st.seconds_total = total.Seconds();
  out.growth = std::move(state);
  return out;
}

nlohmann::json GraphStats::ToJson() const {
  const GraphStats& s = *this;
  return {{"num_gaussians", s.num_gaussians},
          {"excluded_nonfinite", s.excluded_nonfinite},
          {"removed_nodes", s.removed_nodes},
          {"nodes", s.nodes},
          {"added_per_hop", s.added_per_hop},
          {"huge_spheres", s.huge_spheres},
          {"edges_knn", s.edges_knn},
          {"edges", s.edges},
          {"components", s.components},
          {"isolated", s.isolated},
          {"zero_norm_features", s.zero_norm_features},
          {"knn_tie_retries", s.knn_tie_retries},
          {"feature_dim", s.feature_dim},
          {"gate_distance", s.gate_distance},
          {"sigma_f", s.sigma_f},
          {"sigma_x", s.sigma_x},
          {"sigma_x_source", s.sigma_x_source},
          {"lambda", s.lambda},
          {"features_centred", s.centred},
          {"features_common_component", s.common_component},
          {"prior", s.prior.ToJson()},
          {"second_object", s.second_object.ToJson()},
          {"whole_object_group", s.whole_object_group.ToJson()},
          {"seconds", {{"candidates", s.seconds_candidates},
                       {"knn", s.seconds_knn},
                       {"edges", s.seconds_edges},
                       {"total", s.seconds_total}}}};
}

std::string GraphStats::BriefReport() const {
  return "nodes " + std::to_string(nodes) + " (removed " + std::to_string(removed_nodes) + "), edges " +
         std::to_string(edges) + " of " + std::to_string(edges_knn) + " kNN, " + std::to_string(components) +
         (components == 1 ? " component" : " components");
}

}  // namespace al
