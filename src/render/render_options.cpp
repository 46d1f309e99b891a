// RenderOptions::Check and RenderViewsOptions::Check: the ranges the renderer accepts.
#include "al/core/error.hpp"
#include "al/core/option_table.hpp"
#include "al/render/render.hpp"
#include "al/render/render_views.hpp"

namespace al {

void RenderOptions::Check() const {
  using R = NumericRange;
  CheckOptionRange("render", "scale_modifier", scale_modifier, R::Above(0), "multiplier of every Gaussian's scale");
  CheckOptionRange("render", "max_sh_degree", max_sh_degree, R::Closed(0, 3), "highest SH degree evaluated");
  CheckOptionRange("render", "num_threads", num_threads, R::AtLeast(0), "OpenMP threads, 0 = default");
  for (int c = 0; c < 3; ++c)
    CheckOptionRange("render", "background", background[c], R::Any(), "background colour r,g,b");
}

void RenderViewsOptions::Check() const {
  if (scene.empty()) throw Error("render: --scene is required", ExitCode::kUsage);
  if (cameras.empty()) throw Error("render: --cameras is required", ExitCode::kUsage);
  if (out_dir.empty()) throw Error("render: --out is required", ExitCode::kUsage);
  CheckOptionRange("render", "width", width, NumericRange::Closed(0, 65536), "image width, 0 = the camera's");
  CheckOptionRange("render", "height", height, NumericRange::Closed(0, 65536), "image height, 0 = the camera's");
  render.Check();
}

}  // namespace al
