#include "al/metrics/mask.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "al/core/error.hpp"

namespace al::metrics {

std::size_t Mask::Count() const {
  std::size_t n = 0;
  for (std::uint8_t b : bits) n += b != 0;
  return n;
}

Mask EmptyMask(int width, int height) {
  Mask m;
  m.width = std::max(width, 0);
  m.height = std::max(height, 0);
  m.bits.assign(std::size_t(m.width) * std::size_t(m.height), 0);
  return m;
}

std::vector<int> NearestSourceIndex(int in, int out, ResizeRule rule) {
  std::vector<int> src(std::max(out, 0));
  for (int d = 0; d < out; ++d) {
    // Integer arithmetic: floor(d·in/out) and floor((2d+1)·in/(2·out)) are exact this way.
    std::int64_t s = rule == ResizeRule::kFloor ? std::int64_t(d) * in / out
                                                : (2 * std::int64_t(d) + 1) * in / (2 * std::int64_t(out));
    src[d] = int(std::min<std::int64_t>(s, in - 1));
  }
  return src;
}

namespace {
template <class T>
std::vector<T> ResizePlane(const std::vector<T>& data, int w, int h, int ow, int oh, ResizeRule rule) {
  std::vector<T> out(std::size_t(std::max(ow, 0)) * std::size_t(std::max(oh, 0)), T(0));
  if (w <= 0 || h <= 0) return out;  // an empty source resizes to all zeros
  const auto xs = NearestSourceIndex(w, ow, rule), ys = NearestSourceIndex(h, oh, rule);
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) out[std::size_t(y) * ow + x] = data[std::size_t(ys[y]) * w + xs[x]];
  return out;
}
}  // namespace

Gray8 Resize(const Gray8& image, int width, int height, ResizeRule rule) {
  if (image.width == width && image.height == height) return image;
  return {width, height, ResizePlane(image.pixels, image.width, image.height, width, height, rule)};
}

Mask Resize(const Mask& mask, int width, int height, ResizeRule rule) {
  if (mask.width == width && mask.height == height) return mask;
  return {width, height, ResizePlane(mask.bits, mask.width, mask.height, width, height, rule)};
}

Mask Binarize(const Gray8& image, std::uint8_t threshold) {
  Mask m{image.width, image.height, std::vector<std::uint8_t>(image.pixels.size())};
  for (std::size_t i = 0; i < image.pixels.size(); ++i) m.bits[i] = image.pixels[i] > threshold;
  return m;
}

Gray8 ToLuma8(const PngData& png, bool* lossy) {
  if (lossy) *lossy = false;
  const std::size_t n = std::size_t(png.width) * std::size_t(png.height);
  const int c = png.channels;
  if (png.width < 0 || png.height < 0 || c < 1 || c > 4 || png.values.size() != n * std::size_t(c))
    throw Error("ToLuma8: inconsistent image buffer");
  Gray8 g{png.width, png.height, std::vector<std::uint8_t>(n)};
  const int depth = png.bit_depth;
  const bool colour = c >= 3;
  auto to8 = [&](std::uint16_t v) -> std::uint32_t {
    if (depth == 16) {
      if (!colour) {  // PIL I;16 → L clips
        if (v > 255 && lossy) *lossy = true;
        return std::min<std::uint32_t>(v, 255);
      }
      if ((v & 0xFF) && lossy) *lossy = true;
      return v >> 8;  // PIL reads 16-bit colour PNGs as 8-bit RGB (high byte)
    }
    if (depth < 8) return std::uint32_t(v) * 255u / ((1u << depth) - 1u);
    return v;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t* p = &png.values[i * c];
    if (colour) {
      const std::uint32_t r = to8(p[0]), gg = to8(p[1]), b = to8(p[2]);
      g.pixels[i] = std::uint8_t((r * 19595u + gg * 38470u + b * 7471u + 0x8000u) >> 16);
    } else {
      g.pixels[i] = std::uint8_t(to8(p[0]));
    }
  }
  return g;
}

Overlap CountOverlap(const Mask& a, const Mask& b) {
  if (a.width != b.width || a.height != b.height || a.bits.size() != b.bits.size())
    throw Error("mask size mismatch: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
                std::to_string(b.width) + "x" + std::to_string(b.height));
  Overlap o;
  for (std::size_t i = 0; i < a.bits.size(); ++i) {
    const bool x = a.bits[i] != 0, y = b.bits[i] != 0;
    o.a += x;
    o.b += y;
    o.intersection += x && y;
    o.union_ += x || y;
  }
  return o;
}

double IoU(const Mask& a, const Mask& b) {
  const Overlap o = CountOverlap(a, b);
  return o.union_ == 0 ? 0.0 : double(o.intersection) / double(o.union_);
}

double AccIn(const Mask& object, const Mask& predicted) {
  const Overlap o = CountOverlap(object, predicted);
  return o.a == 0 ? 0.0 : double(o.intersection) / double(o.a);
}

}  // namespace al::metrics
