// NearestRowTree (nearest_row.hpp).
#include "src/graph/nearest_row.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "al/core/error.hpp"

namespace al {
namespace {

// Squared distance as FLANN's L2_Simple<float> computes it, so the distances (and with them the
// order of the additions taken back, farthest first) are the ones RowTree gave.
inline float SquaredDistance(const float* a, const float* b) {
  float result = 0.0f;
  for (int d = 0; d < 3; ++d) {
    const float diff = a[d] - b[d];
    result += diff * diff;
  }
  return result;
}

// A lower bound of the distance from p to any point of the box, in double.
inline double BoxSquaredDistance(const float* lo, const float* hi, const float* p) {
  double sum = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double below = double(lo[d]) - double(p[d]), above = double(p[d]) - double(hi[d]);
    const double gap = std::max({below, above, 0.0});
    sum += gap * gap;
  }
  return sum;
}

// A box can hold a nearer (or equally near) row. The margin covers float rounding of the rows'
// own distances (relative 1e-7), so pruning never drops an answer.
inline bool MayHoldBetter(double box_sq, float best_sq) {
  return !(box_sq > double(best_sq) * (1.0 + 1e-5) + 1e-30);
}

}  // namespace

NearestRowTree::NearestRowTree(const std::vector<float>& xyz, const std::vector<std::int64_t>& rows) {
  if (rows.size() > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw Error("NearestRowTree: more than 2^31 rows", ExitCode::kInternal);
  std::vector<Point> points;
  for (std::size_t t = 0; t < rows.size(); ++t) {
    const float* q = &xyz[3 * std::size_t(rows[t])];
    if (std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])) points.push_back({{q[0], q[1], q[2]}, std::int32_t(t)});
  }
  if (points.empty()) return;
  nodes_.reserve(4 * (points.size() / kLeafSize + 1));
  nodes_.resize(1);
  Build(0, points, 0, std::int32_t(points.size()));
  scratch_ = {};
  // Rows in tree order, so a leaf scans contiguous memory.
  pts_.resize(3 * points.size());
  rows_.resize(points.size());
  input_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::copy_n(points[i].x, 3, &pts_[3 * i]);
    input_[i] = points[i].input;
    rows_[i] = rows[points[i].input];
  }
}

// Moves the points of [begin, end) below `cut` on axis dim to the front; returns where the others
// start. Every point is written to both ends of a scratch range and only one cursor moves, so the
// loop has no data-dependent branch.
std::int32_t NearestRowTree::PartitionBelow(std::vector<Point>& points, std::int32_t begin, std::int32_t end, int dim,
                                            float cut) {
  scratch_.resize(points.size());
  std::int32_t below = begin, above = end - 1;
  for (std::int32_t i = begin; i < end; ++i) {
    const Point& p = points[std::size_t(i)];
    const bool is_below = p.x[dim] < cut;
    scratch_[std::size_t(below)] = p;
    scratch_[std::size_t(above)] = p;
    below += is_below;
    above -= !is_below;
  }
  std::copy(scratch_.begin() + begin, scratch_.begin() + end, points.begin() + begin);
  return below;
}

// Fills node `id` with points[begin, end) and its subtree: split the box's widest side until a leaf is small or its points coincide. The points themselves are permuted
// (not an index into them), so every pass reads memory in order. Both children are allocated
// before either is filled, so they sit side by side.
void NearestRowTree::Build(std::int32_t id, std::vector<Point>& points, std::int32_t begin, std::int32_t end) {
  Node n{};
  n.begin = begin;
  n.end = end;
  n.first_child = -1;
  for (int d = 0; d < 3; ++d) n.lo[d] = n.hi[d] = points[std::size_t(begin)].x[d];
  for (std::int32_t i = begin + 1; i < end; ++i)
    for (int d = 0; d < 3; ++d) {
      n.lo[d] = std::min(n.lo[d], points[std::size_t(i)].x[d]);
      n.hi[d] = std::max(n.hi[d], points[std::size_t(i)].x[d]);
    }
  int dim = 0;
  for (int d = 1; d < 3; ++d)
    if (n.hi[d] - n.lo[d] > n.hi[dim] - n.lo[dim]) dim = d;
  if (end - begin <= kLeafSize || !(n.hi[dim] > n.lo[dim])) {
    nodes_[std::size_t(id)] = n;
    return;
  }
  // The middle of the widest side, partitioned without branches (the side of a point is a coin
  // flip, which std::partition pays for in mispredictions); the tight boxes keep an unbalanced tree
  // cheap to search. A side left empty (a box one float wide) falls back to the median.
  const float cut = n.lo[dim] + 0.5f * (n.hi[dim] - n.lo[dim]);
  std::int32_t mid = PartitionBelow(points, begin, end, dim, cut);
  if (mid == begin || mid == end) {
    mid = begin + (end - begin) / 2;
    std::nth_element(points.begin() + begin, points.begin() + mid, points.begin() + end,
                     [dim](const Point& a, const Point& b) {
                       return a.x[dim] < b.x[dim] || (a.x[dim] == b.x[dim] && a.input < b.input);
                     });
  }
  n.first_child = std::int32_t(nodes_.size());
  nodes_[std::size_t(id)] = n;
  nodes_.resize(nodes_.size() + 2);
  Build(n.first_child, points, begin, mid);
  Build(n.first_child + 1, points, mid, end);
}

NearestRowTree::Hit NearestRowTree::Nearest(const float* p) const {
  Hit best;
  if (!nodes_.empty()) Search(0, p, best);
  return best;
}

void NearestRowTree::Search(std::int32_t id, const float* p, Hit& best) const {
  const Node& n = nodes_[std::size_t(id)];
  if (n.first_child < 0) {
    for (std::int32_t i = n.begin; i < n.end; ++i) {
      const float d = SquaredDistance(&pts_[3 * std::size_t(i)], p);
      if (d < best.sq_dist || (d == best.sq_dist && rows_[std::size_t(i)] < best.row))
        best = {rows_[std::size_t(i)], input_[std::size_t(i)], d};
    }
    return;
  }
  std::int32_t near = n.first_child, far = n.first_child + 1;
  double near_sq = BoxSquaredDistance(nodes_[std::size_t(near)].lo, nodes_[std::size_t(near)].hi, p);
  double far_sq = BoxSquaredDistance(nodes_[std::size_t(far)].lo, nodes_[std::size_t(far)].hi, p);
  if (far_sq < near_sq) std::swap(near, far), std::swap(near_sq, far_sq);
  if (MayHoldBetter(near_sq, best.sq_dist)) Search(near, p, best);
  if (MayHoldBetter(far_sq, best.sq_dist)) Search(far, p, best);
}

}  // namespace al
