// Sphere-intersection candidate growth with a radius-augmented kd-tree (see candidates.hpp).
#include "al/graph/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "al/core/timer.hpp"

namespace al {
namespace {

// Implicit kd-tree over a set of spheres; each node stores its box and largest radius.
class SphereTree {
 public:
  SphereTree(std::span<const float> xyz, std::span<const double> radii, const std::vector<std::int32_t>& ids) {
    if (ids.empty()) return;
    // The members' centres and radii copied once: the build partitions them in place, so a
    // comparison reads its coordinate beside the member instead of at a random scene index, and a
    // leaf's tests read one contiguous block.
    members_.resize(ids.size());
    const auto m = static_cast<std::int64_t>(ids.size());
#pragma omp parallel for schedule(static) if (m > std::int64_t(kParallelBuild))
    for (std::int64_t k = 0; k < m; ++k) {
      const std::size_t i = std::size_t(ids[std::size_t(k)]);
      members_[std::size_t(k)] = {{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, ids[std::size_t(k)], radii[i]};
    }
    nodes_.resize(NodeCount(members_.size()));
    // The subtrees of a node own disjoint node and member ranges, so they are built as parallel tasks.
#pragma omp parallel if (members_.size() > kParallelBuild)
#pragma omp single
    Build(0, members_.size(), 0, Bounds(0, members_.size()));
  }

  bool empty() const { return members_.empty(); }

  // ∃ member i with SpheresIntersect(i, j)?
  bool AnyIntersects(const float* p, double r) const {
    if (members_.empty()) return false;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      // Conservative prune: every member is at least box-distance away.
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double v = p[a];
        const double lo = n.lo[a], hi = n.hi[a];
        const double g = v < lo ? lo - v : (v > hi ? v - hi : 0.0);
        d2 += g * g;
      }
      const double reach = r + n.max_r;
      if (d2 > reach * reach * (1.0 + 1e-9)) continue;
      if (n.left < 0) {
        for (std::uint32_t k = n.begin; k < n.end; ++k)
          if (SpheresIntersect(members_[k].xyz, members_[k].r, p, r)) return true;
        continue;
      }
      stack[top++] = n.right;
      stack[top++] = n.left;
    }
    return false;
  }

 private:
  struct Node {
    float lo[3], hi[3];
    double max_r;
    std::uint32_t begin, end;
    std::int32_t left = -1, right = -1;  // children (leaf: -1)
  };

  // Nodes of the subtree over `size` members: the node ids of a subtree are preassigned (its left
  // child right after it, then the left subtree, then the right one).
  static std::size_t NodeCount(std::size_t size) {
    return size <= kLeaf ? 1 : 1 + NodeCount(size / 2) + NodeCount(size - size / 2);
  }

  // The box and largest radius of members [begin, end).
  Node Bounds(std::size_t begin, std::size_t end) const {
    Node n;
    n.begin = static_cast<std::uint32_t>(begin);
    n.end = static_cast<std::uint32_t>(end);
    n.max_r = 0.0;
    for (int a = 0; a < 3; ++a) {
      n.lo[a] = std::numeric_limits<float>::infinity();
      n.hi[a] = -std::numeric_limits<float>::infinity();
    }
    for (std::size_t k = begin; k < end; ++k) {
      const Member& q = members_[k];
      for (int a = 0; a < 3; ++a) {
        n.lo[a] = std::min(n.lo[a], q.xyz[a]);
        n.hi[a] = std::max(n.hi[a], q.xyz[a]);
      }
      n.max_r = std::max(n.max_r, q.r);
    }
    return n;
  }

