// What is left of an object after a removal, measured on renders (docs/eval.md, "Residuals").
//
// residual (with an ideal render): for a removal M of a target T, three renders of one view —
// before (the full scene), after (without M) and ideal (without T, or without the refinement that
// stands in for T). The object's footprint is O = the pixels where ‖rgb_before − rgb_ideal‖ > 0.1
// (Euclidean, RGB clamped to [0, 1]); a view's residual is the mean over O of
// min(1, ‖rgb_after − rgb_ideal‖ / ‖rgb_before − rgb_ideal‖): the share of the object's visible
// signal still there, 0 = gone, 1 = untouched. Views with |O| < 64 are not scored (the scene's
// residual is the mean over the scored views). With T from ground-truth labels it is residual_gt;
// with the first refinement's render as the ideal it is residual_est.
//
// pixel residual (residual_px, object masks only): the share of the object mask where the after
// render still matches the before render, per pixel, in colour (‖Δrgb‖ ≤ colour_tol) and in depth
// (both hit and |Δz| ≤ depth_tol · z_before, or both empty). No whole-image stretch: each pixel is
// judged by its own change.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "al/core/option_table.hpp"
#include "al/metrics/mask.hpp"
#include "al/metrics/stats.hpp"

namespace al::metrics {

struct ResidualOptions {
  // The definition's constants (issue 32); options only so that a study can vary them.
  double footprint = 0.1;            // O = pixels where ‖before − ideal‖ > this (RGB in [0, 1])
  int min_pixels = 64;               // views with fewer footprint (or mask) pixels are not scored
  // residual_px: a mask pixel is "still there" when its colour moved by at most colour_tol
  // (Euclidean, RGB in [0, 1]) and its depth by at most depth_tol of the depth before. Chosen on
  // the tuning half of bench/residual (4 scenes of both generators, 38 removals; docs/eval.md): the
  // smallest mean error against residual_gt among the pairs that keep every perfect removal
  // <= 0.02 (0.2 / 0.15: MAE 0.071, Spearman 0.94, perfect <= 0.016; the first guess 0.1 / 0.02:
  // MAE 0.171). Tighter tolerances miss scattered leftovers, which blend with what is behind them.
  double colour_tol = 0.2;
  double depth_tol = 0.15;
  float alpha_hit = 0.0f;            // a pixel has depth iff alpha > this (METRICS.md §6)
  static const OptionTable<ResidualOptions>& Table();  // residual_footprint, residual_min_pixels, px_colour_tol, px_depth_tol
  void Check() const;
};

// One view's residual; value is empty when fewer than min_pixels pixels are scored.
struct ViewResidual {
  std::optional<double> value;
  std::size_t pixels = 0;  // |O| (residual) or |mask| (pixel residual)
};

// RGB images (H*W*3, not clamped; non-finite values read as 0) of one size.
struct ResidualRenders {
  int width = 0, height = 0;
  std::span<const float> before, after, ideal;
};

// The residual of one view. `share` (optional) receives per pixel min(1, ratio) on O and -1
// elsewhere (the overlay of report.html). Throws al::Error when the sizes disagree.
ViewResidual ComputeResidual(const ResidualRenders& renders, const ResidualOptions& options,
                             std::vector<float>* share = nullptr);

// What residual_px reads of one render: H*W*3 RGB, H*W expected depth and alpha.
struct PixelRender {
  std::span<const float> rgb, depth, alpha;
};

// The pixel residual of one view over `object` (same size as the renders). `still` (optional)
// receives the mask pixels that still match. Throws al::Error when the sizes disagree.
ViewResidual ComputePixelResidual(const PixelRender& before, const PixelRender& after, const Mask& object,
                                  const ResidualOptions& options, Mask* still = nullptr);

// Mean and spread over the scored views, and how many views were too small to score.
struct ResidualSummary {
  MeanStd stats;                 // over the views with a value (count = scored views)
  std::size_t small_views = 0;   // views with fewer than min_pixels pixels
};
ResidualSummary SummarizeResidual(const std::vector<ViewResidual>& views);

}  // namespace al::metrics
