// The refinement graph (SPEC §4): candidates by sphere intersection with the removed set, kNN
// among candidates, a semantic gate on feature distance, similarity weights, and the
// RefineProblem every solver takes.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/core/option_table.hpp"
#include "al/graph/either_object.hpp"
#include "al/graph/prior.hpp"
#include "al/graph/removed_parts.hpp"
#include "al/graph/restore_window.hpp"
#include "al/graph/taken_whole.hpp"
#include "al/graph/problem.hpp"
#include "al/scene/scene.hpp"

namespace al {

enum class DeltaMode {
  kDistance,  // δ bounds ‖f̂_u − f̂_v‖ (default; δ = 0.8 ⇔ cosine ≥ 0.68)
  kCosine,    // δ is a cosine threshold; distance bound √(2(1 − δ))
};

// [project, docs/refine.md] Centring of the semantic features: normalised, the scene's mean
// subtracted, normalised again, so a component all features share (CLIP-like fields: every pair
// at cosine ~0.75) does not pass every edge through the gate. It also stretches the small
// differences of features near the scene mean, which costs FGS-like refinement on fields without
// such a component (docs/refine.md), hence kShared.
enum class Centring {
  kAuto,    // the refine stages' preset decides (fgs: kShared, else kOn); a direct caller gets kOn
  kOn,      // always centre
  kOff,     // never (SPEC §4.4 literally)
  kShared,  // centre only when the features share a strong component (kSharedComponentNorm)
};
// |mean of the unit feature rows| from which kShared centres: its square is about the mean
// pairwise cosine, so 0.7 ≈ 0.5. Real and gen_scenes.py CLIP-like fields: 0.87–0.89; the D = 16/32
// fields of gen_scenes.py and al-refine synth: 0.39–0.57.
inline constexpr double kSharedComponentNorm = 0.7;

struct GraphOptions {
  int k = 10;                      // neighbours per node
  double delta = 0.8;              // semantic gate (see delta_mode)
  DeltaMode delta_mode = DeltaMode::kDistance;
  // Edge weight scale (included in edge_weights). Unset = auto: the refine stages take the
  // --method preset's value for the solver (MethodPreset::LambdaFor: 1.5 for gg with bk, else 1);
  // a direct caller of BuildRefineGraph gets 1.
  std::optional<double> lambda;
  double Lambda() const { return lambda.value_or(1.0); }
  // [project] Width of the feature kernel exp(−d_f²/σ_f²) as a multiple of the gate bound: σ_f =
  // feature_width · gate (SPEC §4.4: 1). Unset = auto: the refine stages take the --method
  // preset's (MethodPreset::feature_width: 2 for sags, else 1); a direct caller gets 1. The gate
  // itself (which edges exist) does not change.
  std::optional<double> feature_width;
  double FeatureWidth() const { return feature_width.value_or(1.0); }
  bool spatial = true;             // multiply weights by exp(−d_x²/σ_x²)
  int hops = 1;                    // candidate growth repetitions
  // [project] Rounds of candidate growth where the cut keeps adding (refine stages: after each
  // solve, the candidate set also grows one hop around what was added; stops when the additions
  // no longer change; 8: docs/refine.md). 0 = the fixed candidate set of SPEC §4.2.
  int grow_rounds = 8;
  double radius_scale = 1.0;       // r_i = max_k exp(scale_ik) · radius_scale
  int knn_checks = 0;              // 0 = exact kNN; > 0 approximate (FLANN checks)
  double kl_smoothing = 0.1;       // copied into the problem
  // Features: true = L2-normalise rows, zero-norm rows get no edges (semantic features);
  // false = raw Euclidean distance (colour fallback, SPEC §3).
  bool normalize_features = true;
  Centring centre = Centring::kAuto;  // see Centring; kOff = SPEC §4.4 literally
  // [project] The unary's feature prior (al/graph/prior.hpp); weight 0 = y from the mask alone.
  PriorOptions prior;
  // [project] After the refine stages' last round, restored Gaussians in a feature region the
  // method took whole stay removed (al/graph/taken_whole.hpp); auto = on (every preset). Not read
  // by BuildRefineGraph: the graph is the same either way.
  PriorSwitch taken_whole_guard = PriorSwitch::kAuto;
  // [project] After the last round, restored Gaussians whose cosine to the removed set's prototype
  // lies within restore_window_mads robust σ below the removed median stay removed, unless the
  // removed set holds a second object (al/graph/restore_window.hpp); opt-in: auto = off for every
  // preset (its held-out check failed one criterion, docs/refine.md item 15).
  PriorSwitch restore_window = PriorSwitch::kAuto;
  double restore_window_mads = kRestoreWindowMads;
  // [project] After the last round, when the removed set holds a second object, additions that
  // complete one of the two objects stop where F1 against the other could fall by more than this
  // (al/graph/either_object.hpp); >= 1 = never. Not read by BuildRefineGraph.
  double second_object_tolerance = kEitherObjectTolerance;
  // [project] The same bound for an object group taken whole beside a group of other features
  // taken in part (GraphStats::whole_object_group, al/graph/removed_parts.hpp): auto = only where
  // the additions are a layer of a body that goes on beyond them (al/graph/continuing_body.hpp),
  // on = always, off = never; the readings are reported whatever it says. Not read by
  // BuildRefineGraph.
  PriorSwitch feature_group_bound = PriorSwitch::kAuto;
  double feature_group_tolerance = kFeatureGroupTolerance;  // the bound's tolerance, as above

