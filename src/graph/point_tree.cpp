// Exact 3-D kd-tree with (distance, index) lists (see point_tree.hpp).
#include "point_tree.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

namespace al {
namespace {

constexpr std::size_t kLeaf = 32;              // points per leaf at most
constexpr std::size_t kParallelBuild = 32768;  // smaller subtrees: built by one task

}  // namespace

// The list lives in the caller's vector, sized m up front; its length is a local count (a
// vector's end pointer would be stored and reloaded around every insertion).
struct PointTree::Search {
  const float* q;
  std::int32_t skip;
  std::size_t m;
  TreeNeighbor* list;
  std::size_t count = 0;
  double limit = std::numeric_limits<double>::infinity();  // see Reachable

  float Worst() const { return count < m ? std::numeric_limits<float>::infinity() : list[m - 1].d; }
  // Can a point at distance >= bound still enter the list? The margin covers the float rounding of
  // the bound and of the points' distances: a subtree is skipped only when all of it is farther.
  bool Reachable(double bound) const { return !(bound > limit); }
  // (d, i) into the ascending list of at most m entries: entries after its place move up one.
  void Offer(float d, std::int32_t i) {
    std::size_t t = count;
    const TreeNeighbor entry{d, i};
    if (count == m) {
      if (!NeighborBefore(entry, list[m - 1])) return;
      t = m - 1;
    } else {
      ++count;
    }
    for (; t > 0 && NeighborBefore(entry, list[t - 1]); --t) list[t] = list[t - 1];
    list[t] = entry;
    if (count == m) limit = double(list[m - 1].d) * (1.0 + 1e-5) + 1e-30;
  }
};

std::size_t PointTree::NodeCount(std::size_t size) {
  return size <= kLeaf ? 1 : 1 + NodeCount(size / 2) + NodeCount(size - size / 2);
}

PointTree::PointTree(std::span<const float> xyz) {
  const std::size_t n = xyz.size() / 3;
  if (n == 0) return;
  std::vector<Member> members(n);
  for (std::size_t i = 0; i < n; ++i) members[i] = {{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, std::int32_t(i)};
  nodes_.resize(NodeCount(n));
  // Subtrees own disjoint node and member ranges: built as parallel tasks.
#pragma omp parallel if (n > kParallelBuild)
#pragma omp single
  root_box_ = Build(members.data(), 0, n, 0, Bounds(members.data(), 0, n));
  x_.resize(n), y_.resize(n), z_.resize(n), ids_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    x_[t] = members[t].xyz[0], y_[t] = members[t].xyz[1], z_[t] = members[t].xyz[2];
    ids_[t] = members[t].id;
  }
}

PointTree::Box PointTree::Bounds(const Member* members, std::size_t begin, std::size_t end) {
  Box b;
  for (int a = 0; a < 3; ++a) b.lo[a] = std::numeric_limits<float>::infinity(), b.hi[a] = -b.lo[a];
  for (std::size_t k = begin; k < end; ++k)
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], members[k].xyz[a]);
      b.hi[a] = std::max(b.hi[a], members[k].xyz[a]);
    }
  return b;
}

// Split at the median of the longest axis of `region` (the parent's region cut at the parent's
// median: the axis without a pass over the members; ties by index, so the tree is a function of
// the set); returns the members' tight box, a leaf's from its members and a split's as its
// children's union (3M room scene, 685k points: build 0.055 -> 0.048 s). members is a pointer, not a
// reference: an OpenMP task's implicit firstprivate would copy the object a reference refers to.
PointTree::Box PointTree::Build(Member* members, std::size_t begin, std::size_t end, std::size_t id, Box region) {
  if (end - begin <= kLeaf) {
    nodes_[id] = Node{0.0f, 0.0f, 0, std::uint32_t(begin), std::uint32_t(end), 0};
    return Bounds(members, begin, end);
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (region.hi[a] - region.lo[a] > region.hi[axis] - region.lo[axis]) axis = a;
  const std::size_t mid = begin + (end - begin) / 2;
  std::nth_element(members + begin, members + mid, members + end, [axis](const Member& x, const Member& y) {
    return x.xyz[axis] < y.xyz[axis] || (x.xyz[axis] == y.xyz[axis] && x.id < y.id);
  });
  Node n{0.0f, 0.0f, std::uint32_t(id + 1 + NodeCount(mid - begin)), std::uint32_t(begin), std::uint32_t(end),
         std::uint32_t(axis)};
  Box left_region = region, right_region = region, left;
  left_region.hi[axis] = right_region.lo[axis] = members[mid].xyz[axis];
#pragma omp task shared(left) if (end - begin > kParallelBuild)
  left = Build(members, begin, mid, id + 1, left_region);
  const Box right = Build(members, mid, end, n.right, right_region);
#pragma omp taskwait
  n.cut_lo = left.hi[axis], n.cut_hi = right.lo[axis];
  nodes_[id] = n;
  Box box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::min(left.lo[a], right.lo[a]);
    box.hi[a] = std::max(left.hi[a], right.hi[a]);
  }
  return box;
}

