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
// in `added` blended 65 % towards pink (255, 105, 180), as in the paper's refinement figures; with
// `refined` and `restored`, also the pixels where the refined render's front Gaussian is one the
// refinement restored, blended towards cyan (0, 200, 255) over the refined render's colour.
// Returns the number of painted pixels through `painted` (may be null).
Image8 AddedOverlay(const RenderOutput& after, const std::vector<bool>& added, std::size_t* painted = nullptr,
                    const RenderOutput* refined = nullptr, const std::vector<bool>* restored = nullptr);

}  // namespace al::eval
