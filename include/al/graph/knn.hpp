// k nearest neighbours among a point set (SPEC §4.3). Exact by default: al's 3-D kd-tree
// (src/graph/point_tree.hpp), whose lists are ordered by (float squared distance, index) in one
// descent and equal FLANN's exact KDTreeSingleIndex with the tie rule below (the tests compare
// both with brute force); checks > 0 selects FLANN's randomized kd-trees with that many leaf
// checks (approximate), where more neighbours are requested until the k-th is no longer tied with
// the last returned one. The query point is excluded by index, not by distance (duplicates are
// neighbours at distance 0); equal distances are broken by the smaller point index, so the
// answer does not depend on the tree. OpenMP over blocks of queries in a spatial order; the
// result is independent of the thread count. When a leaf of the exact tree holds more than 8
// exactly coincident points, the points are grouped first (one query per position, O(k) per
// point): the answer is the same, but a pile of 100k duplicates no longer makes every query look
// at the whole pile.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace al {

struct KnnOptions {
  int k = 10;       // neighbours per point (fewer when the set is smaller)
  int checks = 0;   // 0 = exact; > 0 = approximate (randomized kd-trees, this many checks)
  void Check() const;  // k >= 1, checks >= 0
};

struct KnnResult {
  int k = 0;                             // row stride
  std::vector<std::int32_t> neighbors;   // n*k, ascending (squared distance, index); -1 = none
  std::vector<float> sq_dist;            // n*k, float squared distances (FLANN L2_3D's sums)
  std::size_t tie_retries = 0;           // queries re-run because of a tie at the boundary (grouped
                                         // or approximate search; the exact tree needs none)
  std::size_t coincident = 0;            // points at exactly the position of an earlier point
  double seconds = 0.0;
};

// xyz: n×3 row-major.
KnnResult KnnAmongPoints(std::span<const float> xyz, const KnnOptions& options = {});

// The same lists after points were added (a later round of candidate growth): xyz holds all n
// points, before the lists of the old ones (in their own numbering), new_of_old maps an old index
// to its index in xyz (ascending: the order of the old points is kept) and added lists the new
// points' indices. Only the added points are queried; an old point's list changes only where an
// added point comes closer than its k-th neighbour (tested against the added points' kd-tree).
// Equal to KnnAmongPoints(xyz) (exact search only; approximate search, or a k that grows with n,
// falls back to it). `coincident` keeps before's count.
KnnResult KnnWithAddedPoints(std::span<const float> xyz, const KnnResult& before,
                             std::span<const std::int32_t> new_of_old, std::span<const std::int32_t> added,
                             const KnnOptions& options = {});

// 63-bit Morton code order of the points (ties by index); exposed for the benchmarks.
std::vector<std::int32_t> MortonOrder(std::span<const float> xyz);

}  // namespace al