std::size_t PointTree::LargestPileInALeaf() const {
  std::size_t largest = 0;
  const auto count = static_cast<std::int64_t>(nodes_.size());
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : largest)
  for (std::int64_t id = 0; id < count; ++id) {
    const Node& node = nodes_[std::size_t(id)];
    if (node.right != 0) continue;
    std::array<std::array<std::uint32_t, 3>, kLeaf> keys;
    const std::size_t size = node.end - node.begin;
    for (std::size_t t = 0; t < size; ++t) {
      const float p[3] = {x_[node.begin + t], y_[node.begin + t], z_[node.begin + t]};
      std::memcpy(keys[t].data(), p, sizeof p);
    }
    std::sort(keys.begin(), keys.begin() + std::ptrdiff_t(size));
    for (std::size_t t = 0, run = 1; t < size; ++t, ++run) {
      if (t > 0 && keys[t] != keys[t - 1]) run = 1;
      largest = std::max(largest, run);
    }
  }
  return largest;
}

void PointTree::ScanLeaf(const Node& node, Search& s) const {
  float d[kLeaf];
  const float* q = s.q;
  const std::size_t b = node.begin, size = node.end - node.begin;
  for (std::size_t t = 0; t < size; ++t) {  // FLANN L2_3D: ((0 + dx²) + dy²) + dz² in float
    const float dx = q[0] - x_[b + t], dy = q[1] - y_[b + t], dz = q[2] - z_[b + t];
    float sum = dx * dx;
    sum += dy * dy;
    sum += dz * dz;
    d[t] = sum;
  }
  // Which points can enter (at most the list's last distance; ties by index are Offer's): a mask
  // from one vectorised compare, so the usual "farther" costs no branch per point.
  const float worst = s.Worst();
  std::uint32_t enter = 0;
  for (std::size_t t = 0; t < size; ++t) enter |= std::uint32_t(d[t] <= worst) << t;
  for (; enter != 0; enter &= enter - 1) {
    const int t = __builtin_ctz(enter);
    if (ids_[b + t] != s.skip) s.Offer(d[t], ids_[b + t]);
  }
}

// The nearer side first; the far side when the bound, raised along the split axis to the gap, can
// still reach the list. axis_bound holds the bound's per-axis terms.
void PointTree::Descend(std::uint32_t id, double bound, double* axis_bound, Search& s) const {
  const Node& node = nodes_[id];
  if (node.right == 0) {
    ScanLeaf(node, s);
    return;
  }
  const std::uint32_t a = node.axis;
  const double to_lo = double(s.q[a]) - node.cut_lo, to_hi = double(s.q[a]) - node.cut_hi;
  const bool left_first = to_lo + to_hi < 0;
  const double gap = left_first ? to_hi * to_hi : to_lo * to_lo;
  Descend(left_first ? id + 1 : node.right, bound, axis_bound, s);
  const double saved = axis_bound[a];
  const double far_bound = bound + gap - saved;
  if (!s.Reachable(far_bound)) return;
  axis_bound[a] = gap;
  Descend(left_first ? node.right : id + 1, far_bound, axis_bound, s);
  axis_bound[a] = saved;
}

void PointTree::Nearest(const float* q, std::size_t m, std::int32_t skip, std::vector<TreeNeighbor>& out) const {
  out.clear();
  if (nodes_.empty() || m == 0) return;
  out.resize(m);
  Search s{q, skip, m, out.data()};
  double axis_bound[3], bound = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double below = double(root_box_.lo[a]) - q[a], above = double(q[a]) - root_box_.hi[a];
    const double g = std::max({below, above, 0.0});
    axis_bound[a] = g * g;
    bound += axis_bound[a];
  }
  Descend(0, bound, axis_bound, s);
  out.resize(s.count);
}

}  // namespace al
