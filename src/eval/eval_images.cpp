#include "al/eval/images.hpp"

#include <algorithm>
#include <cmath>

namespace al::eval {
namespace {

std::uint8_t To8(float v) {
  const float c = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(std::lround(c * 255.0f));
}

void Blend(std::uint8_t* px, const float colour[3], float mix) {
  for (int c = 0; c < 3; ++c) px[c] = std::uint8_t(std::lround((1 - mix) * px[c] + mix * colour[c]));
}

}  // namespace

Image8 RenderToRgb8(const RenderOutput& render) {
  const std::size_t n = std::size_t(render.width) * std::size_t(render.height) * 3;
  Image8 img{render.width, render.height, 3, std::vector<std::uint8_t>(n)};
  for (std::size_t i = 0; i < n; ++i) img.pixels[i] = To8(render.rgb[i]);
  return img;
}

Image8 DepthDiffImage(const metrics::Mask& changed, const metrics::Mask& object) {
  const int w = changed.width, h = changed.height;
  const metrics::Mask o = metrics::Resize(object, w, h, metrics::ResizeRule::kExact);
  Image8 img{w, h, 3, std::vector<std::uint8_t>(std::size_t(w) * h * 3, 0)};
  auto in = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h && o.bits[std::size_t(y) * w + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      std::uint8_t* px = &img.pixels[p * 3];
      if (changed.bits[p]) px[0] = px[1] = px[2] = 255;
      // Outline drawn over the change so the object's extent stays visible where it changed.
      if (in(x, y) && !(in(x - 1, y) && in(x + 1, y) && in(x, y - 1) && in(x, y + 1))) {
        px[0] = 0;
        px[1] = 255;
        px[2] = 0;
      }
    }
  return img;
}

Image8 AddedOverlay(const RenderOutput& after, const std::vector<bool>& added, std::size_t* painted) {
  Image8 img = RenderToRgb8(after);
  static constexpr float kPink[3] = {255.f, 105.f, 180.f};
  constexpr float kMix = 0.65f;
  std::size_t count = 0;
  const std::size_t n = std::size_t(after.width) * std::size_t(after.height);
  for (std::size_t p = 0; p < n && p < after.front_id.size(); ++p) {
    const std::int32_t id = after.front_id[p];
    if (id < 0 || std::size_t(id) >= added.size() || !added[std::size_t(id)]) continue;
    ++count;
    for (int c = 0; c < 3; ++c)
      img.pixels[p * 3 + c] = std::uint8_t(std::lround((1 - kMix) * img.pixels[p * 3 + c] + kMix * kPink[c]));
  }
  if (painted) *painted = count;
  return img;
}

Image8 ResidualOverlay(const RenderOutput& render, const metrics::Mask& object, const metrics::Mask& changed) {
  Image8 img = RenderToRgb8(render);
  const metrics::Mask o = metrics::Resize(object, changed.width, changed.height, metrics::ResizeRule::kExact);
  static constexpr float kRed[3] = {230.f, 20.f, 20.f};
  if (changed.width != img.width || changed.height != img.height) return img;
  for (std::size_t p = 0; p < o.bits.size(); ++p)
    if (o.bits[p] && !changed.bits[p]) Blend(&img.pixels[p * 3], kRed, 0.6f);
  return img;
}

void PaintRestored(Image8& image, const RenderOutput& render, const std::vector<bool>& restored) {
  static constexpr float kCyan[3] = {0.f, 200.f, 230.f};
  const std::size_t n = std::min(std::size_t(image.width) * std::size_t(image.height), render.front_id.size());
  for (std::size_t p = 0; p < n; ++p) {
    const std::int32_t id = render.front_id[p];
    if (id >= 0 && std::size_t(id) < restored.size() && restored[std::size_t(id)]) Blend(&image.pixels[p * 3], kCyan, 0.65f);
  }
}

}  // namespace al::eval
