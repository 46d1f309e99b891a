#include "al/metrics/depth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "al/core/error.hpp"

namespace al::metrics {

namespace {
double Clip(double z) { return std::max(z, 1e-30); }
}  // namespace

std::array<double, 255> GhtObjective(const Histogram256& n, const GhtOptions& o) {
  // Exact integer moments; the floating-point part keeps the reference operation order so that
  // ties (frequent with empty bins) are detected by exact equality as in the released code.
  std::int64_t t0 = 0, t1 = 0, t2 = 0;
  for (int j = 0; j < 256; ++j) t0 += n[j], t1 += n[j] * j, t2 += n[j] * std::int64_t(j) * j;
  std::array<double, 255> f{};
  std::int64_t s0 = 0, s1 = 0, s2 = 0;
  const double tau2 = o.tau * o.tau;
  for (int i = 0; i < 255; ++i) {
    s0 += n[i];
    s1 += n[i] * i;
    s2 += n[i] * std::int64_t(i) * i;
    const double w0 = Clip(double(s0)), w1 = Clip(double(t0 - s0));
    const double p0 = w0 / (w0 + w1), p1 = w1 / (w0 + w1);
    const double mu0 = double(s1) / w0, mu1 = double(t1 - s1) / w1;
    const double d0 = double(s2) - w0 * (mu0 * mu0), d1 = double(t2 - s2) - w1 * (mu1 * mu1);
    const double v0 = Clip(((p0 * o.nu) * tau2 + d0) / (p0 * o.nu + w0));
    const double v1 = Clip(((p1 * o.nu) * tau2 + d1) / (p1 * o.nu + w1));
    const double f0 = -d0 / v0 - w0 * std::log(v0) + 2 * (w0 + o.kappa * o.omega) * std::log(w0);
    const double f1 = -d1 / v1 - w1 * std::log(v1) + 2 * (w1 + o.kappa * (1 - o.omega)) * std::log(w1);
    f[i] = f0 + f1;
  }
  return f;
}

double GhtThreshold(const Histogram256& histogram, const GhtOptions& options) {
  const auto f = GhtObjective(histogram, options);
  const double best = *std::max_element(f.begin(), f.end());
  double sum = 0;
  int count = 0;
  for (int i = 0; i < 255; ++i)
    if (f[i] == best) sum += i, ++count;
  return count ? sum / count : 0.0;  // count is 0 only if every f is NaN
}

const std::array<std::uint8_t, 256>& GrayReversedLut() {
  static const std::array<std::uint8_t, 256> lut = [] {
    std::array<std::uint8_t, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = std::uint8_t(std::trunc(255.0 * (1.0 - double(i) * (1.0 / 255.0))));
    return t;
  }();
  return lut;
}

namespace {

Histogram256 HistogramOf(const std::vector<std::uint8_t>& bytes) {
  Histogram256 h{};
  for (std::uint8_t b : bytes) ++h[b];
  return h;
}

}  // namespace

const char* DepthHolesName(DepthHoles holes) { return holes == DepthHoles::kBoth ? "both" : "before"; }

std::optional<DepthHoles> DepthHolesFromName(const std::string& name) {
  if (name == "before") return DepthHoles::kBefore;
  if (name == "both") return DepthHoles::kBoth;
  return std::nullopt;
}

namespace {

// Step 1 of METRICS.md §4: |Δ| in float32, 0 where the depth before is missing (and, with kBoth,
// where the depth after is missing). Counts the holes into r.
std::vector<float> AbsDifference8Bit(const Gray8& before, const Gray8& after, DepthHoles holes, DepthChange& r) {
  std::vector<float> a(before.pixels.size(), 0.0f);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::uint8_t d1 = before.pixels[i], d2 = after.pixels[i];
    if (d1 == 0) {
      ++r.holes_before;
      continue;
    }
    if (d2 == 0) {
      ++r.holes_after;
      if (holes == DepthHoles::kBoth) continue;
    } else {
      ++r.valid_pixels;
    }
    a[i] = std::fabs(float(d2) - float(d1));
  }
  return a;
}

// Step 2: min–max stretch (kept in r.level), colormap index, inverted gray LUT into r.image.
void StretchAndInvert(const std::vector<float>& a, DepthChange& r) {
  r.level.assign(a.size(), 0.0f);
  if (a.empty()) return;
  const auto [lo_it, hi_it] = std::minmax_element(a.begin(), a.end());
  const float lo = *lo_it, hi = *hi_it;
  if (hi == lo) return;  // constant |Δ|: every byte 255
  const auto& lut = GrayReversedLut();
  const float range = hi - lo;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const float unit = (a[i] - lo) / range;
    r.level[i] = 256.0f * unit;
    r.image.pixels[i] = lut[std::min(int(std::trunc(r.level[i])), 255)];
  }
}

}  // namespace

