#include "al/metrics/depth_trust.hpp"

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "al/metrics/depth.hpp"

namespace al::metrics {

std::string DepthTrustOptions::Check() const {
  if (min_object_pixels < 0) return "trust: min object pixels must be >= 0";
  for (double v : {max_outside_share, min_object_peak, min_object_median})
    if (!(v >= 0 && v <= 1)) return "trust: shares and fractions must be in [0, 1]";
  return "";
}

nlohmann::json DepthTrustOptions::ToJson() const {
  return {{"min_object_pixels", min_object_pixels},
          {"max_outside_share", max_outside_share},
          {"min_object_peak", min_object_peak},
          {"min_object_median", min_object_median}};
}

bool DepthTrust::Trusted() const {
  return !small_object && !change_outside_object && !stretch_outside_object && !object_change_compressed;
}

std::vector<std::string> DepthTrust::Flags() const {
  // Names from a table of string_views: GCC 12 falsely warns (-Warray-bounds, bug 105651) on
  // push_back of string literals once inlined, as the libraries' precompiled header makes them.
  const std::pair<bool, std::string_view> named[] = {{small_object, "small_object"},
                                                     {change_outside_object, "change_outside_object"},
                                                     {stretch_outside_object, "stretch_outside_object"},
                                                     {object_change_compressed, "object_change_compressed"}};
  std::vector<std::string> f;
  for (const auto& [set, name] : named)
    if (set) f.emplace_back(name);
  return f;
}

nlohmann::json DepthTrust::ToJson() const {
  return {{"flags", Flags()},
          {"object_pixels", object_pixels},
          {"outside_share", outside_share},
          {"object_peak", object_peak},
          {"object_median", object_median}};
}

namespace {

// What the flags read, counted on the object's pixel grid (the change resized with the exact rule,
// as ScoreDepthChange does).
struct TrustCounts {
  std::int64_t object_pixels = 0, changed_inside = 0, changed_outside = 0;
  std::vector<float> object_levels;  // levels > 0 of the object's pixels
  float object_peak = 0;
};

TrustCounts CountOnObjectGrid(const Mask& object, const DepthChange& change) {
  const int cw = change.changed.width, ch = change.changed.height;
  const auto xs = NearestSourceIndex(cw, object.width, ResizeRule::kExact);
  const auto ys = NearestSourceIndex(ch, object.height, ResizeRule::kExact);
  const bool has_level = change.level.size() == change.changed.bits.size();
  TrustCounts c;
  for (int y = 0; y < object.height; ++y)
    for (int x = 0; x < object.width; ++x) {
      const std::size_t src = std::size_t(ys[y]) * std::size_t(cw) + std::size_t(xs[x]);
      const bool changed = change.changed.bits[src] != 0;
      if (!object.bits[std::size_t(y) * std::size_t(object.width) + std::size_t(x)]) {
        c.changed_outside += changed;
        continue;
      }
      ++c.object_pixels;
      c.changed_inside += changed;
      const float level = has_level ? change.level[src] : 0.0f;
      if (level > 0) c.object_levels.push_back(level), c.object_peak = std::max(c.object_peak, level);
    }
  return c;
}

}  // namespace

DepthTrust AssessDepthTrust(const Mask* object, const DepthChange& change, const DepthTrustOptions& o) {
  const Mask empty = EmptyMask(change.changed.width, change.changed.height);
  TrustCounts c = CountOnObjectGrid(object ? *object : empty, change);
  DepthTrust t;
  t.object_pixels = c.object_pixels;
  t.small_object = c.object_pixels < o.min_object_pixels;
  const std::int64_t changed = c.changed_inside + c.changed_outside;
  t.outside_share = changed == 0 ? 0.0 : double(c.changed_outside) / double(changed);
  t.change_outside_object = changed > 0 && t.outside_share > o.max_outside_share;
  const float image_peak = change.level.empty() ? 0.0f : *std::max_element(change.level.begin(), change.level.end());
  // An object whose depth did not change at all scores 0 whatever the stretch: nothing to flag.
  if (c.object_levels.empty() || !(image_peak > 0)) return t;
  auto mid = c.object_levels.begin() + std::ptrdiff_t(c.object_levels.size() / 2);
  std::nth_element(c.object_levels.begin(), mid, c.object_levels.end());
  t.object_peak = double(c.object_peak) / double(image_peak);
  t.object_median = double(*mid) / double(image_peak);
  t.stretch_outside_object = t.object_peak < o.min_object_peak;
  t.object_change_compressed = t.object_median < o.min_object_median;
  return t;
}

}  // namespace al::metrics
