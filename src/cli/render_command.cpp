// `al-refine render --scene S --cameras C [--removed R] [--views ...] [--npy] --out DIR`:
// flags -> RenderViewsOptions -> RenderViewsToFolder (al/render/render_views.hpp).
#include <cstdio>

#include "al/render/render_views.hpp"
#include "src/cli/background_flag.hpp"
#include "src/cli/command.hpp"
#include "src/cli/warnings.hpp"

namespace al::cli {

class RenderCommand : public Command {
 public:
  std::string Name() const override { return "render"; }
  std::string Description() const override {
    return "Render views of a scene (optionally without a removed set) on the CPU, INRIA-exact: RGB, depth and "
           "alpha PNGs, optional float .npy";
  }
  void Setup(CLI::App& app) override {
    app.add_option("--scene", o_.scene, "Scene file (.ply or .splat)")->required();
    app.add_option("--cameras", o_.cameras, "Cameras: INRIA cameras.json, COLMAP folder, or JSON list")->required();
    app.add_option("--removed", o_.removed, "Removed set (.npy mask/indices, .txt indices, or subset .ply)");
    app.add_option("--removed-is", removed_is_, "Whether --removed lists removed or remaining Gaussians")
        ->check(CLI::IsMember({"removed", "remaining"}))
        ->default_val("removed");
    app.add_option("--views", o_.views, "Comma-separated view names, or all")->default_val("all");
    app.add_option("--bg", bg_, "Background: 0 (black), 1 (white) or r,g,b")->default_val("0");
    app.add_flag("--npy", o_.npy, "Also write float32 rgb/depth/alpha and int32 radii .npy files");
    app.add_option("--width", o_.width, "Render width (keeps the field of view)")->check(CLI::Range(1, 65536));
    app.add_option("--height", o_.height, "Render height (keeps the field of view)")->check(CLI::Range(1, 65536));
    app.add_option("--sh-degree", o_.render.max_sh_degree, "Maximum SH degree evaluated")
        ->check(CLI::Range(0, 3))
        ->default_val(3);
    app.add_option("--threads", o_.render.num_threads, "OpenMP threads (0 = default)")->check(CLI::NonNegativeNumber);
    app.add_option("--out", o_.out_dir, "Output directory")->required();
  }

  int Run() override {
    o_.removed_is = removed_is_ == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
    o_.render.background = ParseBackground(bg_);
    o_.params = {{"scene", o_.scene},     {"cameras", o_.cameras},   {"removed", o_.removed},
                 {"removed_is", removed_is_}, {"views", o_.views},   {"bg", bg_},
                 {"npy", o_.npy},         {"width", o_.width},       {"height", o_.height},
                 {"sh_degree", o_.render.max_sh_degree}, {"threads", o_.render.num_threads}};
    const RenderViewsResult r = RenderViewsToFolder(o_);
    PrintReportWarnings(r.report);
    std::printf("rendered %zu views of %zu Gaussians (%zu removed) -> %s\n", r.views,
                r.report["counts"]["num_gaussians"].get<std::size_t>(), r.num_removed, o_.out_dir.c_str());
    return 0;
  }

 private:
  RenderViewsOptions o_;
  std::string removed_is_ = "removed", bg_ = "0";
};

AL_REGISTER_COMMAND(RenderCommand);

}  // namespace al::cli
