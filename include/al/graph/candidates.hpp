// Candidate growth (SPEC §4.2): C = R ∪ { j ∉ R : ∃ i ∈ R, ‖μ_i − μ_j‖ < r_i + r_j }, repeated
// `hops` times (each hop grows from the Gaussians the previous hop added). Exact: equal to the
// brute-force O(|R|·N) test with the predicate SpheresIntersect below. Near-linear: the growing set
// goes into a kd-tree whose nodes carry their largest radius (branch and bound on
// dist(μ_j, box) − max r); the largest spheres (more than 8× the median radius) live in small trees
// of their own, one per factor-8 range of radius, so huge Gaussians do not weaken the pruning of
// the main tree nor of each other. The trees are built in parallel tasks.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace al {

// The one intersection predicate (double precision): ‖a − b‖² < (ra + rb)².
inline bool SpheresIntersect(const float* a, double ra, const float* b, double rb) {
  const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
  const double s = ra + rb;
  return dx * dx + dy * dy + dz * dz < s * s;
}

struct CandidateStats {
  std::size_t seeds = 0;               // |R| among active Gaussians
  std::vector<std::size_t> added_per_hop;
  std::size_t huge_spheres = 0;        // growing-set spheres handled by the second tree
  double seconds = 0.0;
};

// xyz: N×3 row-major centres; radii: N; active[i] == false excludes i from everything (non-finite).
// seeds: N (the removed set). Returns in_candidates (N). Deterministic, thread-count independent.
std::vector<std::uint8_t> GrowCandidates(std::span<const float> xyz, std::span<const double> radii,
                                         std::span<const std::uint8_t> active,
                                         std::span<const std::uint8_t> seeds, int hops,
                                         CandidateStats* stats = nullptr);

}  // namespace al
