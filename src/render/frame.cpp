// Depth order, tile binning (RASTERIZER.md §4) and per-tile compositing (§5, §7).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "src/render/frame.hpp"

namespace al::render_internal {
namespace {

// LSD radix sort of unique 64-bit keys (float bits of tz > 0 order like the values, the low
// 32 bits hold the scene index, so the result is the (tz, index) order). Digits on which all
// keys agree are skipped, which makes small scenes cheap.
void RadixSort(std::vector<std::uint64_t>& keys) {
  constexpr int kBits = 16;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  std::vector<std::uint64_t> tmp(keys.size());
  std::vector<std::uint32_t> count(kBuckets);
  for (int shift = 0; shift < 64; shift += kBits) {
    std::fill(count.begin(), count.end(), 0u);
    for (std::uint64_t k : keys) ++count[(k >> shift) & (kBuckets - 1)];
    if (!keys.empty() && count[(keys[0] >> shift) & (kBuckets - 1)] == keys.size()) continue;
    std::uint32_t sum = 0;
    for (auto& c : count) {
      const std::uint32_t next = sum + c;
      c = sum;
      sum = next;
    }
    for (std::uint64_t k : keys) tmp[count[(k >> shift) & (kBuckets - 1)]++] = k;
    keys.swap(tmp);
  }
}

}  // namespace

void BuildFrame(Frame& frame) {
  const Projected& p = frame.proj;
  const std::size_t n = p.status.size();
  std::vector<std::uint64_t> keys;
  keys.reserve(p.visible);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.status[i] != kVisible) continue;
    std::uint32_t bits;
    std::memcpy(&bits, &p.tz[i], sizeof bits);
    keys.push_back((std::uint64_t{bits} << 32) | static_cast<std::uint32_t>(i));
  }
  RadixSort(keys);

  frame.splats.resize(keys.size());
  frame.rects.resize(keys.size());
  const int gx = frame.view.grid_x, gy = frame.view.grid_y;
  const std::size_t tiles = static_cast<std::size_t>(gx) * gy;
  std::vector<std::uint32_t> count(tiles + 1, 0);
  for (std::size_t r = 0; r < keys.size(); ++r) {
    const std::uint32_t i = static_cast<std::uint32_t>(keys[r]);
    Splat& s = frame.splats[r];
    s.u = p.u[i];
    s.v = p.v[i];
    s.a = p.conic_a[i];
    s.b = p.conic_b[i];
    s.c = p.conic_c[i];
    s.opacity = p.opacity[i];
    s.red = p.red[i];
    s.green = p.green[i];
    s.blue = p.blue[i];
    s.tz = p.tz[i];
    // alpha = o*exp(power) < 1/255 whenever power < ln(1/(255 o)); the 1e-3 margin keeps the
    // shortcut exact despite expf/float rounding (o = 0 gives +inf: never blended).
    const double floor = std::log(1.0 / (255.0 * static_cast<double>(s.opacity))) - 1e-3;
    s.power_floor = static_cast<float>(floor);
    s.id = static_cast<std::int32_t>(i);
    // power = -q/2 with q = d^T [A B; B C] d, so power >= floor inside the ellipse q <= -2 floor,
    // whose half-extents are sqrt(k C / det), sqrt(k A / det). Relative and absolute margins
    // cover float rounding of power; a non-positive-definite conic keeps the full rectangle.
    TileRect& rect = frame.rects[r];
    rect = {p.xmin[i], p.ymin[i], p.xmax[i], p.ymax[i]};
    const double k = std::max(0.0, -2.0 * static_cast<double>(s.power_floor));
    const double det = double(s.a) * s.c - double(s.b) * s.b;
    if (det > 0 && std::isfinite(det) && s.a > 0 && s.c > 0) {
      const double ex = std::sqrt(k * s.c / det) * 1.001 + 0.05, ey = std::sqrt(k * s.a / det) * 1.001 + 0.05;
      s.ext_x = static_cast<float>(std::min(ex, 1e30));
      s.ext_y = static_cast<float>(std::min(ey, 1e30));
      auto tile_lo = [](double c) { return c <= 0 ? 0.0 : std::floor(c / kTile); };
      const double tx0 = tile_lo(std::ceil(s.u - ex)), tx1 = tile_lo(std::floor(s.u + ex)) + 1;
      const double ty0 = tile_lo(std::ceil(s.v - ey)), ty1 = tile_lo(std::floor(s.v + ey)) + 1;
      if (s.u + ex < 0 || s.v + ey < 0) {
        rect.x1 = rect.x0;  // entirely left of / above the image
      } else {
        // Intersect in double, then narrow (all values end inside [0, grid]).
        const double nx0 = std::max<double>(rect.x0, tx0), ny0 = std::max<double>(rect.y0, ty0);
        const double nx1 = std::min<double>(rect.x1, tx1), ny1 = std::min<double>(rect.y1, ty1);
        if (nx1 <= nx0 || ny1 <= ny0) {
          rect.x1 = rect.x0;
        } else {
          rect = {static_cast<std::int32_t>(nx0), static_cast<std::int32_t>(ny0), static_cast<std::int32_t>(nx1),
                  static_cast<std::int32_t>(ny1)};
        }
      }
    } else {
      s.ext_x = s.ext_y = std::numeric_limits<float>::infinity();
    }
    if (rect.x1 <= rect.x0 || rect.y1 <= rect.y0) rect = {0, 0, 0, 0};
    for (int ty = rect.y0; ty < rect.y1; ++ty)
      for (int tx = rect.x0; tx < rect.x1; ++tx) ++count[static_cast<std::size_t>(ty) * gx + tx];
  }
  frame.tile_offsets.assign(tiles + 1, 0);
  for (std::size_t t = 0; t < tiles; ++t) frame.tile_offsets[t + 1] = frame.tile_offsets[t] + count[t];
  frame.tile_ranks.resize(frame.tile_offsets[tiles]);
  std::vector<std::uint32_t> cursor(frame.tile_offsets.begin(), frame.tile_offsets.end() - 1);
  for (std::size_t r = 0; r < keys.size(); ++r) {
    const TileRect& rect = frame.rects[r];
    for (int ty = rect.y0; ty < rect.y1; ++ty)
      for (int tx = rect.x0; tx < rect.x1; ++tx)
        frame.tile_ranks[cursor[static_cast<std::size_t>(ty) * gx + tx]++] = static_cast<std::uint32_t>(r);
  }
}

