// What a --method preset sets (SPEC §3 table): the feature source, how a subset PLY is read, and
// the value each `auto` graph/decision option takes for that method. Reported under params.preset.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "al/graph/graph.hpp"
#include "al/io/masks.hpp"

namespace al {

struct MethodPreset {
  // A prefix, a preference list ("obj_dc_,auto": the first present; auto = the standard
  // prefixes; none present: the colour fallback, with a warning) or "colour".
  std::string features = "auto";
  // For a subset PLY only: a mask or index list is always the removed set unless --removed-is
  // says otherwise (GG writes its remaining scene as a PLY, never as a mask).
  RemovedIs subset_ply_is = RemovedIs::kRemoved;
  bool gc_polarity = false;
  // The prior's prototype credit under --prototype-credit auto (al/graph/prior.hpp): only SAGS's
  // misses are thin parts of the object alone; GG's and FGS's removed sets can hold a second
  // object whose kept part it would credit (docs/accuracy.md).
  bool prototype_credit = false;
  // ... and its wide credit window: FGS misses sit just below a tight object; GG's hull puts table
  // top in the object group, whose kept part the wide window would credit.
  bool wide_credit = false;
  // --centre auto: FGS-like refinement loses by centring a field without a shared component
  // (docs/refine.md: tuning half, gen D = 16/32 and synth); the other methods gain or break even.
  Centring centre = Centring::kOn;
  // --restore auto: GaussianCut's masks are precise; on synth's gc masks (tuning and reporting
  // halves) every Gaussian the cut restored was the object (docs/accuracy.md).
  bool restore = true;
  // --prior-weight auto: over-removing GG and SAGS's thin misses gain when a doubted label leans
  // to the features' side (0.55; tuning half: gen gg-like +0.065 → +0.075, sags-like +0.016 →
  // +0.026); for FGS it let synth's grabbed look-alike in (docs/refine.md).
  double prior_weight = 0.5;
  // --lambda auto with solver bk: GG's over-removal comes back in larger pieces when the edges
  // weigh more (tuning half, bk: gen gg-like +0.0749 → +0.0759, synth gg +0.0093 → +0.0107).
  // The cut-pursuit solvers keep 1: their KL data term balances the edges on another scale, and
  // at 1.5 cp gained nothing and lowered two more tuning scenes (docs/refine.md).
  double bk_lambda = 1.0;
  // --feature-width auto: SAGS misses thin parts whose features are off (synth: centred cosine
  // about 0.7 to their neighbours, 0.88 inside the object); a kernel twice as wide lets the edges
  // that pass the gate there weigh more (tuning half: synth sags +0.0020 → +0.0026 bk, +0.0026 →
  // +0.0033 cp; docs/refine.md item 12). Within an object's own features the weights stay near 1.
  double feature_width = 1.0;

  // The λ of --lambda auto for a solver (al/solver.hpp names): bk_lambda for bk, else 1.
  double LambdaFor(const std::string& solver) const;
  nlohmann::json ToJson() const;
};

// The preset of fgs, gg, sags, gc or generic (= a default MethodPreset: the generic model).
// Throws al::Error (usage) for any other name.
MethodPreset MethodPresetFor(const std::string& method);

}  // namespace al
