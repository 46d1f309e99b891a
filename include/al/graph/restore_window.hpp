// Restores that look like the removed set stay removed [project, docs/refine.md item 15; opt-in]. The cut
// gives back a removed Gaussian when its graph neighbourhood is mostly kept; on FGS-like masks it
// also gives back the object's own rows that way (gen fgs-like clip512 seed 42 with cp, held-out
// seeds 41-80: 328 restored, none of them background, ΔF1 −0.031; six such scenes of 160, every
// one the cut's own restores). The object rows it restores lie in the upper part of the removed
// set's cosines to its own prototype (the mean centred feature of the removed rows; median z of
// −1 to −3.4 robust standard deviations), the background it rightly restores lower (−2 to −12).
// So a restored Gaussian whose cosine lies within kRestoreWindowMads robust standard deviations
// (1.4826 · MAD) below the removed set's median cosine stays removed.
//
// Only where the removed set holds one object: with a second one (FGS's look-alike on synth) the
// object-like restores are that look-alike, and giving it back is right. Opt-in (--restore-window
// on): on held-out seeds it lifted gen fgs-like means and its worst scenes (−0.10 → +0.004) but
// lowered 15 of 560 runs by more than 0.005, against an acceptance written beforehand; on GG's
// over-removal the table slab its hull swallowed sits inside the window (tuning half: gen gg-like
// +0.0759 → +0.0624 at 1.5).
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/graph/taken_whole.hpp"

namespace al {

inline constexpr double kRestoreWindowMads = 2.0;

struct RestoreWindowStats {
  std::size_t prototype_rows = 0;  // removed rows with a usable feature
  double median = 0.0;             // their cosines to the prototype: median
  double sigma = 0.0;              // ... and robust σ (1.4826 · MAD)
  double floor = 0.0;              // median − mads · σ
  std::size_t kept = 0;            // queried rows at or above the floor (they stay removed)
  nlohmann::json ToJson() const;
};

// features: the scene's features centred on its mean (SceneFeatureMap with centre on); removed:
// N; active: N (inactive rows do not shape the prototype); rows: the removed rows the cut would
// restore. Returns per queried row 1 = inside the window. No usable prototype: all 0.
std::vector<std::uint8_t> InRestoreWindow(const SceneFeatureMap& features, const std::vector<bool>& removed,
                                          const std::vector<std::uint8_t>& active,
                                          const std::vector<std::int64_t>& rows, double mads,
                                          RestoreWindowStats* stats = nullptr);

}  // namespace al