DepthChange DepthChange8Bit(const Gray8& before, const Gray8& after, const GhtOptions& options, DepthHoles holes) {
  if (before.width != after.width || before.height != after.height)
    throw Error("depth pair size mismatch: " + std::to_string(before.width) + "x" + std::to_string(before.height) +
                " vs " + std::to_string(after.width) + "x" + std::to_string(after.height));
  const std::size_t n = before.pixels.size();
  DepthChange r;
  const std::vector<float> a = AbsDifference8Bit(before, after, holes, r);
  r.image = {before.width, before.height, std::vector<std::uint8_t>(n, 255)};
  StretchAndInvert(a, r);
  // Steps 3–5: whole-image histogram, GHT, strict `byte < t`, constant mask = no change.
  r.threshold = GhtThreshold(HistogramOf(r.image.pixels), options);
  r.changed = {before.width, before.height, std::vector<std::uint8_t>(n, 0)};
  std::size_t changed = 0;
  for (std::size_t i = 0; i < n; ++i) changed += r.changed.bits[i] = double(r.image.pixels[i]) < r.threshold;
  if (changed == 0 || changed == n) {
    r.constant = true;
    std::fill(r.changed.bits.begin(), r.changed.bits.end(), 0);
  }
  return r;
}

const char* DepthNormName(DepthNorm norm) { return norm == DepthNorm::kRange ? "range" : "maxdiff"; }

std::vector<std::uint8_t> HitMask(const DepthRender& render, float alpha_hit) {
  const std::size_t n = std::size_t(render.width) * std::size_t(render.height);
  if (render.depth.size() != n || (!render.alpha.empty() && render.alpha.size() != n))
    throw Error("depth render: buffer size does not match " + std::to_string(render.width) + "x" +
                std::to_string(render.height));
  std::vector<std::uint8_t> hit(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float z = render.depth[i];
    const bool alpha_ok = render.alpha.empty() || render.alpha[i] > alpha_hit;
    hit[i] = alpha_ok && std::isfinite(z) && z > 0.0f;
  }
  return hit;
}

namespace {

void CheckSameSize(const DepthRender& a, const DepthRender& b) {
  if (a.width != b.width || a.height != b.height) throw Error("depth render pair size mismatch");
}

}  // namespace

namespace {

// Per-pixel float change of METRICS.md §5 step 1; a hit before that is empty after is marked in
// `vanished` (it takes the top bin under DepthHoles::kBefore).
struct FloatDifference {
  std::vector<double> delta;
  std::vector<std::uint8_t> vanished;
  double max_delta = 0, zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
};

FloatDifference DifferenceFloat(const DepthRender& before, const DepthRender& after, const FloatDepthOptions& o,
                                DepthChange& r) {
  const auto h1 = HitMask(before, o.alpha_hit), h2 = HitMask(after, o.alpha_hit);
  FloatDifference d;
  d.delta.assign(h1.size(), 0.0);
  d.vanished.assign(h1.size(), 0);
  for (std::size_t i = 0; i < h1.size(); ++i) {
    if (h1[i]) d.zmin = std::min(d.zmin, double(before.depth[i])), d.zmax = std::max(d.zmax, double(before.depth[i]));
    if (h2[i]) d.zmin = std::min(d.zmin, double(after.depth[i])), d.zmax = std::max(d.zmax, double(after.depth[i]));
    if (!h1[i]) {
      ++r.holes_before;
    } else if (!h2[i]) {
      ++r.holes_after;
      d.vanished[i] = o.holes == DepthHoles::kBefore;
    } else {
      ++r.valid_pixels;
      d.delta[i] = std::fabs(double(after.depth[i]) - double(before.depth[i]));
      d.max_delta = std::max(d.max_delta, d.delta[i]);
    }
  }
  return d;
}

}  // namespace

