// When acc_Δdepth of one view says little about the removal (docs/metrics.md, "Trust flags").
// acc_Δdepth stretches |Δdepth| between its minimum and maximum over the whole image and lets GHT
// split the result, so the same removal can score 0.02 or 0.91 depending on what else changed and
// on how the object's change compares with the largest change in view. The flags name the cases
// measured to go wrong; they never change the metric itself (the published numbers stay
// comparable), they say which views to read with care and which `refine --auto` must not optimise.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace al::metrics {

struct DepthTrustOptions {
  // small_object: fewer object pixels than this. Below 256 px the same view rendered at lower
  // resolution moved acc by 0.42-0.50 on average (docs/metrics.md).
  std::int64_t min_object_pixels = 256;
  // change_outside_object: more than this share of the changed pixels lie outside the object.
  double max_outside_share = 0.5;
  // stretch_outside_object: the object's largest change is below this fraction of the image's
  // largest change (the min-max stretch is set elsewhere).
  double min_object_peak = 0.75;
  // object_change_compressed: the median change of the object's changed pixels is below this
  // fraction of the largest change (GHT does not separate changes that low from "unchanged").
  double min_object_median = 0.25;
  std::string Check() const;  // empty when valid
  nlohmann::json ToJson() const;
};

struct DepthTrust {
  std::int64_t object_pixels = 0;
  double outside_share = 0;  // |changed ∩ Ō| / |changed|, 0 when nothing changed
  double object_peak = 0;    // largest change on the object / largest change in the image, in [0, 1]
  double object_median = 0;  // median change of the object's changed pixels / largest change, in [0, 1]
  bool small_object = false, change_outside_object = false, stretch_outside_object = false,
       object_change_compressed = false;
  bool Trusted() const;
  std::vector<std::string> Flags() const;  // names of the raised flags, in the order above
  nlohmann::json ToJson() const;
};

}  // namespace al::metrics
