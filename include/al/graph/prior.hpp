// The feature prior of the unary term [project, docs/refine.md]. The removal mask is the only
// evidence of which object the user asked for, but it is noisy; the features say where it is
// probably wrong. Each candidate's observation becomes
//   y_v = (1 − w)·mask_v + w·q_v,   q_v ∈ [0, 1]: does v's feature group say "removed"?
// so at w = 1/2 a Gaussian whose feature agrees with the mask keeps a firm label (y = 1 or 0) and
// one whose feature disagrees becomes neutral (y = 1/2): its neighbours in the graph decide.
// Features alone never flip a label.
//
// q_v: the candidates' unit features are projected on the direction that separates the removed
// candidates from the kept ones (mean_R − mean_kept); a two-Gaussian mixture is fitted to that
// projection by EM (started from the mask), giving each candidate's probability of belonging to
// the upper ("object") group. Each group's removal rate (its share of removed candidates) is the
// mask's verdict on it, and a label is doubted only where the group's majority disagrees (the
// doubt fades in over a short range of removal rates, never a step: prior.cpp):
//  - a removed Gaussian only if its group is the lower one, the method kept at least two thirds
//    of that group (GG's hull takes part of the table top: restore it) and its projection lies
//    below the removed set's own spread, and the lower group stands apart from the removed set
//    (separation ≥ 1.5 of its standard deviations; else it is the object's own tail); a group
//    the method took whole (a look-alike it grabbed, an object part whose features are off) is
//    not second-guessed;
//  - a kept Gaussian only if the method mostly removed the upper group and either it belongs to
//    that group with its projection within the removed set's own spread, or its cosine to the
//    prototype (the mean of the trusted removed rows) is within the trusted rows' own spread.
// "Within the spread": a ramp from 0 at median − 2σ to 1 at the median of the removed
// candidates' projections (σ = 1.4826·MAD, a robust standard deviation); for kept Gaussians it
// reaches half-way to the kept candidates' median when that is further (a tight object).
// Everything is relative to the scene, so neither the feature dimension nor a component all
// features share changes the prior.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "al/scene/scene.hpp"

namespace al {

// Two ways a kept Gaussian can get more credit; each finds misses of one kind of method, and each
// credits the kept part of a second object when the removed set holds one (a table top in GG's
// hull, a look-alike FGS grabbed; docs/refine.md). auto = per --method preset (resolved by
// al::RunRefine's stages); a caller of FeaturePrior or BuildRefineGraph itself gets auto = off.
//  - prototype_credit: credit from the cosine to the removed set's prototype (thin parts SAGS
//    misses); auto = on for sags only;
//  - wide_credit: the kept side's "within the spread" window reaches half-way to the kept median
//    (FGS's misses just below a tight object); auto = on for fgs only.
enum class PriorSwitch { kAuto, kOn, kOff };

struct PriorOptions {
  // w in [0, 1]; 0 = the mask alone (SPEC §4.7). Unset = auto: the --method preset's (0.55 for gg
  // and sags: a doubted label leans to the features' side; docs/refine.md), 0.5 otherwise and for
  // a direct caller of FeaturePrior or BuildRefineGraph.
  std::optional<double> weight;
  double Weight() const { return weight.value_or(0.5); }
  PriorSwitch prototype_credit = PriorSwitch::kAuto;
  PriorSwitch wide_credit = PriorSwitch::kAuto;
  // No credit for kept Gaussians when the removed set holds a second object
  // (al/graph/removed_parts.hpp); auto = on (every preset).
  PriorSwitch second_object_guard = PriorSwitch::kAuto;
  void Check() const;   // throws al::Error (usage) outside [0, 1]
};

struct PriorStats {
  double weight = 0.0;
  double mean_lower = 0.0, mean_upper = 0.0;  // the mixture's groups (projections)
  double sd_lower = 0.0, sd_upper = 0.0;
  double removal_rate_lower = 0.0, removal_rate_upper = 0.0;  // share of each group in R
  double median_removed = 0.0, sigma_removed = 0.0;           // of the removed candidates
  double gap = 0.0;         // median_removed − the kept candidates' median (≥ 0)
  double separation = 0.0;  // (median_removed − mean_lower) / sd_lower
  std::size_t prototype_rows = 0;  // trusted removed rows that make the prototype
  double prototype_cos_median = 0.0, prototype_cos_sigma = 0.0;  // their cosines to it
  std::size_t removed_doubted = 0;  // removed candidates with q < 1/2
  std::size_t kept_doubted = 0;     // kept candidates with q > 1/2
  bool kept_credit = true;          // false: a second object in the removed set (no kept credit)
  nlohmann::json ToJson() const;
};

// features: V×D unit rows (zero rows = no evidence: y = mask); mask: V in {0, 1}. Returns y (V).
// With no removed or no kept candidate the prior has nothing to learn from: y = mask.
// kWithheld: no kept Gaussian gets credit (a second object in the removed set; the graph decides).
// upper_group (optional): per row, the mixture's posterior of the upper ("object") group (rows
// without a feature keep their mask value; empty when the prior had nothing to learn from).
enum class KeptCredit { kAllowed, kWithheld };
std::vector<double> FeaturePrior(const RowMatXf& features, const std::vector<double>& mask,
                                 const PriorOptions& options, PriorStats* stats = nullptr,
                                 KeptCredit kept_credit = KeptCredit::kAllowed,
                                 std::vector<double>* upper_group = nullptr);

}  // namespace al
