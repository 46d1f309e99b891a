// `al-refine render --scene S --cameras C [--removed R] [--views ...] [--npy] --out DIR`:
// INRIA-exact CPU renders (RGB, depth, alpha) per view, with report.json.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/progress.hpp"
#include "al/core/report.hpp"
#include "al/core/timer.hpp"
#include "al/io/cameras.hpp"
#include "al/io/image.hpp"
#include "al/io/masks.hpp"
#include "al/io/npy.hpp"
#include "al/io/ply.hpp"
#include "al/render/render.hpp"
#include "src/cli/background_flag.hpp"
#include "src/cli/command.hpp"

namespace al::cli {
namespace {

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

std::string SafeName(std::string name) {
  for (char& ch : name)
    if (ch == '/' || ch == '\\' || ch == ':') ch = '_';
  return name.empty() ? "view" : name;
}

}  // namespace

class RenderCommand : public Command {
 public:
  std::string Name() const override { return "render"; }
  std::string Description() const override {
    return "Render views of a scene (optionally without a removed set) on the CPU, INRIA-exact: RGB, depth and "
           "alpha PNGs, optional float .npy";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", scene_, "Scene file (.ply or .splat)")->required();
    app.add_option("--cameras", cameras_, "Cameras: INRIA cameras.json, COLMAP folder, or JSON list")->required();
    app.add_option("--removed", removed_, "Removed set (.npy mask/indices, .txt indices, or subset .ply)");
    app.add_option("--removed-is", removed_is_, "Whether --removed lists removed or remaining Gaussians")
        ->check(CLI::IsMember({"removed", "remaining"}))
        ->default_val("removed");
    app.add_option("--views", views_, "Comma-separated view names, or all")->default_val("all");
    app.add_option("--bg", bg_, "Background: 0 (black), 1 (white) or r,g,b")->default_val("0");
    app.add_flag("--npy", npy_, "Also write float32 rgb/depth/alpha and int32 radii .npy files");
    app.add_option("--width", width_, "Render width (keeps the field of view)")->check(CLI::Range(1, 65536));
    app.add_option("--height", height_, "Render height (keeps the field of view)")->check(CLI::Range(1, 65536));
    app.add_option("--sh-degree", sh_degree_, "Maximum SH degree evaluated")->check(CLI::Range(0, 3))->default_val(3);
    app.add_option("--threads", threads_, "OpenMP threads (0 = default)")->check(CLI::NonNegativeNumber);
    app.add_option("--out", out_, "Output directory")->required();
  }

  int Run() override {
    nlohmann::json report = NewReport("render");
    report["params"] = {{"scene", scene_},   {"cameras", cameras_}, {"removed", removed_},
                        {"removed_is", removed_is_}, {"views", views_}, {"bg", bg_},
                        {"npy", npy_},       {"width", width_},     {"height", height_},
                        {"sh_degree", sh_degree_}, {"threads", threads_}};
    RenderOptions options;
    options.background = ParseBackground(bg_);
    options.max_sh_degree = sh_degree_;
    options.num_threads = threads_;
    nlohmann::json warnings = nlohmann::json::array();

    Timer timer;
    const Scene scene = ReadScene(scene_);
    const double load_scene_s = timer.Seconds();
    AddInputFile(report, "scene", scene_);
    timer.Reset();
    CameraLoadResult loaded = ReadCameras(cameras_);
    for (const auto& w : loaded.warnings) warnings.push_back(w);
    std::vector<Camera> views = SelectViews(loaded.cameras, views_);
    const double load_cameras_s = timer.Seconds();
    if (std::filesystem::is_regular_file(cameras_)) AddInputFile(report, "cameras", cameras_);

    std::vector<bool> removed;
    std::size_t num_removed = 0;
    timer.Reset();
    if (!removed_.empty()) {
      RemovalLoadOptions ro;
      ro.removed_is = removed_is_ == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
      RemovalSet set = LoadRemovalSet(removed_, scene, ro);
      removed = std::move(set.removed);
      num_removed = set.num_removed;
      report["removal"] = set.stats;
      for (const auto& w : set.warnings) warnings.push_back(w);
      if (std::filesystem::is_regular_file(removed_)) AddInputFile(report, "removed", removed_);
    }
    const double load_removed_s = timer.Seconds();

    EnsureDirectory(out_);
    const std::filesystem::path dir(out_);
    double render_s = 0, write_s = 0;
    nlohmann::json per_view = nlohmann::json::array();
    Progress progress("render", views.size());
    for (std::size_t vi = 0; vi < views.size(); ++vi) {
      Camera cam = views[vi];
      Resize(cam);
      timer.Reset();
      const RenderOutput out = Render(scene, cam, options, removed);
      const double view_render_s = timer.Seconds();
      render_s += view_render_s;
      timer.Reset();
      const std::string stem = (dir / SafeName(cam.name)).string();
      const double depth_scale = WriteImages(stem, out);
      if (npy_) WriteArrays(stem, out, removed);
      write_s += timer.Seconds();
      double alpha_sum = 0;
      for (float a : out.alpha) alpha_sum += a;
      per_view.push_back({{"name", cam.name},
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
                            {"total", view_render_s}}}});
      progress.Step(vi + 1);
    }
    progress.Finish();