  // The user-settable fields (normalize_features is set by the feature source, not by users).
  static const OptionTable<GraphOptions>& Table();
  void Check() const;  // the table's ranges, and delta in [-1, 1] in cosine mode
};

struct GraphStats {
  std::size_t num_gaussians = 0;
  std::size_t excluded_nonfinite = 0;   // Gaussians with a non-finite parameter or feature
  std::size_t removed_nodes = 0;        // |R| among finite Gaussians
  std::size_t nodes = 0;                // |C|
  std::vector<std::size_t> added_per_hop;
  std::size_t huge_spheres = 0;
  std::size_t edges_knn = 0;            // undirected kNN edges before the gate
  std::size_t edges = 0;                // after the gate
  std::size_t components = 0;           // connected components of the final graph (singletons included)
  std::size_t isolated = 0;             // nodes without an edge
  std::size_t zero_norm_features = 0;   // candidate nodes whose feature has zero norm
  std::size_t knn_tie_retries = 0;
  std::size_t feature_dim = 0;
  double gate_distance = 0.0;           // distance bound actually applied
  double sigma_f = 0.0;                 // feature kernel width: gate_distance × feature_width
  double lambda = 0.0;                  // edge weight scale applied (--lambda auto resolved)
  bool centred = false;                 // features centred on the scene mean
  double common_component = 0.0;        // |mean of the scene's unit feature rows| (0: not computed)
  PriorStats prior;                     // the unary's feature prior (weight 0: off)
  SecondObject second_object;           // a second object in the removed set (al/graph/removed_parts.hpp)
  FeatureGroupParts whole_object_group;  // ... or its feature groups beside a whole object (same header)
  double sigma_x = 0.0;                 // spatial scale (0 when --spatial off)
  std::string sigma_x_source;           // "median_knn_distance", "median_radius", "off"
  double seconds_candidates = 0.0, seconds_knn = 0.0, seconds_edges = 0.0, seconds_total = 0.0;

  nlohmann::json ToJson() const;  // report.json's "graph" block
  std::string BriefReport() const;  // "nodes 1234 (removed 800), edges 5678 of 9000 kNN, 3 components"
};

struct GraphGrowthState;  // src/graph/graph_internal.hpp

struct GraphResult {
  RefineProblem problem;                // nodes in ascending scene index
  GraphStats stats;
  std::vector<std::uint8_t> excluded;   // N: 1 = non-finite, excluded from the graph
  std::vector<std::uint8_t> zero_norm;  // per node: feature of zero norm
  Eigen::VectorXd feature_mean;         // the scene's mean unit feature (zero when not centring)
  std::vector<std::string> warnings;
  // What a later round of candidate growth reuses (GrowRefineGraph); shared by copies of the result.
  std::shared_ptr<GraphGrowthState> growth;
};

// features: N×D rows (scene order); D = 0 is an error (use ColourFeatures). removed: N.
// extra_seeds (N, optional): more Gaussians the candidate set grows from (candidate growth of
// the refine stages: what a previous cut added); they are candidates, their observation stays
// the mask's. Throws al::Error on size mismatches or bad options.
GraphResult BuildRefineGraph(const Scene& scene, Eigen::Ref<const RowMatXf> features,
                             const std::vector<bool>& removed, const GraphOptions& options = {},
                             const std::vector<std::uint8_t>* extra_seeds = nullptr);

// A later round of candidate growth (the refine stages): the graph BuildRefineGraph would return
// for extra_seeds, from `previous`, built from the same scene, features, removed set and options
// with fewer extra seeds. Only the new candidates are searched, queried for their kNN and
// compared feature by feature; the old nodes' lists change only where a new node comes closer
// than their k-th neighbour. With hops > 1 or approximate kNN (knn_checks > 0), or without
// previous.growth, it builds the graph anew. The result is the same either way.
// new_rows: NewCandidateRows(previous, extra_seeds) when the caller has it already (not searched again).
GraphResult GrowRefineGraph(const Scene& scene, Eigen::Ref<const RowMatXf> features, const std::vector<bool>& removed,
                            const GraphOptions& options, GraphResult previous,
                            const std::vector<std::uint8_t>& extra_seeds,
                            const std::vector<std::int64_t>* new_rows = nullptr);

// The Gaussians (ascending scene rows) that GrowRefineGraph(previous, extra_seeds) would add as
// candidates: those whose spheres meet a sphere of an extra seed not grown from yet. nullopt when
// previous kept no growth state (GrowRefineGraph would then build anew).
std::optional<std::vector<std::int64_t>> NewCandidateRows(const GraphResult& previous,
                                                          const std::vector<std::uint8_t>& extra_seeds);

// Median non-zero length of the kNN edges among the points xyz (n×3 row-major); 0 when every edge
// has length 0 or there is none. The graph's σ_x, and the link length of the removed set's parts.
double MedianKnnEdgeLength(const KnnResult& knn, const std::vector<float>& xyz);

// Colour fallback: RGB = 0.5 + C0 · f_dc (N×3, not normalised). Throws when the scene has no f_dc.
RowMatXf ColourFeatures(const Scene& scene);

}  // namespace al
