// al_refine.render: the project's CPU rasterizer (INRIA-exact forward pass, docs/rendering.md).
#include <pybind11/stl.h>

#include "al/core/error.hpp"
#include "al/render/render.hpp"
#include "python/common.hpp"
#include "python/options.hpp"

namespace al::python {
namespace {

// RenderOptions has no options table yet: its few user-facing fields are bound by name here
// (background, sh_degree, threads); a table added later is applied by TakeTableOptions.
RenderOptions RenderOptionsFrom(const std::vector<float>& background, int sh_degree, int threads, py::dict kwargs) {
  RenderOptions o;
  if (background.size() != 3) throw Error("render: background must be 3 numbers (r, g, b)", ExitCode::kUsage);
  o.background = Eigen::Vector3f(background[0], background[1], background[2]);
  if (sh_degree < 0 || sh_degree > 3) throw Error("render: sh_degree must be in [0, 3]", ExitCode::kUsage);
  o.max_sh_degree = sh_degree;
  if (threads < 0) throw Error("render: threads must be >= 0", ExitCode::kUsage);
  o.num_threads = threads;
  TakeTableOptions(o, kwargs);
  for (const auto& [key, value] : kwargs)
    throw Error("render: unknown option '" + py::str(key).cast<std::string>() + "' (background, sh_degree, threads)",
                ExitCode::kUsage);
  return o;
}

py::dict ToPython(const std::string& name, RenderOutput&& r) {
  const py::ssize_t h = r.height, w = r.width;
  py::dict d;
  d["name"] = name;
  d["rgb"] = TakeFloats(std::move(r.rgb), {h, w, 3});
  d["depth"] = TakeFloats(std::move(r.depth), {h, w});
  d["alpha"] = TakeFloats(std::move(r.alpha), {h, w});
  d["front_id"] = TakeInts(std::move(r.front_id), {h, w});
  return d;
}

py::object Render(const PyScene& scene, const py::object& cameras, const py::object& mask,
                  const std::vector<float>& background, int sh_degree, int threads, const py::kwargs& kwargs) {
  const RenderOptions o = RenderOptionsFrom(background, sh_degree, threads, py::dict(kwargs));
  const std::vector<Camera> views = CameraList(cameras);
  std::vector<bool> exclude;
  if (!mask.is_none()) exclude = MaskFromPython(mask.cast<py::array>(), scene.scene->size(), "mask");
  std::vector<RenderOutput> outs(views.size());
  {
    py::gil_scoped_release release;
    for (std::size_t v = 0; v < views.size(); ++v) outs[v] = al::Render(*scene.scene, views[v], o, exclude);
  }
  py::list result;
  for (std::size_t v = 0; v < views.size(); ++v) result.append(ToPython(views[v].name, std::move(outs[v])));
  if (py::isinstance<Camera>(cameras)) return result[0];
  return result;
}

}  // namespace

void BindRender(py::module_& m) {
  m.def("render", &Render, py::arg("scene"), py::arg("cameras"), py::arg("mask") = py::none(), py::kw_only(),
        py::arg("background") = std::vector<float>{0, 0, 0}, py::arg("sh_degree") = 3, py::arg("threads") = 0,
        R"(render(scene, cameras, mask=None, *, background=(0, 0, 0), sh_degree=3, threads=0)

Renders with the project's CPU rasterizer (INRIA-exact forward pass). cameras: a Camera or a
list of them; mask: Gaussians to leave out (bool (N,) or indices), e.g. a removal.
Returns per camera a dict {name, rgb (H, W, 3) float32, depth (H, W) expected depth (0 on
background), alpha (H, W), front_id (H, W) int32 index of the first blended Gaussian or -1};
one dict for one Camera. The arrays own the renderer's memory (no copy). The GIL is released
while rendering.)");
}

}  // namespace al::python
