// The feature prior of the unary term [project, docs/refine.md]. The removal mask is the only
// evidence of which object the user asked for, but it is noisy; the features say where it is
// probably wrong. Each candidate's observation becomes
//   y_v = (1 − w)·mask_v + w·q_v,   q_v ∈ [0, 1] = how much v's feature looks like the removed set's,
// so a Gaussian whose feature agrees with the mask keeps a firm label (y = 1 or 0), and one whose
// feature disagrees becomes neutral (y = 1/2 at w = 1/2): its neighbours decide. Features alone
// never flip a label; the graph does.
// q_v: c_v = ⟨f_v, p⟩ with p the direction that separates the removed candidates from the kept
// ones (unit(mean_R f − mean_{C∖R} f), unit features); calibrated on the removed set's own
// distribution of c, which is mostly the object: q = 1 at or above its median m, 0 at or below
// m − width·σ (σ = 1.4826·MAD, a robust standard deviation), linear between. Everything is relative
// to the scene, so neither the feature dimension nor a shared feature component matters.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/scene/scene.hpp"

namespace al {

struct PriorOptions {
  double weight = 0.5;  // w in [0, 1]; 0 = the mask alone (SPEC §4.7)
  double width = 2.0;   // robust standard deviations below the removed median where q reaches 0
  double full = 0.0;    // robust standard deviations below the removed median where q reaches 1
  bool contrast = true; // p = mean_R − mean_kept (true) or mean_R (false)
  bool mixture = false; // q = posterior of a 2-Gaussian mixture of c over the candidates
  void Check() const;   // throws al::Error (usage) outside the ranges
};

struct PriorStats {
  double weight = 0.0;
  double median_removed = 0.0, sigma_removed = 0.0;  // of c over the removed candidates
  double lo = 0.0, hi = 0.0;                         // q = 0 at lo, 1 at hi
  std::size_t removed_unlike = 0;  // removed candidates with q < 1/2 (the mask is doubted)
  std::size_t kept_like = 0;       // kept candidates with q > 1/2
  nlohmann::json ToJson() const;
};

// features: V×D unit rows (zero rows = no evidence: y = mask); mask: V in {0, 1}. Returns y (V).
// With no removed or no kept candidate the prior has nothing to learn from: y = mask.
std::vector<double> FeaturePrior(const RowMatXf& features, const std::vector<double>& mask,
                                 const PriorOptions& options, PriorStats* stats = nullptr);

}  // namespace al
