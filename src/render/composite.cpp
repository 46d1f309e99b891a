// Per-tile compositing (RASTERIZER.md §5, §7).
//
// The arithmetic per (Gaussian, pixel) is exactly the reference's, in the same order (front to
// back, same float32 expressions); only memory layout and loop structure differ:
//  * the tile's list is gathered in batches into a local structure of arrays, so the scattered
//    loads of the depth-sorted splats overlap instead of stalling one by one;
//  * for each Gaussian, `power` is computed for 4 pixels of a row at once (SSE; x86-64 is the
//    project's baseline ISA). The terms that depend only on the column, (A·dx)·dx and B·dx, are
//    computed once per Gaussian and reused for every row: the same products, so the same bits;
//  * a row bit mask of pixels still blending, AND-ed with the SIMD test `power <= 0 && !(power <
//    floor)`, leaves only the pixels that can blend; exp (scalar libm expf, as before) runs for
//    those alone, then alpha, the stop test and the accumulation run 4 pixels at a time with
//    masks (lanes that fail a test keep their values).
// Pixels never depend on each other, so the evaluation order across pixels is free; within a
// pixel the Gaussians are still visited front to back.
// The optional subset weight (RenderOptions::weight_subset) adds one more masked accumulation of
// the blend weight alpha*T -- the same product that feeds the depth sum -- for the subset's
// splats. The optional feature field (RenderOptions::features) adds, per blending pixel, the
// Gaussian's feature row times the same alpha*T (4 channels at a time; the reference's scalar
// `sum += weight * f`, so the same bits). Gather and Blend are templated on both, so a render
// without them runs the same code as before and every other output keeps its bits either way
// (the new accumulators are write-only).
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "al/core/error.hpp"
#include "src/render/frame.hpp"

