// Completion that either object could pay for [project, docs/refine.md item 11]. When the removed
// set holds a second object (al/graph/removed_parts.hpp: FGS's look-alike, a neighbour GG's hull
// swallowed), the mask does not say which of the two the user meant. The cut completes both, but
// rarely evenly: on synth's look-alike scenes it completed the wrong one by hundreds of Gaussians
// (reporting half, cp: 8 of 60 scenes lowered by more than 0.01, worst −0.031). Balanced
// additions raise F1 under either reading (F1 < 1), one-sided ones are a bet. So the additions
// are read both ways — "the target is part A, the object is A plus what was added to A" and the
// same for B — and the part whose completion would cost the other reading more than `tolerance`
// in F1 loses its additions farthest from it first, just enough that neither reading does.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace al {

// 0.005: on synth's fgs masks of the tuning half (60 scenes, every one with a second object) the
// largest tolerance that keeps every scene above −0.01 with both solvers; docs/refine.md item 11.
inline constexpr double kEitherObjectTolerance = 0.005;

struct EitherObjectInputs {
  const std::vector<float>& xyz;              // 3N scene positions
  const std::vector<bool>& removed;           // N: the method's removed set
  const std::vector<std::int64_t>& part_a;    // scene rows of the removed set's largest part
  const std::vector<std::int64_t>& part_b;    // ... of the second object
  double tolerance = kEitherObjectTolerance;  // F1 either reading may lose; >= 1: never trim
};

struct EitherObjectStats {
  std::size_t parts[2] = {0, 0};    // removed rows of part A (largest) and B, fragments included
  std::size_t added[2] = {0, 0};    // additions nearest to each part
  std::size_t restored[2] = {0, 0};  // each part's rows the refinement gave back
  std::size_t trimmed = 0;           // additions taken back
  int trimmed_part = -1;             // 0 = A, 1 = B, -1 = none
  double worst_before = 0.0;         // the worse reading's ΔF1 estimate before trimming
  double worst_after = 0.0;          // ... after
  nlohmann::json ToJson() const;
};

// Additions = refined rows outside `removed`; each belongs to the part of its nearest row of
// part_a ∪ part_b (ties: the smaller row), and so does every removed row outside the two parts (a
// fragment: its restore counts against that part's reading). Rows with a non-finite position
// are left out. Returns the additions to take back (ascending rows):
// the fewest, farthest from their part first, that bring both readings' ΔF1 to ≥ −tolerance, or
// those that bring the worse reading highest when none do. Deterministic.
std::vector<std::int64_t> TrimOneSidedAdditions(const EitherObjectInputs& in, const std::vector<bool>& refined,
                                                EitherObjectStats* stats = nullptr);

}  // namespace al