    report["counts"] = {{"num_gaussians", scene.size()}, {"num_removed", num_removed},
                        {"num_rendered_gaussians", scene.size() - num_removed}, {"views", views.size()}};
    report["views"] = per_view;
    report["depth_png"] =
        "16-bit grey: depth (view-space z, expected, normalised by alpha) = value * depth_png_scale of the view; "
        "0 = no coverage";
    report["timings_s"] = {{"load_scene", load_scene_s}, {"load_cameras", load_cameras_s},
                           {"load_removed", load_removed_s}, {"render", render_s}, {"write", write_s}};
    report["warnings"] = warnings;
    WriteReport(dir, report);
    return 0;
  }

 private:
  // Resizes keeping the field of view (RASTERIZER.md §10.2): fx' = fx W'/W, fy' = fy H'/H.
  void Resize(Camera& cam) const {
    if (width_ <= 0 && height_ <= 0) return;
    const int w = width_ > 0 ? width_ : std::max(1, int(std::lround(double(cam.width) * height_ / cam.height)));
    const int h = height_ > 0 ? height_ : std::max(1, int(std::lround(double(cam.height) * width_ / cam.width)));
    cam.fx *= double(w) / cam.width;
    cam.cx *= double(w) / cam.width;
    cam.fy *= double(h) / cam.height;
    cam.cy *= double(h) / cam.height;
    cam.width = w;
    cam.height = h;
  }

  // Returns the depth PNG scale (depth = value * scale).
  static double WriteImages(const std::string& stem, const RenderOutput& out) {
    const std::size_t pixels = static_cast<std::size_t>(out.width) * out.height;
    Image8 rgb{out.width, out.height, 3, std::vector<std::uint8_t>(pixels * 3)};
    for (std::size_t i = 0; i < pixels * 3; ++i) rgb.pixels[i] = To8(out.rgb[i]);
    WritePng8(stem + "_rgb.png", rgb);
    Image8 alpha{out.width, out.height, 1, std::vector<std::uint8_t>(pixels)};
    for (std::size_t i = 0; i < pixels; ++i) alpha.pixels[i] = To8(out.alpha[i]);
    WritePng8(stem + "_alpha.png", alpha);

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
    return scale;
  }

  static void WriteArrays(const std::string& stem, const RenderOutput& out, const std::vector<bool>& removed) {
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

  std::string scene_, cameras_, removed_, removed_is_ = "removed", views_ = "all", bg_ = "0", out_;
  bool npy_ = false;
  int width_ = 0, height_ = 0, sh_degree_ = 3, threads_ = 0;
};

AL_REGISTER_COMMAND(RenderCommand);

}  // namespace al::cli