namespace al::render_internal {
namespace {

constexpr int kPix = kTile * kTile;
constexpr int kBatch = 64;  // splats staged per gather; small enough to stay in L1
constexpr std::uint32_t kPrefetch = 16;  // list entries ahead (~ memory latency / gather step)
static_assert(kTile == 16, "row masks and SSE blocks assume 16-pixel tile rows");

// Splats of one batch that reach at least one pixel of the tile, with their pixel window.
struct Batch {
  alignas(16) float u[kBatch], v[kBatch], a[kBatch], b[kBatch], c[kBatch], opacity[kBatch];
  float red[kBatch], green[kBatch], blue[kBatch], tz[kBatch], floor[kBatch];
  std::int32_t id[kBatch];
  std::uint8_t in_subset[kBatch];  // only filled when the subset weight is computed
  const float* feature[kBatch];    // feature row (only filled when features are composited)
  std::int8_t lx0[kBatch], lx1[kBatch], ly0[kBatch], ly1[kBatch];  // tile-local, inclusive
};

// Accumulators of one tile, pixel (lx, ly) at ly * kTile + lx.
struct TileAccum {
  alignas(16) float T[kPix], cr[kPix], cg[kPix], cb[kPix], dsum[kPix], inv[kPix];
  alignas(16) float sw[kPix];  // subset weight (only used when computed)
  std::int32_t fid[kPix];
  std::uint32_t active[kTile];  // bit lx of row ly: the pixel is in the image and still blending
  alignas(16) float colx[kTile], rowy[kTile];  // pixel centres (integers, as float)
};

// Feature sums of one tile: pixel p's channels at sum + p * stride (stride = dim rounded up to 4,
// so every pixel's channels start 16-byte aligned). A per-thread buffer, reused across tiles.
struct FeatureAccum {
  float* sum = nullptr;
  int dim = 0, stride = 0;
};

// Gathers splats from the tile list starting at k until the batch is full or the list ends;
// returns the new list position.
template <bool kSubset, bool kFeature>
std::uint32_t Gather(const Frame& frame, std::uint32_t k, std::uint32_t end, const std::uint8_t* skip,
                     const std::uint8_t* subset, const FeatureInput& features, int x0, int y0, int w, int h,
                     Batch& batch, int& count) {
  count = 0;
  for (; k < end && count < kBatch; ++k) {
    // The splats of a tile are scattered through the depth-sorted array; the window test below
    // branches on their data, so the hardware does not run far ahead on its own.
    if (k + kPrefetch < end) {
      const char* ahead = reinterpret_cast<const char*>(&frame.splats[frame.tile_ranks[k + kPrefetch]]);
      __builtin_prefetch(ahead);
      __builtin_prefetch(ahead + sizeof(Splat) - 1);  // a splat may straddle two cache lines
    }
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
    if (lx0 > lx1 || ly0 > ly1) continue;  // reaches no pixel of this tile
    const int i = count++;
    batch.u[i] = s.u;
    batch.v[i] = s.v;
    batch.a[i] = s.a;
    batch.b[i] = s.b;
    batch.c[i] = s.c;
    batch.opacity[i] = s.opacity;
    batch.red[i] = s.red;
    batch.green[i] = s.green;
    batch.blue[i] = s.blue;
    batch.tz[i] = s.tz;
    batch.floor[i] = s.power_floor;
    batch.id[i] = s.id;
    if constexpr (kSubset) batch.in_subset[i] = subset[rank];
    if constexpr (kFeature) {
      // Read when the batch is blended: start the (scattered) row on its way now.
      batch.feature[i] = features.rows + static_cast<std::size_t>(s.id) * static_cast<std::size_t>(features.dim);
      __builtin_prefetch(batch.feature[i]);
    }
    batch.lx0[i] = static_cast<std::int8_t>(lx0);
    batch.lx1[i] = static_cast<std::int8_t>(lx1);
    batch.ly0[i] = static_cast<std::int8_t>(ly0);
    batch.ly1[i] = static_cast<std::int8_t>(ly1);
  }
  return k;
}

// Lane masks for the 16 subsets of a 4-pixel block (bit l set -> lane l all ones).
struct LaneMasks {
  alignas(16) std::uint32_t m[16][4];
  constexpr LaneMasks() : m() {
    for (int bits = 0; bits < 16; ++bits)
      for (int l = 0; l < 4; ++l) m[bits][l] = (bits >> l) & 1 ? 0xffffffffu : 0u;
  }
};
constexpr LaneMasks kLaneMasks;

inline __m128 Select(__m128 mask, __m128 yes, __m128 no) {
  return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
}

// Adds w * f to one pixel's channel sums, 4 channels at a time (scalar tail): per channel the
// reference's `sum += weight * f`.
inline void AddWeightedFeature(float* sum, const float* f, float w, int dim) {
  const __m128 wv = _mm_set1_ps(w);
  int ch = 0;
  for (; ch + 4 <= dim; ch += 4)
    _mm_store_ps(sum + ch, _mm_add_ps(_mm_load_ps(sum + ch), _mm_mul_ps(wv, _mm_loadu_ps(f + ch))));
  for (; ch < dim; ++ch) sum[ch] += w * f[ch];
}

// The blend of splat g into the 4 pixels at p (lanes in `blend`): colour, depth sums, subset
// weight, feature sums, front id and transmittance, each the reference's float operations.
// The splat's values broadcast to 4 lanes (once per splat, not per block).
struct SplatLanes {
  __m128 red, green, blue, tz;
  __m128i id;
};

template <bool kSubset, bool kFeature>
inline void Accumulate(const Batch& batch, int g, const SplatLanes& s, int p, __m128 blend, __m128 alpha, __m128 t,
                       __m128 test_t, TileAccum& acc, const FeatureAccum& fa) {
  const __m128 red = s.red, green = s.green, blue = s.blue, tz = s.tz;
  _mm_store_ps(acc.cr + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.cr + p), _mm_mul_ps(_mm_mul_ps(red, alpha), t)),
                                  _mm_load_ps(acc.cr + p)));
  _mm_store_ps(acc.cg + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.cg + p), _mm_mul_ps(_mm_mul_ps(green, alpha), t)),
                                  _mm_load_ps(acc.cg + p)));
  _mm_store_ps(acc.cb + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.cb + p), _mm_mul_ps(_mm_mul_ps(blue, alpha), t)),
                                  _mm_load_ps(acc.cb + p)));
  const __m128 weight = _mm_mul_ps(alpha, t);
  _mm_store_ps(acc.dsum + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.dsum + p), _mm_mul_ps(weight, tz)),
                                    _mm_load_ps(acc.dsum + p)));
  // Subset share: sw += alpha*T for blending lanes, the reference's `acc += alpha * T`.
  if constexpr (kSubset)
    if (batch.in_subset[g])
      _mm_store_ps(acc.sw + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.sw + p), weight), _mm_load_ps(acc.sw + p)));
  if constexpr (kFeature) {
    alignas(16) float w[4];
    _mm_store_ps(w, weight);
    for (std::uint32_t lanes = static_cast<std::uint32_t>(_mm_movemask_ps(blend)); lanes != 0; lanes &= lanes - 1) {
      const int l = std::countr_zero(lanes);
      AddWeightedFeature(fa.sum + static_cast<std::size_t>(p + l) * fa.stride, batch.feature[g], w[l], fa.dim);
    }
  }
  _mm_store_ps(acc.inv + p, Select(blend, _mm_add_ps(_mm_load_ps(acc.inv + p), _mm_div_ps(weight, tz)),
                                   _mm_load_ps(acc.inv + p)));
  __m128i* fid = reinterpret_cast<__m128i*>(acc.fid + p);
  const __m128i f = _mm_load_si128(fid);
  const __m128i set = _mm_and_si128(_mm_castps_si128(blend), _mm_cmplt_epi32(f, _mm_setzero_si128()));
  _mm_store_si128(fid, _mm_or_si128(_mm_and_si128(set, s.id), _mm_andnot_si128(set, f)));
  _mm_store_ps(acc.T + p, Select(blend, test_t, t));
}

