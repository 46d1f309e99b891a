// Scattering entries from sources to targets on several threads, in the order of one sequential
// pass over the sources. The sources [0, n) are split into ranges, one per part. A first pass counts
// what each range sends to each target (Count). The counts then become offsets, so that range t's
// entries into target w follow those of the ranges below t (Total, called for every target in
// order). A second pass places each entry at its target's start + Next(t, w). Used for reverse
// adjacency lists: the symmetric adjacency, the max-flow network's arcs, the kNN pairs at their
// smaller end. The parts are loop iterations, not thread ids, so every range is done even with
// fewer threads.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <omp.h>

namespace al {

class RangeScatter {
 public:
  // Parts for the machine: the OpenMP threads, at most 8 (each part keeps a count per target).
  static int DefaultParts() { return std::clamp(omp_get_max_threads(), 1, 8); }

  RangeScatter(std::int64_t sources, std::size_t targets, int parts)
      : sources_(sources), at_(static_cast<std::size_t>(parts), std::vector<std::int32_t>(targets, 0)) {}

  int parts() const { return static_cast<int>(at_.size()); }
  // Sources [first, second) of part t.
  std::pair<std::int64_t, std::int64_t> Range(int t) const {
    return {sources_ * t / parts(), sources_ * (t + 1) / parts()};
  }
  // First pass, from part t's loop: one more entry from range t into target w.
  void Count(int t, std::size_t w) { ++at_[static_cast<std::size_t>(t)][w]; }
  // Between the passes, for every target in order: w's entries from all ranges; range t's counts
  // become its offsets among them.
  std::int64_t Total(std::size_t w) {
    std::int32_t total = 0;
    for (auto& counts : at_) total += std::exchange(counts[w], total);
    return total;
  }
  // Second pass, from part t's loop: the position of range t's next entry into w, from w's start.
  std::int32_t Next(int t, std::size_t w) { return at_[static_cast<std::size_t>(t)][w]++; }

 private:
  std::int64_t sources_;
  std::vector<std::vector<std::int32_t>> at_;
};

// Whether every edge of a forward-star graph is stored at its smaller end (adj[e] > u). Then node
// w's reverse entries all come from sources below w, so they precede w's own edges in a sequential
// fill, and a RangeScatter reproduces that fill.
inline bool StoredAtSmallerEnd(std::span<const std::int64_t> first_edge, std::span<const std::int32_t> adj) {
  const std::int64_t n = static_cast<std::int64_t>(first_edge.size()) - 1;
  bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
  for (std::int64_t u = 0; u < n; ++u)
    for (std::int64_t e = first_edge[u]; e < first_edge[u + 1]; ++e) ok = ok && adj[e] > u;
  return ok;
}

}  // namespace al