DepthChange DepthChangeFloat(const DepthRender& before, const DepthRender& after, const FloatDepthOptions& options) {
  CheckSameSize(before, after);
  DepthChange r;
  const FloatDifference d = DifferenceFloat(before, after, options, r);
  const std::size_t n = d.delta.size();
  const double range =
      options.depth_norm == DepthNorm::kMaxDiff ? d.max_delta : (d.zmax > d.zmin ? d.zmax - d.zmin : 0.0);
  const bool any_vanished = std::find(d.vanished.begin(), d.vanished.end(), 1) != d.vanished.end();
  const bool scaled = range > 0 && std::isfinite(range);
  r.image = {before.width, before.height, std::vector<std::uint8_t>(n, 0)};
  r.changed = {before.width, before.height, std::vector<std::uint8_t>(n, 0)};
  r.level.assign(n, 0.0f);
  if (!scaled && !any_vanished) {
    r.constant = true;  // nothing valid changed: acc 0
    return r;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double level = d.vanished[i] ? 256.0 : scaled ? std::min(256.0 * d.delta[i] / range, 256.0) : 0.0;
    r.level[i] = float(level);
    r.image.pixels[i] = std::uint8_t(std::min(std::floor(level), 255.0));
  }
  r.threshold = GhtThreshold(HistogramOf(r.image.pixels), options.ght);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < n; ++i) changed += r.changed.bits[i] = double(r.image.pixels[i]) > r.threshold;
  r.constant = changed == 0 || changed == n;
  return r;
}

Depth8Pair DepthTo8Bit(const DepthRender& before, const DepthRender& after, float alpha_hit) {
  CheckSameSize(before, after);
  const auto h1 = HitMask(before, alpha_hit), h2 = HitMask(after, alpha_hit);
  Depth8Pair p;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  for (std::size_t i = 0; i < h1.size(); ++i) {
    if (h1[i]) zmin = std::min(zmin, double(before.depth[i])), zmax = std::max(zmax, double(before.depth[i]));
    if (h2[i]) zmin = std::min(zmin, double(after.depth[i])), zmax = std::max(zmax, double(after.depth[i]));
  }
  p.zmin = std::isfinite(zmin) ? zmin : 0.0;
  p.zmax = std::isfinite(zmax) ? zmax : 0.0;
  auto convert = [&](const DepthRender& r, const std::vector<std::uint8_t>& hit, std::size_t& hits) {
    Gray8 g{r.width, r.height, std::vector<std::uint8_t>(hit.size(), 0)};
    for (std::size_t i = 0; i < hit.size(); ++i) {
      if (!hit[i]) continue;
      ++hits;
      double b = 1.0;
      if (zmax > zmin) b = 1.0 + std::floor(254.0 * (double(r.depth[i]) - zmin) / (zmax - zmin) + 0.5);
      g.pixels[i] = std::uint8_t(std::clamp(b, 1.0, 255.0));
    }
    return g;
  };
  p.before = convert(before, h1, p.hits_before);
  p.after = convert(after, h2, p.hits_after);
  return p;
}

DepthScore ScoreDepthChange(const Mask* object, const Mask& changed) {
  DepthScore s;
  s.missing_object = object == nullptr;
  const Mask o = object ? *object : EmptyMask(changed.width, changed.height);
  const Mask c = Resize(changed, o.width, o.height, ResizeRule::kExact);
  const Overlap ov = CountOverlap(o, c);
  s.acc_delta_depth = ov.a == 0 ? 0.0 : double(ov.intersection) / double(ov.a);
  s.iou = ov.union_ == 0 ? 0.0 : double(ov.intersection) / double(ov.union_);
  const std::int64_t outside = std::int64_t(o.bits.size()) - ov.a;
  s.collateral_depth = outside == 0 ? 0.0 : double(ov.b - ov.intersection) / double(outside);
  return s;
}

}  // namespace al::metrics
