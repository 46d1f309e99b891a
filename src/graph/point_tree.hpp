// An exact 3-D kd-tree for the graph's kNN: the k smallest (squared distance, index) pairs, ties
// included, in one descent. FLANN's KDTreeSingleIndex (the reference the tests compare against)
// answers through a result set behind virtual calls and leaves equal distances at the k-th to a
// second, larger search; on the 3M room scene (685k points, k = 10) its search was 0.43 s of the
// kNN stage's 0.55 s, this one's 0.32 s (stage 0.39 s). Its leaves hold their points as three
// coordinate arrays (a leaf's distances are one vectorised loop, its entries a mask), the list
// keeps the (distance, index) order itself, so a tie needs no second search, and the far side of
// a split is searched unless its lower bound (raised along the split axis to the gap, one axis per
// level) is farther than the list's last entry. Distances are FLANN L2_3D's float sums in its
// order, so the lists and sq_dist are the same numbers as before.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace al {

struct TreeNeighbor {
  float d;  // squared distance (float, FLANN's summation order)
  std::int32_t i;
};

// The lists' order: nearer first, ties by the smaller index.
inline bool NeighborBefore(const TreeNeighbor& a, const TreeNeighbor& b) {
  return a.d < b.d || (a.d == b.d && a.i < b.i);
}

class PointTree {
 public:
  // xyz: n×3 row-major; copied (the tree does not keep the span).
  explicit PointTree(std::span<const float> xyz);

  std::size_t size() const { return ids_.size(); }
  // The point indices in the tree's leaf order: near in this list is near in space (query order).
  const std::vector<std::int32_t>& order() const { return ids_; }

  // The most points at exactly one position (equal coordinate bits) within one leaf. A pile of
  // coincident points larger than three leaves fills at least one leaf, so this finds every pile
  // that would cost a query more than a few leaves' scan at distance 0.
  std::size_t LargestPileInALeaf() const;

  // The m smallest (distance, index) pairs over the tree's points other than index `skip`
  // (-1: none), ascending, into out (fewer when the tree holds fewer).
  void Nearest(const float* q, std::size_t m, std::int32_t skip, std::vector<TreeNeighbor>& out) const;

 private:
  // A split (inner node) or a leaf. The cut values are the largest coordinate on the left and the
  // smallest on the right along the axis: the gap between them bounds the distance to the far
  // side incrementally, one axis per level (the scheme of FLANN's and nanoflann's single trees).
  struct Node {
    float cut_lo, cut_hi;
    std::uint32_t right;       // right child (the left one is the next node); 0 = leaf
    std::uint32_t begin, end;  // points [begin, end) in tree order
    std::uint32_t axis;
  };
  struct Member {
    float xyz[3];
    std::int32_t id;
  };
  struct Box {
    float lo[3], hi[3];
  };
  struct Search;  // one query's state
  static std::size_t NodeCount(std::size_t size);
  static Box Bounds(const Member* members, std::size_t begin, std::size_t end);
  Box Build(Member* members, std::size_t begin, std::size_t end, std::size_t id, Box region);
  void Descend(std::uint32_t id, double bound, double* axis_bound, Search& s) const;
  void ScanLeaf(const Node& node, Search& s) const;

  std::vector<Node> nodes_;
  Box root_box_{};
  std::vector<float> x_, y_, z_;   // coordinates in tree order
  std::vector<std::int32_t> ids_;  // point index in tree order
};

}  // namespace al
