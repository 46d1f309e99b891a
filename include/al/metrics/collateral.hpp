// Collateral damage (METRICS.md §7): PSNR of the non-object region before vs after removal.
// (collateral_depth = share of non-object pixels whose depth changed is part of ScoreDepthChange.)
#pragma once
#include <optional>
#include <vector>

#include "al/metrics/mask.hpp"

namespace al::metrics {

// Interleaved RGB, values nominally in [0, 1] (clamped before comparison).
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // height * width * 3
};
// 8-bit PNG colour (any channel count) → [0, 1] RGB.
RgbImage RgbFromPng(const PngData& png);

struct CollateralPsnr {
  std::optional<double> psnr;  // 10·log10(1 / MSE) over Ō, peak 1; empty when MSE = 0 or Ō empty
  bool identical = false;      // MSE = 0 over a non-empty Ō
  std::size_t pixels = 0;      // |Ō|
};

// object: nullptr = no object (Ō = whole image); resized to the renders' size with the exact rule.
CollateralPsnr ComputeCollateralPsnr(const RgbImage& before, const RgbImage& after, const Mask* object);

}  // namespace al::metrics
