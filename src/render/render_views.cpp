// RenderViewsToFolder (al/render/render_views.hpp): `al-refine render` without the flag parsing.
#include "al/render/render_views.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "al/core/memory_limit.hpp"
#include "al/core/output_set.hpp"
#include "al/core/progress.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/io/cameras.hpp"
#include "al/io/image.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

std::uint8_t To8(float v) {
  const float c = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(std::lround(c * 255.0f));
}

// A perceptual blue-green-yellow ramp (viridis-like stops) for the depth preview: near = yellow.
void Ramp(float t, std::uint8_t* rgb) {
  static const float stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  const int k = std::min(3, static_cast<int>(t));
  const float f = t - k;
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<std::uint8_t>(std::lround(stops[k][c] * (1 - f) + stops[k + 1][c] * f));
}

// Resizes keeping the field of view (RASTERIZER.md §10.2): fx' = fx W'/W, fy' = fy H'/H.
void Resize(Camera& cam, int width, int height) {
  if (width <= 0 && height <= 0) return;
  const int w = width > 0 ? width : std::max(1, int(std::lround(double(cam.width) * height / cam.height)));
  const int h = height > 0 ? height : std::max(1, int(std::lround(double(cam.height) * width / cam.width)));
  cam.fx *= double(w) / cam.width;
  cam.cx *= double(w) / cam.width;
  cam.fy *= double(h) / cam.height;
  cam.cy *= double(h) / cam.height;
  cam.width = w;
  cam.height = h;
}

void WriteDepthPngs(const std::string& stem, const RenderOutput& out, double* scale_out) {
  const std::size_t pixels = static_cast<std::size_t>(out.width) * out.height;
  float dmin = std::numeric_limits<float>::infinity(), dmax = 0;
  for (std::size_t i = 0; i < pixels; ++i)
    if (out.alpha[i] > 0 && std::isfinite(out.depth[i]) && out.depth[i] > 0) {
      dmin = std::min(dmin, out.depth[i]);
      dmax = std::max(dmax, out.depth[i]);
    }
  const double scale = dmax > 0 ? double(dmax) / 65535.0 : 1.0;
  Image16 depth{out.width, out.height, std::vector<std::uint16_t>(pixels, 0)};
  Image8 vis{out.width, out.height, 3, std::vector<std::uint8_t>(pixels * 3, 0)};
  // Preview: inverse depth, normalised over the covered pixels (near = bright).
  const float inv_near = dmax > 0 ? 1.0f / dmin : 1.0f, inv_far = dmax > 0 ? 1.0f / dmax : 0.0f;
  for (std::size_t i = 0; i < pixels; ++i) {
    const float d = out.depth[i];
    if (!(out.alpha[i] > 0 && std::isfinite(d) && d > 0)) continue;
    depth.pixels[i] = static_cast<std::uint16_t>(std::clamp<long>(std::lround(d / scale), 1, 65535));
    const float t = inv_near > inv_far ? (1.0f / d - inv_far) / (inv_near - inv_far) : 1.0f;
    Ramp(t, &vis.pixels[i * 3]);
  }
  WritePng16(stem + "_depth.png", depth);
  WritePng8(stem + "_depth_vis.png", vis);
  *scale_out = scale;
}

// Returns the depth PNG scale (depth = value * scale).
double WriteImages(const std::string& stem, const RenderOutput& out) {
  const std::size_t pixels = static_cast<std::size_t>(out.width) * out.height;
  Image8 rgb{out.width, out.height, 3, std::vector<std::uint8_t>(pixels * 3)};
  for (std::size_t i = 0; i < pixels * 3; ++i) rgb.pixels[i] = To8(out.rgb[i]);
  WritePng8(stem + "_rgb.png", rgb);
  Image8 alpha{out.width, out.height, 1, std::vector<std::uint8_t>(pixels)};
  for (std::size_t i = 0; i < pixels; ++i) alpha.pixels[i] = To8(out.alpha[i]);
  WritePng8(stem + "_alpha.png", alpha);
  double scale = 1.0;
  WriteDepthPngs(stem, out, &scale);
  return scale;
}

void WriteArrays(const std::string& stem, const RenderOutput& out, const std::vector<bool>& removed) {
  const std::int64_t h = out.height, w = out.width;
  WriteNpy(stem + "_rgb.npy", out.rgb, {h, w, 3});
  WriteNpy(stem + "_depth.npy", out.depth, {h, w});
  WriteNpy(stem + "_alpha.npy", out.alpha, {h, w});
  std::vector<std::int32_t> radii;
  radii.reserve(out.radii.size());
  for (std::size_t i = 0; i < out.radii.size(); ++i)
    if (removed.empty() || !removed[i]) radii.push_back(out.radii[i]);
  WriteNpy(stem + "_radii.npy", radii, {static_cast<std::int64_t>(radii.size())});
}