void AllocateOutput(int width, int height, std::size_t num_gaussians, bool front_id, RenderOutput& out) {
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  out.width = width;
  out.height = height;
  out.rgb.assign(pixels * 3, 0.0f);
  out.alpha.assign(pixels, 0.0f);
  out.depth.assign(pixels, 0.0f);
  out.invdepth.assign(pixels, 0.0f);
  if (front_id)
    out.front_id.assign(pixels, -1);
  else
    out.front_id.clear();
  out.radii.assign(num_gaussians, 0);
}

void CompositeTile(const Frame& frame, int tile, const std::uint8_t* skip,
                   const Eigen::Vector3f& background, bool front_id, RenderOutput& out) {
  constexpr int kPix = kTile * kTile;
  const int W = frame.view.width, H = frame.view.height;
  const int x0 = (tile % frame.view.grid_x) * kTile, y0 = (tile / frame.view.grid_x) * kTile;
  const int w = std::min(kTile, W - x0), h = std::min(kTile, H - y0);
  const int n = w * h;  // pixels outside the image are never evaluated
  float T[kPix], cr[kPix], cg[kPix], cb[kPix], dsum[kPix], inv[kPix], pxf[kPix], pyf[kPix];
  std::int32_t fid[kPix];
  std::uint8_t active[kPix];
  for (int p = 0; p < n; ++p) {
    T[p] = 1.0f;
    cr[p] = cg[p] = cb[p] = dsum[p] = inv[p] = 0.0f;
    fid[p] = -1;
    active[p] = 1;
    pxf[p] = static_cast<float>(x0 + p % w);
    pyf[p] = static_cast<float>(y0 + p / w);
  }
  int remaining = n;
  const std::uint32_t begin = frame.tile_offsets[tile], end = frame.tile_offsets[tile + 1];
  for (std::uint32_t k = begin; k < end && remaining > 0; ++k) {
    const std::uint32_t rank = frame.tile_ranks[k];
    if (skip != nullptr && skip[rank]) continue;
    const Splat& s = frame.splats[rank];
    // Pixel window of the tile the Gaussian can reach (local coordinates, inclusive).
    int lx0 = 0, lx1 = w - 1, ly0 = 0, ly1 = h - 1;
    if (s.ext_x < 1e29f) {
      auto local = [](float c) { return static_cast<int>(std::clamp(c, -1.0f, float(kTile))); };
      lx0 = std::max(lx0, local(std::ceil(s.u - s.ext_x) - x0));
      lx1 = std::min(lx1, local(std::floor(s.u + s.ext_x) - x0));
      ly0 = std::max(ly0, local(std::ceil(s.v - s.ext_y) - y0));
      ly1 = std::min(ly1, local(std::floor(s.v + s.ext_y) - y0));
    }
    for (int ly = ly0; ly <= ly1; ++ly)
    for (int p = ly * w + lx0; p <= ly * w + lx1; ++p) {
      if (!active[p]) continue;
      const float dx = s.u - pxf[p], dy = s.v - pyf[p];
      const float power = -0.5f * (s.a * dx * dx + s.c * dy * dy) - s.b * dx * dy;
      if (!(power <= 0.0f) || power < s.power_floor) continue;
      const float alpha = std::min(0.99f, s.opacity * std::exp(power));
      if (alpha < 1.0f / 255.0f) continue;
      const float test_t = T[p] * (1.0f - alpha);
      if (test_t < 0.0001f) {
        active[p] = 0;
        --remaining;
        continue;
      }
      const float t = T[p];
      cr[p] += s.red * alpha * t;
      cg[p] += s.green * alpha * t;
      cb[p] += s.blue * alpha * t;
      const float weight = alpha * t;
      dsum[p] += weight * s.tz;
      inv[p] += weight / s.tz;
      if (fid[p] < 0) fid[p] = s.id;
      T[p] = test_t;
    }
  }
  for (int p = 0; p < n; ++p) {
    const std::size_t idx = static_cast<std::size_t>(y0 + p / w) * W + (x0 + p % w);
    out.rgb[idx * 3 + 0] = cr[p] + T[p] * background[0];
    out.rgb[idx * 3 + 1] = cg[p] + T[p] * background[1];
    out.rgb[idx * 3 + 2] = cb[p] + T[p] * background[2];
    const float a = 1.0f - T[p];
    out.alpha[idx] = a;
    out.depth[idx] = dsum[p] / std::max(a, 1e-10f);
    out.invdepth[idx] = inv[p];
    if (front_id) out.front_id[idx] = fid[p];
  }
}

}  // namespace al::render_internal
