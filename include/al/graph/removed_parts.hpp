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

}  // namespace al
