// The exact nearest of chosen scene rows to a query point (ties: the smaller scene row), for the
// refine stages' last step that reads each addition and each removed fragment against the removed
// set's two parts (either_object.cpp).
//
// Why not RowTree (FLANN's single-index kd-tree): FLANN bounds a node by its splitting planes only,
// so a query far from every row keeps meeting nodes whose planes lie within its search radius. On
// the 3M room scene the removed set's fragments lie a median 1.2 m from the parts (kNN edges are
// ~0.8 mm): 14.8k such queries took 1.3-1.4 s, 85 us each, plus 0.25 s to build the tree over the
// 586k part rows. Here every node keeps the tight bounding box of its points, so a far query
// visits the few nodes that face it; nodes split the middle of their widest side (one branch-free
// pass per level) down to leaves of up to kLeafSize rows: 0.06 s CPU for the 586k rows.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

namespace al {

class NearestRowTree {
 public:
  static constexpr std::int32_t kLeafSize = 32;

  struct Hit {
    std::int64_t row = -1;         // scene row of the nearest, -1 when the tree is empty
    std::size_t index = 0;         // its position in the rows given to the constructor
    float sq_dist = std::numeric_limits<float>::infinity();  // squared distance, float as FLANN's L2
  };

  // xyz: 3N scene positions; rows: the scene rows to search, fewer than 2^31 (rows with a
  // non-finite position are left out: no query can be nearest to them).
  NearestRowTree(const std::vector<float>& xyz, const std::vector<std::int64_t>& rows);

  // The nearest row to p (3 floats): the smallest squared distance, computed in float as
  // ((dx² + dy²) + dz²); among equals the smallest scene row. Thread-safe (const).
  Hit Nearest(const float* p) const;

  std::size_t size() const { return rows_.size(); }

 private:
  struct Node {
    float lo[3], hi[3];          // tight bounding box of the node's points
    std::int32_t begin, end;     // its points: [begin, end) of pts_ / rows_
    std::int32_t first_child;    // children at first_child and first_child + 1; -1 for a leaf
  };

  struct Point {
    float x[3];
    std::int32_t input;  // position in the constructor's rows
  };
  std::int32_t PartitionBelow(std::vector<Point>& points, std::int32_t begin, std::int32_t end, int dim, float cut);
  void Build(std::int32_t id, std::vector<Point>& points, std::int32_t begin, std::int32_t end);
  void Search(std::int32_t node, const float* p, Hit& best) const;

  std::vector<float> pts_;          // positions in tree order, 3 per row
  std::vector<std::int64_t> rows_;  // scene rows in tree order
  std::vector<std::size_t> input_;  // positions in the constructor's rows, in tree order
  std::vector<Node> nodes_;
  std::vector<Point> scratch_;  // while building
};

}  // namespace al
