#include "al/metrics/collateral.hpp"

#include <algorithm>
#include <cmath>

#include "al/core/error.hpp"

namespace al::metrics {

RgbImage RgbFromPng(const PngData& png) {
  const std::size_t n = std::size_t(png.width) * std::size_t(png.height);
  if (png.channels < 1 || png.values.size() != n * std::size_t(png.channels)) throw Error("RgbFromPng: bad buffer");
  const double peak = png.bit_depth >= 16 ? 65535.0 : double((1 << png.bit_depth) - 1);
  RgbImage img{png.width, png.height, std::vector<float>(n * 3)};
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const int src = png.channels >= 3 ? c : 0;  // grey (and grey+alpha) replicate
      img.rgb[i * 3 + c] = float(png.values[i * png.channels + src] / peak);
    }
  return img;
}

CollateralPsnr ComputeCollateralPsnr(const RgbImage& before, const RgbImage& after, const Mask* object) {
  const std::size_t n = std::size_t(before.width) * std::size_t(before.height);
  if (before.width != after.width || before.height != after.height || before.rgb.size() != n * 3 ||
      after.rgb.size() != n * 3)
    throw Error("collateral PSNR: before/after renders differ in size");
  const Mask o = object ? Resize(*object, before.width, before.height, ResizeRule::kExact)
                        : EmptyMask(before.width, before.height);
  CollateralPsnr r;
  double sse = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (o.bits[i]) continue;
    ++r.pixels;
    for (int c = 0; c < 3; ++c) {
      const double a = std::clamp(double(before.rgb[i * 3 + c]), 0.0, 1.0);
      const double b = std::clamp(double(after.rgb[i * 3 + c]), 0.0, 1.0);
      sse += (a - b) * (a - b);
    }
  }
  if (r.pixels == 0) return r;
  const double mse = sse / double(r.pixels * 3);
  if (mse == 0) {
    r.identical = true;
    return r;
  }
  r.psnr = 10.0 * std::log10(1.0 / mse);
  return r;
}

}  // namespace al::metrics
