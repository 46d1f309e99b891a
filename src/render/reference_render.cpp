// Plain per-pixel reference renderer (the "slow" half of a gsplat-style split): no tile lists,
// no radix sort, no shortcuts. Every pixel walks all visible Gaussians in (tz, index) order and
// uses a Gaussian iff the pixel's tile lies in its tile rectangle (RASTERIZER.md §3.7, §5).
// Tests compare the fast path against it bit for bit.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "al/render/render.hpp"
#include "src/render/frame.hpp"

namespace al {

using namespace render_internal;

RenderOutput ReferenceRender(const Scene& scene, const Camera& camera, const RenderOptions& options,
                             const std::vector<bool>& exclude) {
  options.Check();
  CheckInputs(scene, camera, exclude);
  const FeatureInput features = FeaturesOf(options, scene.size());
  const int dim = features.dim;
  const ViewParams view = MakeViewParams(camera);
  Projected p;
  RenderOptions one_thread = options;
  one_thread.num_threads = 1;
  Preprocess(scene, view, one_thread, exclude, p);

  std::vector<std::int32_t> order;
  for (std::size_t i = 0; i < scene.size(); ++i)
    if (p.status[i] == kVisible) order.push_back(static_cast<std::int32_t>(i));
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) { return p.tz[a] < p.tz[b]; });

  RenderOutput out;
  AllocateOutput(camera.width, camera.height, scene.size(), options.compute_front_id, out);
  const int W = camera.width, H = camera.height;
  out.feature_dim = dim;
  out.feature.assign(static_cast<std::size_t>(W) * H * dim, 0.0f);
  std::vector<float> fsum(static_cast<std::size_t>(dim));
  for (int py = 0; py < H; ++py) {
    for (int px = 0; px < W; ++px) {
      const int tx = px / kTile, ty = py / kTile;
      float T = 1.0f, acc[3] = {0, 0, 0}, dsum = 0, inv = 0;
      std::int32_t fid = -1;
      std::fill(fsum.begin(), fsum.end(), 0.0f);
      for (std::int32_t i : order) {
        if (tx < p.xmin[i] || tx >= p.xmax[i] || ty < p.ymin[i] || ty >= p.ymax[i]) continue;
        const float dx = p.u[i] - static_cast<float>(px), dy = p.v[i] - static_cast<float>(py);
        const float power = -0.5f * (p.conic_a[i] * dx * dx + p.conic_c[i] * dy * dy) - p.conic_b[i] * dx * dy;
        if (!(power <= 0.0f)) continue;
        const float alpha = std::min(0.99f, p.opacity[i] * std::exp(power));
        if (alpha < 1.0f / 255.0f) continue;
        const float test_t = T * (1.0f - alpha);
        if (test_t < 0.0001f) break;
        acc[0] += p.red[i] * alpha * T;
        acc[1] += p.green[i] * alpha * T;
        acc[2] += p.blue[i] * alpha * T;
        const float weight = alpha * T;
        dsum += weight * p.tz[i];
        inv += weight / p.tz[i];
        for (int ch = 0; ch < dim; ++ch) fsum[ch] += weight * features.rows[std::size_t(i) * dim + ch];
        if (fid < 0) fid = i;
        T = test_t;
      }
      const std::size_t idx = static_cast<std::size_t>(py) * W + px;
      for (int ch = 0; ch < 3; ++ch) out.rgb[idx * 3 + ch] = acc[ch] + T * options.background[ch];
      const float a = 1.0f - T;
      out.alpha[idx] = a;
      out.depth[idx] = dsum / std::max(a, 1e-10f);
      out.invdepth[idx] = inv;
      if (options.compute_front_id) out.front_id[idx] = fid;
      for (int ch = 0; ch < dim; ++ch) out.feature[idx * dim + ch] = fsum[ch] / std::max(a, 1e-10f);
    }
  }
  out.radii = p.radius;
  out.visible_gaussians = p.visible;
  out.excluded_nonfinite = p.nonfinite;
  out.excluded_degenerate = p.degenerate;
  out.tiles_total = static_cast<std::size_t>(view.grid_x) * view.grid_y;
  out.tiles_rendered = out.tiles_total;
  return out;
}

}  // namespace al