// Blends splat g of the batch into the pixels of its window (RASTERIZER.md §5), 4 pixels of a
// row at a time. Per pixel this is the reference's sequence of float32 operations: SSE
// add/mul/div/min are the same IEEE operations as their scalar forms (no FMA on the baseline ISA,
// and contraction is off in ISO C++ mode); only exp stays scalar (libm expf, as before), called
// for the pixels that pass the power tests alone.
template <bool kSubset, bool kFeature>
void Blend(const Batch& batch, int g, TileAccum& acc, const FeatureAccum& fa, int& remaining,
           std::uint64_t& evaluations) {
  const int lx0 = batch.lx0[g], lx1 = batch.lx1[g];
  const std::uint32_t window = ((2u << lx1) - 1u) & ~((1u << lx0) - 1u);
  const int blk0 = lx0 >> 2, blk1 = lx1 >> 2;
  const float v = batch.v[g], c = batch.c[g];
  // Column terms of power = -0.5·(A·dx·dx + C·dy·dy) − B·dx·dy, dx = u − px.
  alignas(16) float adx[kTile], bdx[kTile];
  {
    const __m128 u = _mm_set1_ps(batch.u[g]), a = _mm_set1_ps(batch.a[g]), b = _mm_set1_ps(batch.b[g]);
    for (int k = blk0; k <= blk1; ++k) {
      const __m128 dx = _mm_sub_ps(u, _mm_load_ps(acc.colx + 4 * k));
      _mm_store_ps(adx + 4 * k, _mm_mul_ps(_mm_mul_ps(a, dx), dx));
      _mm_store_ps(bdx + 4 * k, _mm_mul_ps(b, dx));
    }
  }
  const __m128 minus_half = _mm_set1_ps(-0.5f), zero = _mm_setzero_ps(), floor = _mm_set1_ps(batch.floor[g]);
  const __m128 max_alpha = _mm_set1_ps(0.99f), min_alpha = _mm_set1_ps(1.0f / 255.0f);
  const __m128 one = _mm_set1_ps(1.0f), min_t = _mm_set1_ps(0.0001f), opacity = _mm_set1_ps(batch.opacity[g]);
  const SplatLanes lanes_of_g = {_mm_set1_ps(batch.red[g]), _mm_set1_ps(batch.green[g]), _mm_set1_ps(batch.blue[g]),
                                 _mm_set1_ps(batch.tz[g]), _mm_set1_epi32(batch.id[g])};
  for (int ly = batch.ly0[g], ly1 = batch.ly1[g]; ly <= ly1; ++ly) {
    const std::uint32_t bits = acc.active[ly] & window;
    if (bits == 0) continue;
    evaluations += static_cast<std::uint64_t>(std::popcount(bits));
    const float dy = v - acc.rowy[ly];
    const __m128 cdy = _mm_set1_ps(c * dy * dy), vdy = _mm_set1_ps(dy);
    for (int k = blk0; k <= blk1; ++k) {
      const std::uint32_t live = (bits >> (4 * k)) & 0xfu;
      if (live == 0) continue;
      const __m128 power = _mm_sub_ps(_mm_mul_ps(minus_half, _mm_add_ps(_mm_load_ps(adx + 4 * k), cdy)),
                                      _mm_mul_ps(_mm_load_ps(bdx + 4 * k), vdy));
      // Evaluated only if power <= 0 and not power < floor (NaN fails the first test, as in §5).
      const __m128 test = _mm_and_ps(_mm_cmple_ps(power, zero), _mm_cmpnlt_ps(power, floor));
      const std::uint32_t lanes = live & static_cast<std::uint32_t>(_mm_movemask_ps(test));
      if (lanes == 0) continue;
      alignas(16) float pw[4];
      _mm_store_ps(pw, power);
      // Scalar results are combined in registers: storing them one by one and reloading them as a
      // vector would defeat store forwarding and stall on every block.
      const float e0 = lanes & 1u ? std::exp(pw[0]) : 0.0f, e1 = lanes & 2u ? std::exp(pw[1]) : 0.0f;
      const float e2 = lanes & 4u ? std::exp(pw[2]) : 0.0f, e3 = lanes & 8u ? std::exp(pw[3]) : 0.0f;
      // alpha = min(0.99, o·exp(power)): minps(x, 0.99) is x < 0.99 ? x : 0.99, like std::min.
      const __m128 alpha = _mm_min_ps(_mm_mul_ps(opacity, _mm_setr_ps(e0, e1, e2, e3)), max_alpha);
      const __m128 eval = _mm_and_ps(_mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(kLaneMasks.m[lanes]))),
                                     _mm_cmpnlt_ps(alpha, min_alpha));
      const int p = ly * kTile + 4 * k;
      const __m128 t = _mm_load_ps(acc.T + p);
      const __m128 test_t = _mm_mul_ps(t, _mm_sub_ps(one, alpha));
      // test_t < 1e-4 stops the pixel before this Gaussian; otherwise it blends.
      const __m128 stop = _mm_and_ps(eval, _mm_cmplt_ps(test_t, min_t));
      const __m128 blend = _mm_andnot_ps(stop, eval);
      const std::uint32_t stopped = static_cast<std::uint32_t>(_mm_movemask_ps(stop));
      if (stopped != 0) {
        acc.active[ly] &= ~(stopped << (4 * k));
        remaining -= std::popcount(stopped);
      }
      if (_mm_movemask_ps(blend) == 0) continue;
      Accumulate<kSubset, kFeature>(batch, g, lanes_of_g, p, blend, alpha, t, test_t, acc, fa);
    }
  }
}

}  // namespace

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
  out.subset_weight.clear();  // the caller allocates it when a subset is given
  out.feature.clear();        // likewise the feature image
  out.feature_dim = 0;
}

