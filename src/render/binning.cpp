// Depth order and tile binning (RASTERIZER.md §4), parallel over contiguous chunks.
//
// Every step splits its input into `chunks` contiguous pieces handled by one loop iteration each
// and combines them in chunk order (per-chunk histograms, prefix sums), so the result is the same
// for any chunk count and any OpenMP team size: the sequential order, computed in parallel.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "src/render/frame.hpp"

namespace al::render_internal {
namespace {

// Below this many items per chunk, waking another thread costs more than it saves.
constexpr std::size_t kMinPerChunk = 4096;

int ChunkCount(std::size_t items, int threads) {
  const std::size_t by_size = std::max<std::size_t>(1, items / kMinPerChunk);
  return static_cast<int>(std::clamp<std::size_t>(by_size, 1, static_cast<std::size_t>(std::max(1, threads))));
}

std::size_t ChunkBegin(std::size_t items, int chunks, int c) {
  return items * static_cast<std::size_t>(c) / static_cast<std::size_t>(chunks);
}

// Stable LSD radix sort of the keys by their high 32 bits (float bits of tz > 0, which order like
// the values). Keys arrive in scene-index order, so sorting by tz alone, stably, gives INRIA's
// (tz, index) order; this halves the passes of a full 64-bit sort. 11-bit digits keep each
// chunk's histogram (8 KiB) and scatter targets cache-friendly; a digit on which all keys agree
// is skipped.
void SortByDepth(std::vector<std::uint64_t>& keys, int threads) {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  const std::size_t n = keys.size();
  if (n < 2) return;
  const int chunks = ChunkCount(n, threads);
  std::vector<std::uint64_t> tmp(n);
  std::vector<std::uint32_t> hist(static_cast<std::size_t>(chunks) * kBuckets);
  for (int shift = 32; shift < 64; shift += kBits) {
    auto digit = [shift](std::uint64_t k) { return static_cast<std::size_t>(k >> shift) & (kBuckets - 1); };
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
    for (int c = 0; c < chunks; ++c) {
      std::uint32_t* h = hist.data() + static_cast<std::size_t>(c) * kBuckets;
      std::fill(h, h + kBuckets, 0u);
      for (std::size_t i = ChunkBegin(n, chunks, c), e = ChunkBegin(n, chunks, c + 1); i < e; ++i) ++h[digit(keys[i])];
    }
    // Exclusive offsets, bucket-major then chunk-major: chunk c's keys of bucket b follow those of
    // earlier chunks, which is what makes the sort stable.
    const std::size_t first = digit(keys[0]);
    std::size_t first_total = 0;
    for (int c = 0; c < chunks; ++c) first_total += hist[static_cast<std::size_t>(c) * kBuckets + first];
    if (first_total == n) continue;
    std::uint32_t sum = 0;
    for (std::size_t b = 0; b < kBuckets; ++b)
      for (int c = 0; c < chunks; ++c) {
        std::uint32_t& h = hist[static_cast<std::size_t>(c) * kBuckets + b];
        const std::uint32_t next = sum + h;
        h = sum;
        sum = next;
      }
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
    for (int c = 0; c < chunks; ++c) {
      std::uint32_t* h = hist.data() + static_cast<std::size_t>(c) * kBuckets;
      for (std::size_t i = ChunkBegin(n, chunks, c), e = ChunkBegin(n, chunks, c + 1); i < e; ++i)
        tmp[h[digit(keys[i])]++] = keys[i];
    }
    keys.swap(tmp);
  }
}

// Packs Gaussian i into the splat of its rank and returns the tiles it is listed in.
TileRect MakeSplat(const Projected& p, std::uint32_t i, Splat& s) {
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
  TileRect rect = {p.xmin[i], p.ymin[i], p.xmax[i], p.ymax[i]};
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
  return rect;
}

// The visible Gaussians in scene-index order: packed splats and rectangles, and their sort keys
// (tz bits << 32 | position in this list; the position grows with the scene index, so it breaks
// depth ties exactly like the index). Reading the preprocessing arrays sequentially here, and
// later moving one packed splat per rank, avoids a scattered read of every array per rank.
struct Packed {
  std::vector<std::uint64_t> keys;
  std::vector<Splat> splats;
  std::vector<TileRect> rects;
};

Packed PackVisible(const Projected& p, int threads) {
  const std::size_t n = p.status.size();
  const int chunks = ChunkCount(n, threads);
  std::vector<std::size_t> start(static_cast<std::size_t>(chunks) + 1, 0);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
  for (int c = 0; c < chunks; ++c) {
    std::size_t count = 0;
    for (std::size_t i = ChunkBegin(n, chunks, c), e = ChunkBegin(n, chunks, c + 1); i < e; ++i)
      count += p.status[i] == kVisible;
    start[c + 1] = count;
  }
  for (int c = 0; c < chunks; ++c) start[c + 1] += start[c];
  Packed packed;
  packed.keys.resize(start[chunks]);
  packed.splats.resize(start[chunks]);
  packed.rects.resize(start[chunks]);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
  for (int c = 0; c < chunks; ++c) {
    std::size_t j = start[c];
    for (std::size_t i = ChunkBegin(n, chunks, c), e = ChunkBegin(n, chunks, c + 1); i < e; ++i) {
      if (p.status[i] != kVisible) continue;
      std::uint32_t bits;
      std::memcpy(&bits, &p.tz[i], sizeof bits);
      packed.keys[j] = (std::uint64_t{bits} << 32) | static_cast<std::uint32_t>(j);
      packed.rects[j] = MakeSplat(p, static_cast<std::uint32_t>(i), packed.splats[j]);
      ++j;
    }
  }
  return packed;
}

}  // namespace

void BuildFrame(Frame& frame, int threads) {
  threads = std::max(1, threads);
  Packed packed = PackVisible(frame.proj, threads);
  std::vector<std::uint64_t>& keys = packed.keys;
  SortByDepth(keys, threads);

  const std::size_t visible = keys.size();
  frame.splats.resize(visible);
  frame.rects.resize(visible);
  const int gx = frame.view.grid_x, gy = frame.view.grid_y;
  const std::size_t tiles = static_cast<std::size_t>(gx) * gy;
  // Per chunk of ranks: splats and rectangles in depth order, per-tile entry counts.
  const int chunks = ChunkCount(visible, threads);
  std::vector<std::uint32_t> count(static_cast<std::size_t>(chunks) * tiles, 0);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
  for (int c = 0; c < chunks; ++c) {
    std::uint32_t* cnt = count.data() + static_cast<std::size_t>(c) * tiles;
    for (std::size_t r = ChunkBegin(visible, chunks, c), e = ChunkBegin(visible, chunks, c + 1); r < e; ++r) {
      const std::uint32_t j = static_cast<std::uint32_t>(keys[r]);
      frame.splats[r] = packed.splats[j];
      const TileRect rect = packed.rects[j];
      frame.rects[r] = rect;
      for (int ty = rect.y0; ty < rect.y1; ++ty)
        for (int tx = rect.x0; tx < rect.x1; ++tx) ++cnt[static_cast<std::size_t>(ty) * gx + tx];
    }
  }
  // Tile t's list is chunk 0's entries for t, then chunk 1's, ... (ranks ascending = front to
  // back); count becomes each chunk's write cursor.
  frame.tile_offsets.assign(tiles + 1, 0);
  for (std::size_t t = 0; t < tiles; ++t) {
    std::uint32_t pos = frame.tile_offsets[t];
    for (int c = 0; c < chunks; ++c) {
      std::uint32_t& cnt = count[static_cast<std::size_t>(c) * tiles + t];
      const std::uint32_t next = pos + cnt;
      cnt = pos;
      pos = next;
    }
    frame.tile_offsets[t + 1] = pos;
  }
  frame.tile_ranks.resize(frame.tile_offsets[tiles]);
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (chunks > 1)
  for (int c = 0; c < chunks; ++c) {
    std::uint32_t* cursor = count.data() + static_cast<std::size_t>(c) * tiles;
    for (std::size_t r = ChunkBegin(visible, chunks, c), e = ChunkBegin(visible, chunks, c + 1); r < e; ++r) {
      const TileRect& rect = frame.rects[r];
      for (int ty = rect.y0; ty < rect.y1; ++ty)
        for (int tx = rect.x0; tx < rect.x1; ++tx)
          frame.tile_ranks[cursor[static_cast<std::size_t>(ty) * gx + tx]++] = static_cast<std::uint32_t>(r);
    }
  }
}

}  // namespace al::render_internal
