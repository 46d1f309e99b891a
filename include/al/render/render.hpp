// CPU 3DGS rasterizer reproducing the INRIA forward pass (RASTERIZER.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "al/io/camera.hpp"
#include "al/scene/scene.hpp"

namespace al {

struct RenderOptions {
  Eigen::Vector3f background = Eigen::Vector3f::Zero();
  float scale_modifier = 1.0f;
  int max_sh_degree = 3;            // evaluated degree = min(scene.sh_degree, this)
  bool frustum_cull = true;         // extra cull that never changes a pixel (RASTERIZER.md §9)
  int num_threads = 0;              // 0 = OpenMP default
  bool compute_front_id = true;
  // Optional (scene-sized, not owned): also accumulate, per pixel, the sum of alpha*T over the
  // Gaussians where (*weight_subset)[i] is true -- the subset's share of the full composite (an
  // object mask is share >= 0.5). Computed in the same compositing pass, so the share uses exactly
  // the T of the image itself; null = not computed, at no cost. Full renders only (Render and
  // IncrementalRenderer::before()); After() and ReferenceRender leave subset_weight empty.
  const std::vector<bool>* weight_subset = nullptr;
  // Optional (N x D row-major, D in [1, kMaxFeatureChannels], not owned): a per-Gaussian feature
  // composited with the same blend weights alpha*T as RGB, in the same pass; RenderOutput::feature
  // receives sum(alpha*T*f) / max(alpha, 1e-10) per pixel (normalised per pixel like the expected
  // depth; 0 where nothing blended). Null = not computed, at no cost (the compositing loop is the
  // one without features). Every other output is bit-identical with or without it. An
  // IncrementalRenderer keeps this pointer for After(): the matrix must outlive the renderer.
  // For D > kMaxFeatureChannels render a projection (al/render/feature_field.hpp).
  const RowMatXf* features = nullptr;
  void Check() const;  // scale_modifier > 0, max_sh_degree in [0, 3], num_threads >= 0, finite background
};

// Most feature channels one render composites (64 floats per pixel = a 64 KiB tile accumulator).
constexpr int kMaxFeatureChannels = 64;

struct RenderOutput {
  int width = 0, height = 0;
  std::vector<float> rgb;           // H*W*3, background composited, not clamped
  std::vector<float> alpha;         // H*W
  std::vector<float> depth;         // H*W expected depth (normalised by alpha), 0 on background
  std::vector<float> invdepth;      // H*W, not normalised
  std::vector<std::int32_t> front_id;  // H*W scene index of the first blended Gaussian, -1 if none
  std::vector<std::int32_t> radii;  // per scene Gaussian (0 = invisible or excluded)
  std::vector<float> subset_weight; // H*W sum of alpha*T over options.weight_subset; empty if none
  int feature_dim = 0;              // D of options.features (0 = none)
  std::vector<float> feature;       // H*W*D pixel-major, see RenderOptions::features; empty if none
  // Statistics.
  std::size_t visible_gaussians = 0, excluded_nonfinite = 0;
  // Finite parameters whose projection overflowed (e.g. log-scale 60): never rendered, counted.
  std::size_t excluded_degenerate = 0;
  std::size_t tiles_total = 0, tiles_rendered = 0, tiles_copied = 0;
  std::size_t tile_entries = 0;     // (Gaussian, tile) pairs in the tile lists
  // (Gaussian, pixel) pairs whose power was evaluated in the composited tiles: pixels inside a
  // Gaussian's window that were still blending (the compositing work; cf. tile_entries · 256).
  std::size_t pixel_evaluations = 0;
  double seconds_preprocess = 0, seconds_binning = 0, seconds_composite = 0;
};

// Per-view state a "before" render keeps so an "after" render can be incremental.
struct RenderCache;

// Full render of the scene without the Gaussians where exclude[i] is true (exclude may be empty).
RenderOutput Render(const Scene& scene, const Camera& camera, const RenderOptions& options = {},
                    const std::vector<bool>& exclude = {});

// Slow per-pixel reference (src/render/reference_render.cpp): same preprocessing, then for every
// pixel a loop over all visible Gaussians sorted by (tz, index), testing tile-rectangle
// membership per pixel. Single-threaded; for tests of the fast path only.
RenderOutput ReferenceRender(const Scene& scene, const Camera& camera, const RenderOptions& options = {},
                             const std::vector<bool>& exclude = {});

// Renders "before" and keeps what an incremental "after" render needs.
class IncrementalRenderer {
 public:
  IncrementalRenderer(const Scene& scene, const Camera& camera, const RenderOptions& options = {},
                      const std::vector<bool>& base_exclude = {});
  ~IncrementalRenderer();
  IncrementalRenderer(const IncrementalRenderer&) = delete;
  IncrementalRenderer& operator=(const IncrementalRenderer&) = delete;
  const RenderOutput& before() const;
  // Bit-identical to Render(scene, camera, options, base_exclude OR removed), the feature image
  // included; only tiles whose lists contain a removed Gaussian are recomposited.
  RenderOutput After(const std::vector<bool>& removed) const;

 private:
  RenderCache* cache_;
};

}  // namespace al