nlohmann::json ViewRecord(const Camera& cam, const RenderOutput& out, double depth_scale, double seconds) {
  double alpha_sum = 0;
  for (float a : out.alpha) alpha_sum += a;
  return {{"name", cam.name},
          {"width", cam.width},
          {"height", cam.height},
          {"visible_gaussians", out.visible_gaussians},
          {"excluded_nonfinite", out.excluded_nonfinite},
          {"excluded_degenerate", out.excluded_degenerate},
          {"tiles_total", out.tiles_total},
          {"tile_entries", out.tile_entries},
          {"alpha_mean", alpha_sum / std::max<std::size_t>(1, out.alpha.size())},
          {"depth_png_scale", depth_scale},
          {"timings_s",
           {{"preprocess", out.seconds_preprocess},
            {"binning", out.seconds_binning},
            {"composite", out.seconds_composite},
            {"total", seconds}}}};
}

// The views to render, resized; refuses a view whose render would exceed the memory limit.
std::vector<Camera> PlanViews(const RenderViewsOptions& o, std::size_t gaussians, nlohmann::json& warnings) {
  CameraLoadResult loaded = ReadCameras(o.cameras);
  for (const auto& w : loaded.warnings) warnings.push_back(w);
  std::vector<Camera> views = SelectViews(loaded.cameras, o.views);
  for (Camera& cam : views) {
    Resize(cam, o.width, o.height);
    CheckMemoryEstimate("render of view '" + cam.name + "' at " + std::to_string(cam.width) + "x" +
                            std::to_string(cam.height),
                        EstimateRenderBytes(gaussians, cam.width, cam.height));
  }
  return views;
}

}  // namespace

double EstimateRenderBytes(std::size_t gaussians, int width, int height, int feature_channels) {
  const double pixels = double(width) * double(height);
  // Per pixel: float rgb/alpha/depth/invdepth + front id (28 B), 8/16-bit images and their PNG
  // encodings (~12 B), a float per composited feature channel; per Gaussian: projection, sorted
  // splats, rectangles, radii (~150 B).
  return pixels * (40.0 + 4.0 * std::max(0, feature_channels)) + double(gaussians) * 150.0;
}

RenderViewsResult RenderViewsToFolder(const RenderViewsOptions& o) {
  o.Check();
  OutputSetOptions so;
  so.command = "render";
  so.inputs = {o.scene, o.cameras, o.removed};
  so.planned = {"report.json"};
  OutputSet set(o.out_dir, so);
  nlohmann::json report = NewReport("render");
  report["params"] = o.params;
  nlohmann::json& warnings = report["warnings"];
  Timer timer;
  const Scene scene = ReadScene(o.scene);
  report["timings_s"]["load_scene"] = timer.Seconds();
  AddInputFile(report, "scene", o.scene);
  for (const auto& w : MissingRenderColumns(scene)) warnings.push_back(w);
  timer.Reset();
  const std::vector<Camera> views = PlanViews(o, scene.size(), warnings);
  report["timings_s"]["load_cameras"] = timer.Seconds();
  if (fs::is_regular_file(o.cameras)) AddInputFile(report, "cameras", o.cameras);

  RenderViewsResult result;
  std::vector<bool> removed;
  timer.Reset();
  if (!o.removed.empty()) {
    RemovalSet r = LoadRemovalSet(o.removed, scene, {o.removed_is});
    removed = std::move(r.removed);
    result.num_removed = r.num_removed;
    report["removal"] = r.stats;
    for (const auto& w : r.warnings) warnings.push_back(w);
    if (fs::is_regular_file(o.removed)) AddInputFile(report, "removed", o.removed);
  }
  report["timings_s"]["load_removed"] = timer.Seconds();

  double render_s = 0, write_s = 0;
  nlohmann::json per_view = nlohmann::json::array();
  Progress progress("render", views.size(), o.progress);
  for (std::size_t vi = 0; vi < views.size(); ++vi) {
    timer.Reset();
    const RenderOutput out = Render(scene, views[vi], o.render, removed);
    const double view_s = timer.Seconds();
    render_s += view_s;
    timer.Reset();
    const std::string stem = (set.dir() / SafeFileName(views[vi].name)).string();
    const double depth_scale = WriteImages(stem, out);
    if (o.npy) WriteArrays(stem, out, removed);
    write_s += timer.Seconds();
    per_view.push_back(ViewRecord(views[vi], out, depth_scale, view_s));
    progress.Step(vi + 1);
  }
  progress.Finish();

  result.views = views.size();
  report["counts"] = {{"num_gaussians", scene.size()}, {"num_removed", result.num_removed},
                      {"num_rendered_gaussians", scene.size() - result.num_removed}, {"views", views.size()}};
  report["views"] = per_view;
  report["depth_png"] =
      "16-bit grey: depth (view-space z, expected, normalised by alpha) = value * depth_png_scale of the view; "
      "0 = no coverage";
  report["timings_s"]["render"] = render_s;
  report["timings_s"]["write"] = write_s;
  result.report = set.Commit(std::move(report));
  return result;
}

}  // namespace al