namespace {

// Composites the tile's list with one instantiation of Gather/Blend (no per-splat mode tests).
template <bool kSubset, bool kFeature>
std::uint64_t CompositeList(const Frame& frame, int tile, const std::uint8_t* skip, const std::uint8_t* subset,
                            const FeatureInput& features, int x0, int y0, int w, int h, TileAccum& acc,
                            const FeatureAccum& fa) {
  int remaining = w * h;
  Batch batch;
  std::uint64_t evaluations = 0;
  std::uint32_t k = frame.tile_offsets[tile];
  const std::uint32_t end = frame.tile_offsets[tile + 1];
  while (k < end && remaining > 0) {
    int count = 0;
    k = Gather<kSubset, kFeature>(frame, k, end, skip, subset, features, x0, y0, w, h, batch, count);
    for (int g = 0; g < count && remaining > 0; ++g)
      Blend<kSubset, kFeature>(batch, g, acc, fa, remaining, evaluations);
  }
  return evaluations;
}

// The tile's feature sums, zeroed: a per-thread buffer that grows to the largest dim seen.
FeatureAccum TileFeatureAccum(int dim) {
  thread_local std::vector<float> buffer;
  FeatureAccum fa;
  fa.dim = dim;
  fa.stride = (dim + 3) & ~3;
  const std::size_t size = static_cast<std::size_t>(kPix) * static_cast<std::size_t>(fa.stride);
  if (buffer.size() < size) buffer.resize(size);
  std::fill(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(size), 0.0f);
  fa.sum = buffer.data();  // malloc alignment (16 on x86-64) and a stride of 4 floats: aligned rows
  return fa;
}

}  // namespace

