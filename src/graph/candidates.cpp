// Sphere-intersection candidate growth with a radius-augmented kd-tree (see candidates.hpp).
#include "al/graph/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "al/core/timer.hpp"

namespace al {
namespace {

// Implicit kd-tree over a set of spheres; each node stores its box and largest radius.
class SphereTree {
 public:
  SphereTree(std::span<const float> xyz, std::span<const double> radii, std::vector<std::int32_t> ids)
      : xyz_(xyz), radii_(radii), ids_(std::move(ids)) {
    if (!ids_.empty()) Build(0, ids_.size());
  }

  bool empty() const { return ids_.empty(); }

  // ∃ member i with SpheresIntersect(i, j)?
  bool AnyIntersects(const float* p, double r) const {
    if (ids_.empty()) return false;
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
        for (std::uint32_t k = n.begin; k < n.end; ++k) {
          const std::int32_t i = ids_[k];
          if (SpheresIntersect(&xyz_[3 * std::size_t(i)], radii_[i], p, r)) return true;
        }
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

  std::int32_t Build(std::size_t begin, std::size_t end) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    Node n;
    n.begin = static_cast<std::uint32_t>(begin);
    n.end = static_cast<std::uint32_t>(end);
    n.max_r = 0.0;
    for (int a = 0; a < 3; ++a) {
      n.lo[a] = std::numeric_limits<float>::infinity();
      n.hi[a] = -std::numeric_limits<float>::infinity();
    }
    for (std::size_t k = begin; k < end; ++k) {
      const float* q = &xyz_[3 * std::size_t(ids_[k])];
      for (int a = 0; a < 3; ++a) {
        n.lo[a] = std::min(n.lo[a], q[a]);
        n.hi[a] = std::max(n.hi[a], q[a]);
      }
      n.max_r = std::max(n.max_r, radii_[ids_[k]]);
    }
    if (end - begin > kLeaf) {
      int axis = 0;
      for (int a = 1; a < 3; ++a)
        if (n.hi[a] - n.lo[a] > n.hi[axis] - n.lo[axis]) axis = a;
      const std::size_t mid = begin + (end - begin) / 2;
      // Ties by id keep the tree (and so the traversal) a function of the set alone.
      std::nth_element(ids_.begin() + begin, ids_.begin() + mid, ids_.begin() + end,
                       [&](std::int32_t x, std::int32_t y) {
                         const float vx = xyz_[3 * std::size_t(x) + axis], vy = xyz_[3 * std::size_t(y) + axis];
                         return vx < vy || (vx == vy && x < y);
                       });
      n.left = Build(begin, mid);
      n.right = Build(mid, end);
    }
    nodes_[id] = n;
    return id;
  }

  static constexpr std::size_t kLeaf = 8;
  std::span<const float> xyz_;
  std::span<const double> radii_;
  std::vector<std::int32_t> ids_;
  std::vector<Node> nodes_;
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
    // Split the growing set: the huge spheres get their own tree.
    std::vector<double> r(frontier.size());
    for (std::size_t k = 0; k < frontier.size(); ++k) r[k] = radii[frontier[k]];
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    const double huge = 8.0 * r[r.size() / 2];
    std::vector<std::int32_t> normal_ids, huge_ids;
    for (std::int32_t i : frontier) (radii[i] > huge ? huge_ids : normal_ids).push_back(i);
    local.huge_spheres += huge_ids.size();
    const SphereTree normal(xyz, radii, std::move(normal_ids));
    const SphereTree big(xyz, radii, std::move(huge_ids));
    std::vector<std::uint8_t> hit(N, 0);
    const auto n = static_cast<std::int64_t>(N);
#pragma omp parallel for schedule(dynamic, 4096)
    for (std::int64_t j = 0; j < n; ++j) {
      if (in[j] || !active[j]) continue;
      const float* p = &xyz[3 * std::size_t(j)];
      hit[j] = normal.AnyIntersects(p, radii[j]) || big.AnyIntersects(p, radii[j]);
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
