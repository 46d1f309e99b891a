// al_refine.synth: a synthetic scene with ground truth and the four simulated removals (SPEC §7).
#include <pybind11/stl.h>

#include "al/core/error.hpp"
#include "al/fixtures/synth.hpp"
#include "python/common.hpp"
#include "python/options.hpp"

namespace al::python {
namespace {

struct PySynth {
  std::shared_ptr<PyScene> scene;
  py::object labels, removed, masks, class_embeddings, stats;
  std::vector<Camera> cameras;
  int target_id = 0;
  std::string target_name, preset;
};

// SynthOptions has no options table yet: the fields bound here by name are preset, n, seed,
// views, width, height, feature_dim, sh_degree, masks; a table added later is applied by
// TakeTableOptions.
fixtures::SynthOptions SynthOptionsFrom(const std::string& preset, std::size_t n, std::uint64_t seed, int views,
                                        int width, int height, int feature_dim, int sh_degree, bool masks,
                                        py::dict kwargs) {
  fixtures::SynthOptions o;
  o.preset = preset;
  o.num_gaussians = n;
  o.seed = seed;
  o.num_views = views;
  o.width = width;
  o.height = height;
  o.feature_dim = feature_dim;
  o.sh_degree = sh_degree;
  o.compute_masks = masks;
  TakeTableOptions(o, kwargs);
  for (const auto& [key, value] : kwargs)
    throw Error("synth: unknown option '" + py::str(key).cast<std::string>() +
                    "' (preset, n, seed, views, width, height, feature_dim, sh_degree, masks)",
                ExitCode::kUsage);
  return o;
}

PySynth ToPython(fixtures::SynthScene&& s) {
  PySynth p;
  p.scene = std::make_shared<PyScene>();
  p.scene->scene = std::make_shared<Scene>(std::move(s.scene));
  p.labels = TakeInts(std::move(s.labels), {py::ssize_t(p.scene->scene->size())});
  py::dict removed;
  for (const auto& [name, mask] : s.removed) removed[py::str(name)] = MaskToNumpy(mask);
  p.removed = removed;
  py::list masks;
  for (std::size_t v = 0; v < s.target_masks.size(); ++v) {
    const Camera& c = s.cameras[v];
    py::array_t<std::uint8_t> m({py::ssize_t(c.height), py::ssize_t(c.width)});
    std::copy(s.target_masks[v].begin(), s.target_masks[v].end(), m.mutable_data());
    masks.append(m);
  }
  p.masks = masks;
  const RowMatXf& e = s.class_embeddings;
  p.class_embeddings = py::array_t<float>({e.rows(), e.cols()}, e.data());
  p.stats = FromJson(s.stats);
  p.cameras = std::move(s.cameras);
  p.target_id = s.target_id;
  p.target_name = s.target_name;
  p.preset = s.preset;
  return p;
}

PySynth Synth(const std::string& preset, std::size_t n, std::uint64_t seed, int views, int width, int height,
              int feature_dim, int sh_degree, bool masks, const py::kwargs& kwargs) {
  const fixtures::SynthOptions o =
      SynthOptionsFrom(preset, n, seed, views, width, height, feature_dim, sh_degree, masks, py::dict(kwargs));
  fixtures::SynthScene s;
  {
    py::gil_scoped_release release;
    s = fixtures::Synthesize(o);
  }
  return ToPython(std::move(s));
}

}  // namespace

void BindSynth(py::module_& m) {
  py::class_<PySynth>(m, "Synth", "What synth() returns: a scene, its ground truth and simulated removals.")
      .def_readonly("scene", &PySynth::scene)
      .def_readonly("labels", &PySynth::labels, "int32 (N,): object id per Gaussian (0 = background)")
      .def_readonly("removed", &PySynth::removed, "{'fgs', 'sags', 'gg', 'gc'}: bool (N,) simulated removals")
      .def_readonly("masks", &PySynth::masks, "per view uint8 (H, W): 1 where the target is (share >= 0.5)")
      .def_readonly("cameras", &PySynth::cameras)
      .def_readonly("class_embeddings", &PySynth::class_embeddings, "(classes, D) unit text embeddings")
      .def_readonly("stats", &PySynth::stats)
      .def_readonly("target_id", &PySynth::target_id)
      .def_readonly("target_name", &PySynth::target_name)
      .def_readonly("preset", &PySynth::preset)
      .def("__repr__", [](const PySynth& s) {
        return "<al_refine.Synth " + s.preset + " target '" + s.target_name + "' (id " + std::to_string(s.target_id) +
               "), " + std::to_string(s.scene->scene->size()) + " Gaussians, " + std::to_string(s.cameras.size()) +
               " views>";
      });
  m.def("synth", &Synth, py::arg("preset") = "room", py::arg("n") = 200000, py::arg("seed") = 1, py::kw_only(),
        py::arg("views") = 24, py::arg("width") = 320, py::arg("height") = 240, py::arg("feature_dim") = 16,
        py::arg("sh_degree") = 1, py::arg("masks") = true,
        R"(synth(preset="room", n=200000, seed=1, *, views=24, width=320, height=240, feature_dim=16,
      sh_degree=1, masks=True)

A synthetic scene (the generator of `al-refine synth`, deterministic in the seed): preset room,
counter or garden with n Gaussians, ground-truth labels, orbit cameras, per-view target masks and
the simulated removals of fgs, sags, gg and gc. The GIL is released while generating.)");
}

}  // namespace al::python
