// Residuals of an object on renders (al/metrics/residual.hpp).
#include "al/metrics/residual.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "al/core/error.hpp"

namespace al::metrics {
namespace {

// A render's colour as a PNG would hold it: clamped to [0, 1], non-finite read as 0.
double Channel(float v) { return std::isfinite(v) ? std::clamp(double(v), 0.0, 1.0) : 0.0; }

double ColourDistance(std::span<const float> a, std::span<const float> b, std::size_t p) {
  double d2 = 0;
  for (std::size_t c = 0; c < 3; ++c) {
    const double d = Channel(a[3 * p + c]) - Channel(b[3 * p + c]);
    d2 += d * d;
  }
  return std::sqrt(d2);
}

void CheckSize(std::size_t got, std::size_t want, const char* what) {
  if (got != want)
    throw Error(std::string("residual: ") + what + " has " + std::to_string(got) + " values, expected " +
                    std::to_string(want),
                ExitCode::kInternal);
}

ViewResidual Finish(double sum, std::size_t pixels, const ResidualOptions& o) {
  ViewResidual r;
  r.pixels = pixels;
  if (pixels > 0 && pixels >= std::size_t(o.min_pixels)) r.value = sum / double(pixels);
  return r;
}

// A pixel "has depth" as in METRICS.md §6: alpha above alpha_hit and a finite depth > 0.
bool Hit(const PixelRender& r, std::size_t p, float alpha_hit) {
  return r.alpha[p] > alpha_hit && std::isfinite(r.depth[p]) && r.depth[p] > 0;
}

bool DepthStill(const PixelRender& before, const PixelRender& after, std::size_t p, const ResidualOptions& o) {
  const bool hb = Hit(before, p, o.alpha_hit), ha = Hit(after, p, o.alpha_hit);
  if (hb != ha) return false;
  if (!hb) return true;
  return std::fabs(double(after.depth[p]) - double(before.depth[p])) <= o.depth_tol * double(before.depth[p]);
}

}  // namespace

const OptionTable<ResidualOptions>& ResidualOptions::Table() {
  using O = ResidualOptions;
  using R = NumericRange;
  static const auto table =
      OptionTable<O>("residual")
          .Real("residual_footprint", &O::footprint, R::Open(0, 2),
                "the object's footprint: pixels whose RGB distance before vs ideal exceeds this (RGB in [0, 1])")
          .Int("residual_min_pixels", &O::min_pixels, R::Closed(1, 1e9),
               "views whose footprint (residual_px: object mask) has fewer pixels are not scored")
          .Real("px_colour_tol", &O::colour_tol, R::Closed(0, 2),
                "residual_px: a mask pixel still matches when its RGB moved by at most this")
          .Real("px_depth_tol", &O::depth_tol, R::Closed(0, 10),
                "residual_px: ... and its depth by at most this share of the depth before");
  return table;
}

void ResidualOptions::Check() const {
  Table().Check(*this);
  CheckOptionRange("residual", "alpha_hit", alpha_hit, NumericRange::Closed(0, 1), "a pixel has depth iff alpha > this");
}

ViewResidual ComputeResidual(const ResidualRenders& r, const ResidualOptions& o, std::vector<float>* share) {
  const std::size_t n = std::size_t(std::max(r.width, 0)) * std::size_t(std::max(r.height, 0));
  CheckSize(r.before.size(), 3 * n, "the before render");
  CheckSize(r.after.size(), 3 * n, "the after render");
  CheckSize(r.ideal.size(), 3 * n, "the ideal render");
  if (share) share->assign(n, -1.0f);
  double sum = 0;
  std::size_t pixels = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const double signal = ColourDistance(r.before, r.ideal, p);
    if (!(signal > o.footprint)) continue;
    const double left = std::min(1.0, ColourDistance(r.after, r.ideal, p) / signal);
    sum += left;
    ++pixels;
    if (share) (*share)[p] = float(left);
  }
  return Finish(sum, pixels, o);
}

ViewResidual ComputePixelResidual(const PixelRender& before, const PixelRender& after, const Mask& object,
                                  const ResidualOptions& o, Mask* still) {
  const std::size_t n = std::size_t(std::max(object.width, 0)) * std::size_t(std::max(object.height, 0));
  CheckSize(object.bits.size(), n, "the object mask");
  for (const PixelRender* r : {&before, &after}) {
    CheckSize(r->rgb.size(), 3 * n, "a render's colour");
    CheckSize(r->depth.size(), n, "a render's depth");
    CheckSize(r->alpha.size(), n, "a render's alpha");
  }
  if (still) *still = EmptyMask(object.width, object.height);
  std::size_t pixels = 0, kept = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (!object.bits[p]) continue;
    ++pixels;
    if (!(ColourDistance(before.rgb, after.rgb, p) <= o.colour_tol) || !DepthStill(before, after, p, o)) continue;
    ++kept;
    if (still) still->bits[p] = 1;
  }
  return Finish(double(kept), pixels, o);
}

ResidualSummary SummarizeResidual(const std::vector<ViewResidual>& views) {
  ResidualSummary s;
  std::vector<double> values;
  for (const ViewResidual& v : views) {
    if (v.value) values.push_back(*v.value);
    else ++s.small_views;
  }
  s.stats = ComputeMeanStd(values);
  return s;
}

}  // namespace al::metrics
