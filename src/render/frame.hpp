// Internal state of one view's render: per-Gaussian preprocessing (RASTERIZER.md §3), the global
// (tz, index) order (§4) and the per-tile lists, shared by the fast path, the incremental "after"
// render and the slow reference renderer.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "al/io/camera.hpp"
#include "al/render/render.hpp"
#include "al/scene/scene.hpp"

namespace al::render_internal {

constexpr int kTile = 16;

// Why a Gaussian did not produce a splat.
enum Status : std::uint8_t {
  kVisible = 0,
  kExcluded = 1,     // masked out by the caller
  kNonFinite = 2,    // a non-finite parameter (counted, never rendered)
  kCulled = 3,       // near plane, det == 0, empty tile rectangle (INRIA culls)
  kDegenerate = 4,   // finite input whose projection overflowed to Inf/NaN (never rendered)
};

// Per-Gaussian preprocessing results, structure of arrays over scene indices.
struct Projected {
  std::vector<float> u, v, conic_a, conic_b, conic_c, opacity, red, green, blue, tz;
  std::vector<std::int32_t> radius;
  std::vector<std::int32_t> xmin, ymin, xmax, ymax;  // tile rectangle, max exclusive
  std::vector<std::uint8_t> status;
  std::size_t visible = 0, nonfinite = 0, degenerate = 0;
};

// The float32 camera quantities the kernel uses (computed the INRIA way).
struct ViewParams {
  int width = 0, height = 0, grid_x = 0, grid_y = 0;
  float tan_fovx = 0, tan_fovy = 0, focal_x = 0, focal_y = 0;
  float view[12] = {};       // W2C rows 0..2 (R | t), float32
  float proj_x[4] = {}, proj_y[4] = {}, proj_w[4] = {};  // rows of P*W2C used for the 2D mean
  float campos[3] = {};
};

ViewParams MakeViewParams(const Camera& camera);

// Validates the scene/camera/mask shapes; throws al::Error on bad input.
void CheckInputs(const Scene& scene, const Camera& camera, const std::vector<bool>& exclude);

void Preprocess(const Scene& scene, const ViewParams& view, const RenderOptions& options,
                const std::vector<bool>& exclude, Projected& out);

// One visible Gaussian in depth order, packed for the compositing loop.
struct Splat {
  float u, v, a, b, c, opacity, red, green, blue, tz;
  float power_floor;  // power below this certainly gives alpha < 1/255 (skips the exp)
  // Half-extents (px) of the ellipse power >= power_floor, with a safety margin: pixels outside
  // [u - ext_x, u + ext_x] x [v - ext_y, v + ext_y] can never blend this Gaussian.
  float ext_x, ext_y;
  std::int32_t id;    // scene index
};

// Tiles a splat is listed in: its INRIA tile rectangle intersected with the tiles its effective
// ellipse can reach (dropping only tiles where it provably changes no pixel, RASTERIZER.md §9).
struct TileRect {
  std::int32_t x0, y0, x1, y1;  // max exclusive
};

struct Frame {
  ViewParams view;
  Projected proj;
  std::vector<Splat> splats;                 // visible Gaussians sorted by (tz, index)
  std::vector<TileRect> rects;               // per rank
  std::vector<std::uint32_t> tile_offsets;   // grid_x*grid_y + 1
  std::vector<std::uint32_t> tile_ranks;     // ranks into splats, front to back per tile
};

// Sort + binning (§4), src/render/binning.cpp. The result does not depend on threads.
void BuildFrame(Frame& frame, int threads);

// Per-Gaussian features for the compositing loop: scene-indexed rows of `dim` floats (null = none).
struct FeatureInput {
  const float* rows = nullptr;
  int dim = 0;
};

// Composites one tile into out (RASTERIZER.md §5, §7), src/render/composite.cpp. skip (by rank)
// may be null. subset (by rank) may be null; if set, out.subset_weight (H*W, allocated by the
// caller) receives the per-pixel sum of alpha*T over the ranks where subset[rank] != 0. With
// features.rows set, out.feature (H*W*dim, allocated by the caller) receives sum(alpha*T*f) /
// max(alpha, 1e-10). Returns the number of (Gaussian, pixel) power evaluations.
std::uint64_t CompositeTile(const Frame& frame, int tile, const std::uint8_t* skip, const std::uint8_t* subset,
                            const FeatureInput& features, const Eigen::Vector3f& background, bool front_id,
                            RenderOutput& out);

// The features of options as a FeatureInput; checks the shape (al::Error).
FeatureInput FeaturesOf(const RenderOptions& options, std::size_t num_gaussians);

// Allocates the image buffers of out.
void AllocateOutput(int width, int height, std::size_t num_gaussians, bool front_id, RenderOutput& out);

int ThreadCount(const RenderOptions& options);

}  // namespace al::render_internal
