// A second object in the removed set [project, docs/refine.md]. A removal method can take two
// objects: FGS a look-alike its prompt also matches, GG a neighbour its hull swallowed. The
// feature prior then credits the kept part of whichever the features point at, and refinement
// completes an object the user did not ask for (synth fgs, tuning half, 60 scenes: 2 lowered by
// more than 0.01 with bk, worst −0.048; 3 with cp, worst −0.061). From the mask alone nobody can
// tell which of the two is the target (in 23 of those 60 masks the look-alike's part was the
// larger), so when the removed set holds a second object the prior credits no kept Gaussian; the
// cut still adds what the graph connects, and removed Gaussians can still be doubted.
//
// "A second object": a spatially separate part of the removed candidates (connected over kNN
// edges no longer than kPartLinkScale × the median non-zero kNN edge) that holds at least kSecondShare of
// them, besides the largest part, and whose mean unit feature has a cosine below kSameObjectCosine
// to the largest part's. On the tuning half the parts an object's own removal splits into have
// cosines ≥ 0.966 and hold ≤ 11 % of the removed set (gen, 4 styles × 20 scenes × 3 methods); the
// second objects of synth's fgs masks hold 24–49 % at cosines ≤ 0.931.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/graph/knn.hpp"
#include "al/graph/prior.hpp"
#include "al/scene/scene.hpp"

namespace al {

inline constexpr double kPartLinkScale = 3.0;
inline constexpr double kSecondShare = 0.2;
inline constexpr double kSameObjectCosine = 0.95;

struct SecondObject {
  std::size_t rows = 0;          // removed candidates in the second part (0: none)
  std::size_t largest_rows = 0;  // ... in the largest part
  double share = 0.0;            // rows / removed candidates
  double cosine = 1.0;           // of the two parts' mean unit features
  // Scene rows of the two parts (ascending; empty when none was found): which object an addition
  // completes (al/graph/either_object.hpp).
  std::vector<std::int64_t> largest_scene_rows, second_scene_rows;
  bool Found() const { return rows > 0; }
  nlohmann::json ToJson() const;  // null when none was found
};

// knn: among the candidate nodes; median_edge: their median non-zero kNN edge length
// (MedianKnnEdgeLength, al/graph/graph.hpp; also σ_x); removed: per node (≥ 1/2 = removed);
// features: the scene's raw feature rows (uncentred); node_ids: node → scene row. Deterministic.
SecondObject FindSecondObject(const KnnResult& knn, double median_edge, const std::vector<double>& removed,
                              Eigen::Ref<const RowMatXf> features, const std::vector<std::int64_t>& node_ids);

// The removed set's feature groups, when the object group is already whole [project,
// docs/refine.md item 13]. SAGS's footprint can take a touching neighbour's near side with the
// target (gen sags-like d16 seed 33: 2,459 of a ball's 3,685 Gaussians beside a target taken
// whole). Touching, the two are one spatial part, so FindSecondObject does not see them; the
// prior's mixture does: its upper ("object") group is removed whole and a lower group that stands
// apart is removed in part. The prototype credit then completes the lower group, which is right
// when it is the object's own off-feature part (synth's thin parts; gen clip512 seed 3) and wrong
// when it is a neighbour — the mask cannot tell, so it is a bet like item 11's, bounded the same
// way (al/graph/either_object.hpp) with the two groups' removed rows as the parts.
inline constexpr double kWholeGroupRate = 0.98;    // the upper group's removal rate: "whole"
inline constexpr double kApartSeparation = 2.5;    // PriorStats::separation: the lower group stands apart
// The bound's tolerance (GraphOptions::feature_group_tolerance; 1 = never take back), item 11's;
// where it applies is GraphOptions::feature_group_bound (al/graph/continuing_body.hpp).
inline constexpr double kFeatureGroupTolerance = 0.005;

struct FeatureGroupParts {
  std::vector<std::int64_t> object_rows, other_rows;  // removed scene rows of the upper / lower group
  bool Found() const { return !object_rows.empty() && !other_rows.empty(); }
  nlohmann::json ToJson() const;  // null when not found
};

// prior: the FeaturePrior's statistics; upper: its upper-group posterior per node (empty: none);
// removed: per node, the mask before the prior (≥ 1/2 = removed). Found only when the prior gave
// kept Gaussians credit, the upper group's removal rate is ≥ kWholeGroupRate and the separation
// ≥ kApartSeparation.
FeatureGroupParts FindWholeObjectGroup(const PriorStats& prior, const std::vector<double>& upper,
                                       const std::vector<double>& removed, const std::vector<std::int64_t>& node_ids);

}  // namespace al
