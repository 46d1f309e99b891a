// Fast path: preprocessing, binning, OpenMP over tiles; incremental "after" render (§9).
#include "al/render/render.hpp"

#include <algorithm>

#include "al/core/error.hpp"
#include "al/core/timer.hpp"
#include "src/render/frame.hpp"

namespace al {

using namespace render_internal;

struct RenderCache {
  Frame frame;
  RenderOutput before;
  RenderOptions options;
};

namespace {

void CompositeTiles(const Frame& frame, const std::vector<int>* tiles, const std::uint8_t* skip,
                    const std::uint8_t* subset, const FeatureInput& features, const RenderOptions& options,
                    RenderOutput& out) {
  const int total = tiles ? static_cast<int>(tiles->size()) : frame.view.grid_x * frame.view.grid_y;
  std::uint64_t evaluations = 0;
  // Tile costs vary by orders of magnitude (list lengths), hence the dynamic schedule.
#pragma omp parallel for schedule(dynamic, 1) num_threads(ThreadCount(options)) reduction(+ : evaluations)
  for (int k = 0; k < total; ++k)
    evaluations +=
        CompositeTile(frame, tiles ? (*tiles)[k] : k, skip, subset, features, options.background,
                      options.compute_front_id, out);
  out.pixel_evaluations = evaluations;
}

void FullRender(const Scene& scene, const Camera& camera, const RenderOptions& options,
                const std::vector<bool>& exclude, Frame& frame, RenderOutput& out) {
  options.Check();
  CheckInputs(scene, camera, exclude);
  if (options.weight_subset != nullptr && options.weight_subset->size() != scene.size())
    throw Error("weight subset has " + std::to_string(options.weight_subset->size()) + " entries, scene has " +
                std::to_string(scene.size()) + " Gaussians");
  const FeatureInput features = FeaturesOf(options, scene.size());
  Timer timer;
  frame.view = MakeViewParams(camera);
  Preprocess(scene, frame.view, options, exclude, frame.proj);
  out.seconds_preprocess = timer.Seconds();
  timer.Reset();
  BuildFrame(frame, ThreadCount(options));
  out.seconds_binning = timer.Seconds();
  timer.Reset();
  AllocateOutput(camera.width, camera.height, scene.size(), options.compute_front_id, out);
  // Subset flags by depth rank, so the compositing loop reads one byte next to the splat it
  // already gathers instead of a scene-indexed bit.
  std::vector<std::uint8_t> subset;
  if (options.weight_subset != nullptr) {
    const std::vector<bool>& in = *options.weight_subset;
    subset.resize(frame.splats.size());
    for (std::size_t r = 0; r < frame.splats.size(); ++r) subset[r] = in[frame.splats[r].id] ? 1 : 0;
    out.subset_weight.assign(static_cast<std::size_t>(camera.width) * camera.height, 0.0f);
  }
  if (features.rows != nullptr) {
    out.feature_dim = features.dim;
    out.feature.assign(static_cast<std::size_t>(camera.width) * camera.height * features.dim, 0.0f);
  }
  CompositeTiles(frame, nullptr, nullptr, subset.empty() ? nullptr : subset.data(), features, options, out);
  out.seconds_composite = timer.Seconds();
  out.radii = frame.proj.radius;
  out.visible_gaussians = frame.proj.visible;
  out.excluded_nonfinite = frame.proj.nonfinite;
  out.excluded_degenerate = frame.proj.degenerate;
  out.tiles_total = static_cast<std::size_t>(frame.view.grid_x) * frame.view.grid_y;
  out.tiles_rendered = out.tiles_total;
  out.tiles_copied = 0;
  out.tile_entries = frame.tile_ranks.size();
}

}  // namespace

RenderOutput Render(const Scene& scene, const Camera& camera, const RenderOptions& options,
                    const std::vector<bool>& exclude) {
  Frame frame;
  RenderOutput out;
  FullRender(scene, camera, options, exclude, frame, out);
  return out;
}

IncrementalRenderer::IncrementalRenderer(const Scene& scene, const Camera& camera, const RenderOptions& options,
                                         const std::vector<bool>& base_exclude)
    : cache_(new RenderCache) {
  try {
    cache_->options = options;
    cache_->options.weight_subset = nullptr;  // the caller's vector need not outlive the constructor
    FullRender(scene, camera, options, base_exclude, cache_->frame, cache_->before);
  } catch (...) {
    delete cache_;
    throw;
  }
}

IncrementalRenderer::~IncrementalRenderer() { delete cache_; }

const RenderOutput& IncrementalRenderer::before() const { return cache_->before; }

RenderOutput IncrementalRenderer::After(const std::vector<bool>& removed) const {
  const Frame& frame = cache_->frame;
  const RenderOutput& before = cache_->before;
  const std::size_t n = frame.proj.status.size();
  if (!removed.empty() && removed.size() != n)
    throw Error("removal mask has " + std::to_string(removed.size()) + " entries, scene has " +
                std::to_string(n) + " Gaussians");
  Timer timer;
  RenderOutput out = before;
  out.subset_weight.clear();  // a "before" quantity: not recomputed for the after image
  out.seconds_preprocess = 0;
  out.seconds_binning = 0;
  const int gx = frame.view.grid_x;
  const std::size_t tiles = out.tiles_total;
  // Ranks of removed visible Gaussians and the tiles their rectangles cover.
  std::vector<std::uint8_t> skip(frame.splats.size(), 0);
  std::vector<std::uint8_t> dirty(tiles, 0);
  const Projected& p = frame.proj;
  std::size_t removed_entries = 0, removed_visible = 0, removed_nonfinite = 0, removed_degenerate = 0;
  if (!removed.empty()) {
    for (std::size_t r = 0; r < frame.splats.size(); ++r) {
      const std::int32_t i = frame.splats[r].id;
      if (!removed[i]) continue;
      skip[r] = 1;
      ++removed_visible;
      const TileRect& rect = frame.rects[r];
      removed_entries += static_cast<std::size_t>(rect.x1 - rect.x0) * (rect.y1 - rect.y0);
      for (int ty = rect.y0; ty < rect.y1; ++ty)
        for (int tx = rect.x0; tx < rect.x1; ++tx) dirty[static_cast<std::size_t>(ty) * gx + tx] = 1;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!removed[i]) continue;
      out.radii[i] = 0;
      removed_nonfinite += p.status[i] == kNonFinite;
      removed_degenerate += p.status[i] == kDegenerate;
    }
  }
  std::vector<int> work;
  for (std::size_t t = 0; t < tiles; ++t)
    if (dirty[t]) work.push_back(static_cast<int>(t));
  out.seconds_binning = timer.Seconds();
  timer.Reset();
  // The feature image (copied with `before`) is recomposited in the same tiles.
  CompositeTiles(frame, &work, skip.data(), nullptr, FeaturesOf(cache_->options, n), cache_->options, out);
  out.seconds_composite = timer.Seconds();
  out.visible_gaussians = before.visible_gaussians - removed_visible;
  out.excluded_nonfinite = before.excluded_nonfinite - removed_nonfinite;
  out.excluded_degenerate = before.excluded_degenerate - removed_degenerate;
  out.tiles_rendered = work.size();
  out.tiles_copied = tiles - work.size();
  out.tile_entries = before.tile_entries - removed_entries;
  return out;
}

}  // namespace al
