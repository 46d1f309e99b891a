#include "al/eval/images.hpp"

#include <algorithm>
#include <cmath>

namespace al::eval {
namespace {

std::uint8_t To8(float v) {
  const float c = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(std::lround(c * 255.0f));
}

// Object pixels with a 4-neighbour outside the object or on the image border.
bool OnOutline(const metrics::Mask& o, int x, int y) {
  auto in = [&](int u, int v) { return u >= 0 && v >= 0 && u < o.width && v < o.height && o.bits[std::size_t(v) * o.width + u]; };
  return in(x, y) && !(in(x - 1, y) && in(x + 1, y) && in(x, y - 1) && in(x, y + 1));
}

// One half of FeatureSegImage: the render as dimmed grey, tinted where the masks say.
void PaintPanel(const RenderOutput& render, const metrics::Mask& object, const metrics::Mask& target,
                const metrics::Mask* residual_of, int x_offset, Image8& img) {
  const Image8 rgb = RenderToRgb8(render);
  const int w = render.width, h = render.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      const std::uint8_t* src = &rgb.pixels[p * 3];
      const float grey = 0.5f * (0.299f * src[0] + 0.587f * src[1] + 0.114f * src[2]);
      float c[3] = {grey, grey, grey};
      const float* tint = nullptr;
      static constexpr float kBlue[3] = {40, 110, 255}, kRed[3] = {255, 30, 30}, kGreen[3] = {0, 255, 0};
      if (target.bits[p]) tint = residual_of && residual_of->bits[p] && object.bits[p] ? kRed : kBlue;
      if (tint)
        for (int k = 0; k < 3; ++k) c[k] = 0.35f * c[k] + 0.65f * tint[k];
      if (OnOutline(object, x, y)) tint = kGreen;
      std::uint8_t* dst = &img.pixels[(std::size_t(y) * img.width + x_offset + x) * 3];
      for (int k = 0; k < 3; ++k) dst[k] = static_cast<std::uint8_t>(std::lround(tint == kGreen ? tint[k] : c[k]));
    }
}

void Blend(std::uint8_t* px, const float colour[3], float mix) {
  for (int c = 0; c < 3; ++c) px[c] = std::uint8_t(std::lround((1 - mix) * px[c] + mix * colour[c]));
}

}  // namespace

Image8 FeatureSegImage(const RenderOutput& before, const RenderOutput& after, const metrics::Mask& object,
                       const metrics::Mask& target_before, const metrics::Mask& target_after) {
  const int w = before.width, h = before.height;
  Image8 img{2 * w, h, 3, std::vector<std::uint8_t>(std::size_t(2 * w) * h * 3, 0)};
  PaintPanel(before, object, target_before, nullptr, 0, img);
  // Residual: target after where it was the object's target before.
  PaintPanel(after, object, target_after, &target_before, w, img);
  return img;
}

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

Image8 ResidualOverlay(const RenderOutput& render, const std::vector<float>& share) {
  Image8 img = RenderToRgb8(render);
  const std::size_t n = std::size_t(render.width) * std::size_t(render.height);
  if (share.size() != n) return img;
  metrics::Mask footprint = metrics::EmptyMask(render.width, render.height);
  for (std::size_t p = 0; p < n; ++p) footprint.bits[p] = share[p] >= 0 ? 1 : 0;
  static constexpr float kRed[3] = {230.f, 20.f, 20.f}, kGreen[3] = {0.f, 255.f, 0.f};
  for (int y = 0; y < render.height; ++y)
    for (int x = 0; x < render.width; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(render.width) + std::size_t(x);
      if (share[p] > 0) Blend(&img.pixels[p * 3], kRed, 0.8f * std::min(share[p], 1.0f));
      if (OnOutline(footprint, x, y)) Blend(&img.pixels[p * 3], kGreen, 1.0f);
    }
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