  // Split at the median of the longest axis of `region`: the parent's region cut at the parent's
  // median, which picks the axis without a pass over the members. The node's tight box and largest
  // radius are its children's, joined once they are built (3M room scene, 601k seeds: build
  // 0.085 -> 0.068 s, where every level took a bounds pass before its split).
  void Build(std::size_t begin, std::size_t end, std::size_t id, Node region) {
    if (end - begin <= kLeaf) {
      nodes_[id] = Bounds(begin, end);
      return;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (region.hi[a] - region.lo[a] > region.hi[axis] - region.lo[axis]) axis = a;
    const std::size_t mid = begin + (end - begin) / 2;
    // Ties by id keep the tree (and so the traversal) a function of the set alone.
    std::nth_element(members_.begin() + std::ptrdiff_t(begin), members_.begin() + std::ptrdiff_t(mid),
                     members_.begin() + std::ptrdiff_t(end), [axis](const Member& x, const Member& y) {
                       return x.xyz[axis] < y.xyz[axis] || (x.xyz[axis] == y.xyz[axis] && x.id < y.id);
                     });
    const std::size_t left = id + 1, right = id + 1 + NodeCount(mid - begin);
    Node left_region = region, right_region = region;
    left_region.hi[axis] = right_region.lo[axis] = members_[mid].xyz[axis];
#pragma omp task if (end - begin > kParallelBuild)
    Build(begin, mid, left, left_region);
    Build(mid, end, right, right_region);
#pragma omp taskwait
    Node n = nodes_[left];
    const Node& r = nodes_[right];
    for (int a = 0; a < 3; ++a) n.lo[a] = std::min(n.lo[a], r.lo[a]), n.hi[a] = std::max(n.hi[a], r.hi[a]);
    n.max_r = std::max(n.max_r, r.max_r);
    n.begin = std::uint32_t(begin), n.end = std::uint32_t(end);
    n.left = std::int32_t(left), n.right = std::int32_t(right);
    nodes_[id] = n;
  }

  static constexpr std::size_t kLeaf = 8;
  static constexpr std::size_t kParallelBuild = 32768;  // smaller subtrees: one task
  std::vector<Node> nodes_;
  struct Member {
    float xyz[3];
    std::int32_t id;  // scene index: ties in a split are broken by it
    double r;
  };
  std::vector<Member> members_;
};

// The growing set as trees by radius: the spheres up to 8x the median radius in one, the larger
// ("huge") ones in one tree per factor-8 range of radius. A node prunes with its largest radius,
// so a tree mixing radii a hundred times apart visits most of itself for every query, while every
// tree costs each query a descent: on the 3M room scene (32k huge spheres scattered over the room)
// factor-2 ranges made 5 trees and 122M node visits, factor 8 makes 3 and 77M (candidate growth
// 0.38 -> 0.30 s; factor 4 0.31 s, one tree for all 0.56 s). The answer does not depend on the
// split (an exact test).
class GrowingSet {
 public:
  GrowingSet(std::span<const float> xyz, std::span<const double> radii, const std::vector<std::int32_t>& members) {
    std::vector<double> r(members.size());
    for (std::size_t k = 0; k < members.size(); ++k) r[k] = radii[std::size_t(members[k])];
    std::nth_element(r.begin(), r.begin() + std::ptrdiff_t(r.size() / 2), r.end());
    const double huge = 8.0 * r[r.size() / 2];
    std::vector<std::vector<std::int32_t>> ids(1 + kHugeClasses);
    for (std::int32_t i : members) ids[ClassOf(radii[std::size_t(i)], huge)].push_back(i);
    huge_ = members.size() - ids[0].size();
    for (auto& c : ids)
      if (!c.empty()) trees_.push_back(std::make_unique<SphereTree>(xyz, radii, std::move(c)));
  }
  std::size_t huge() const { return huge_; }
  bool AnyIntersects(const float* p, double r) const {
    for (const auto& t : trees_)
      if (t->AnyIntersects(p, r)) return true;
    return false;
  }

 private:
  static constexpr std::size_t kHugeClasses = 14;  // 8x .. 8^14 x 8x the median; larger ones share the last
  static std::size_t ClassOf(double r, double huge) {
    if (!(r > huge)) return 0;
    const double factors_of_8 = std::floor(std::log2(r / huge) / 3.0);
    return 1 + std::size_t(std::clamp(factors_of_8, 0.0, double(kHugeClasses - 1)));
  }
  std::vector<std::unique_ptr<SphereTree>> trees_;
  std::size_t huge_ = 0;
};

}  // namespace

std::vector<std::uint8_t> GrowCandidates(std::span<const float> xyz, std::span<const double> radii,
                                         std::span<const std::uint8_t> active,
                                         std::span<const std::uint8_t> seeds, int hops,
                                         CandidateStats* stats) {
  Timer timer;
  const std::size_t N = radii.size();
  std::vector<std::uint8_t> in(N, 0);
  std::vector<std::int32_t> frontier;
  for (std::size_t i = 0; i < N; ++i)
    if (seeds[i] && active[i]) {
      in[i] = 1;
      frontier.push_back(static_cast<std::int32_t>(i));
    }
  CandidateStats local;
  local.seeds = frontier.size();
  for (int hop = 0; hop < hops && !frontier.empty(); ++hop) {
    const GrowingSet growing(xyz, radii, frontier);
    local.huge_spheres += growing.huge();
    std::vector<std::uint8_t> hit(N, 0);
    const auto n = static_cast<std::int64_t>(N);
#pragma omp parallel for schedule(dynamic, 4096)
    for (std::int64_t j = 0; j < n; ++j) {
      if (in[j] || !active[j]) continue;
      hit[j] = growing.AnyIntersects(&xyz[3 * std::size_t(j)], radii[j]);
    }
    frontier.clear();
    for (std::size_t j = 0; j < N; ++j)
      if (hit[j]) {
        in[j] = 1;
        frontier.push_back(static_cast<std::int32_t>(j));
      }
    local.added_per_hop.push_back(frontier.size());
  }
  local.seconds = timer.Seconds();
  if (stats) *stats = local;
  return in;
}

}  // namespace al
