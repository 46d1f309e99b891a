// The evaluator's per-view pictures (SPEC §6): 8-bit RGB of a render, the thresholded depth change
// with the object outline, and the refinement overlay of the paper's figures (pink = added).
#pragma once
#include <vector>

#include "al/io/image.hpp"
#include "al/metrics/mask.hpp"
#include "al/render/render.hpp"

namespace al::eval {

// RGB clamped to [0, 1], rounded to 8 bits (non-finite values → 0).
Image8 RenderToRgb8(const RenderOutput& render);

// Changed pixels white, others black; the boundary of `object` (resized to the change mask's size
// with the exact rule) green: object pixels with a 4-neighbour outside the object or on the border.
Image8 DepthDiffImage(const metrics::Mask& changed, const metrics::Mask& object);

// The "after" render with the pixels whose front-most blended Gaussian (RenderOutput::front_id) is
// in `added` blended 65 % towards pink (255, 105, 180), as in the paper's refinement figures.
// Returns the number of painted pixels through `painted` (may be null).
Image8 AddedOverlay(const RenderOutput& after, const std::vector<bool>& added, std::size_t* painted = nullptr);

// The feature segmentations of a before/after pair side by side (2W x H): left the "before" render
// with its target pixels tinted blue, right the "after" render with its target pixels tinted blue
// and the residual pixels (object ∩ target before ∩ target after) red; the object outline green on
// both. Renders are dimmed to grey so the colours read.
Image8 FeatureSegImage(const RenderOutput& before, const RenderOutput& after, const metrics::Mask& object,
                       const metrics::Mask& target_before, const metrics::Mask& target_after);

// The residual overlay of report.html: `render` (the column's) with each pixel of the residual's
// footprint (share >= 0, al/eval/residuals.hpp) blended towards red (230, 20, 20) by 0.8 x its
// share of the object still there, and the footprint outlined green: what is left of the object,
// and where. A share of another size leaves the render as it is.
Image8 ResidualOverlay(const RenderOutput& render, const std::vector<float>& share);

// Paints, in place, the pixels of `image` whose front-most Gaussian in `render` (the render that
// shows them, i.e. without the refinement's removal) is in `restored`, 65 % towards cyan (0, 200, 230).
void PaintRestored(Image8& image, const RenderOutput& render, const std::vector<bool>& restored);

}  // namespace al::eval