FeatureInput FeaturesOf(const RenderOptions& options, std::size_t num_gaussians) {
  if (options.features == nullptr) return {};
  const RowMatXf& f = *options.features;
  if (f.rows() != static_cast<Eigen::Index>(num_gaussians))
    throw Error("features have " + std::to_string(f.rows()) + " rows, scene has " + std::to_string(num_gaussians) +
                " Gaussians");
  if (f.cols() < 1 || f.cols() > kMaxFeatureChannels)
    throw Error("features have " + std::to_string(f.cols()) + " channels; a render composites 1.." +
                std::to_string(kMaxFeatureChannels) + " (project wider features first, al/render/feature_field.hpp)");
  return {f.data(), static_cast<int>(f.cols())};
}

std::uint64_t CompositeTile(const Frame& frame, int tile, const std::uint8_t* skip, const std::uint8_t* subset,
                            const FeatureInput& features, const Eigen::Vector3f& background, bool front_id,
                            RenderOutput& out) {
  const int W = frame.view.width, H = frame.view.height;
  const int x0 = (tile % frame.view.grid_x) * kTile, y0 = (tile / frame.view.grid_x) * kTile;
  const int w = std::min(kTile, W - x0), h = std::min(kTile, H - y0);
  TileAccum acc;
  std::fill(std::begin(acc.T), std::end(acc.T), 1.0f);
  for (float* f : {acc.cr, acc.cg, acc.cb, acc.dsum, acc.inv}) std::fill(f, f + kPix, 0.0f);
  if (subset != nullptr) std::fill(std::begin(acc.sw), std::end(acc.sw), 0.0f);
  std::fill(std::begin(acc.fid), std::end(acc.fid), -1);
  for (int i = 0; i < kTile; ++i) {
    // Pixels outside the image (partial edge tiles) are never active, hence never evaluated.
    acc.active[i] = i < h ? (1u << w) - 1u : 0u;
    acc.colx[i] = static_cast<float>(x0 + i);
    acc.rowy[i] = static_cast<float>(y0 + i);
  }
  const bool with_features = features.rows != nullptr;
  const FeatureAccum fa = with_features ? TileFeatureAccum(features.dim) : FeatureAccum{};
  std::uint64_t evaluations = 0;
  if (subset != nullptr)
    evaluations = with_features ? CompositeList<true, true>(frame, tile, skip, subset, features, x0, y0, w, h, acc, fa)
                                : CompositeList<true, false>(frame, tile, skip, subset, features, x0, y0, w, h, acc, fa);
  else
    evaluations = with_features ? CompositeList<false, true>(frame, tile, skip, subset, features, x0, y0, w, h, acc, fa)
                                : CompositeList<false, false>(frame, tile, skip, subset, features, x0, y0, w, h, acc, fa);
  for (int ly = 0; ly < h; ++ly)
    for (int lx = 0; lx < w; ++lx) {
      const int p = ly * kTile + lx;
      const std::size_t idx = static_cast<std::size_t>(y0 + ly) * W + (x0 + lx);
      out.rgb[idx * 3 + 0] = acc.cr[p] + acc.T[p] * background[0];
      out.rgb[idx * 3 + 1] = acc.cg[p] + acc.T[p] * background[1];
      out.rgb[idx * 3 + 2] = acc.cb[p] + acc.T[p] * background[2];
      const float alpha = 1.0f - acc.T[p];
      out.alpha[idx] = alpha;
      out.depth[idx] = acc.dsum[p] / std::max(alpha, 1e-10f);
      out.invdepth[idx] = acc.inv[p];
      if (front_id) out.front_id[idx] = acc.fid[p];
      if (subset != nullptr) out.subset_weight[idx] = acc.sw[p];
      if (with_features) {
        // Per-pixel normalisation, as for the expected depth.
        const float norm = std::max(alpha, 1e-10f);
        const float* sum = fa.sum + static_cast<std::size_t>(p) * fa.stride;
        float* dst = out.feature.data() + idx * static_cast<std::size_t>(fa.dim);
        for (int ch = 0; ch < fa.dim; ++ch) dst[ch] = sum[ch] / norm;
      }
    }
  return evaluations;
}

}  // namespace al::render_internal
