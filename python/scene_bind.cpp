// al_refine.Scene: a 3DGS scene loaded from a file or built from NumPy arrays (raw, pre-activation
// values as 3DGS stores them: opacity logits, log scales, unnormalised quaternions w x y z).
#include <cmath>

#include <pybind11/stl.h>

#include "al/core/error.hpp"
#include "al/io/ply.hpp"
#include "python/common.hpp"

namespace al::python {
namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// Rows of an (N, cols) float array (or (N,) when cols == 1) as a C-order float32 array.
FloatArray Rows(const py::array& a, py::ssize_t n, py::ssize_t cols, const std::string& what) {
  const FloatArray f = FloatArray::ensure(a);
  if (!f) throw Error(what + ": not convertible to float32", ExitCode::kBadInput);
  const bool ok = cols == 1 ? (f.ndim() == 1 || (f.ndim() == 2 && f.shape(1) == 1)) && f.shape(0) == n
                            : f.ndim() == 2 && f.shape(0) == n && f.shape(1) == cols;
  if (!ok)
    throw Error(what + ": expected shape (" + std::to_string(n) + (cols == 1 ? ",)" : ", " + std::to_string(cols) + ")"),
                ExitCode::kBadInput);
  return f;
}

template <class M>
void CopyRows(const FloatArray& f, M& out) {
  out.resize(f.shape(0), f.shape(1));
  const float* p = f.data();
  for (Eigen::Index i = 0; i < out.rows(); ++i)
    for (Eigen::Index c = 0; c < out.cols(); ++c) out(i, c) = p[i * out.cols() + c];
}

// sh of shape (N, K, 3) (3DGS's get_features) or (N, 3K), K = (degree + 1)^2.
void SetSh(Scene& s, const py::array& sh, py::ssize_t n) {
  const FloatArray f = FloatArray::ensure(sh);
  if (!f || f.ndim() < 2 || f.shape(0) != n || (f.ndim() == 3 && f.shape(2) != 3) || f.ndim() > 3)
    throw Error("sh: expected shape (N, K, 3) or (N, 3K) with N = " + std::to_string(n), ExitCode::kBadInput);
  const py::ssize_t cols = f.size() / std::max<py::ssize_t>(1, n);
  const int degree = int(std::lround(std::sqrt(double(cols / 3)))) - 1;
  if (cols % 3 != 0 || degree < 0 || degree > 3 || (degree + 1) * (degree + 1) * 3 != cols)
    throw Error("sh: " + std::to_string(cols / 3) + " coefficients per channel; expected 1, 4, 9 or 16",
                ExitCode::kBadInput);
  s.sh.resize(n, cols);
  std::copy(f.data(), f.data() + f.size(), s.sh.data());
  s.sh_degree = degree;
  s.has_f_dc = true;
}

std::shared_ptr<PyScene> FromArrays(const py::array& xyz, const py::array& opacity, const py::array& scales,
                                    const py::array& rotations, const py::array& sh, const py::object& features) {
  auto out = std::make_shared<PyScene>();
  out->scene = std::make_shared<Scene>();
  Scene& s = *out->scene;
  if (xyz.ndim() != 2 || xyz.shape(1) != 3) throw Error("xyz: expected shape (N, 3)", ExitCode::kBadInput);
  const py::ssize_t n = xyz.shape(0);
  CopyRows(Rows(xyz, n, 3, "xyz"), s.means);
  CopyRows(Rows(scales, n, 3, "scales"), s.log_scales);
  CopyRows(Rows(rotations, n, 4, "rotations"), s.rotations);
  const FloatArray o = Rows(opacity, n, 1, "opacity");
  s.opacity_logits = Eigen::Map<const Eigen::VectorXf>(o.data(), n);
  SetSh(s, sh, n);
  s.has_opacity = s.has_scales = s.has_rotations = true;
  s.source_format = "arrays";
  out->copied = {"xyz", "opacity", "scales", "rotations", "sh"};
  if (!features.is_none()) {
    py::array f = features.cast<py::array>();
    if (f.ndim() != 2 || f.shape(0) != n) throw Error("features: expected shape (N, D)", ExitCode::kBadInput);
    const py::dtype dt = f.dtype();
    const bool in_place = dt.kind() == 'f' && dt.itemsize() == 4 && dt.byteorder() != '>' && (f.flags() & py::array::c_style);
    if (!in_place) {
      py::module_::import("warnings").attr("warn")("features: not C-contiguous float32, copied",
                                                   py::module_::import("al_refine").attr("CopyWarning"), 2);
      f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(f);
      out->copied.push_back("features");
    }
    out->features = f;
  }
  return out;
}

std::shared_ptr<PyScene> Load(const std::string& path) {
  auto out = std::make_shared<PyScene>();
  py::gil_scoped_release release;
  out->scene = std::make_shared<Scene>(ReadScene(path));
  return out;
}

// A read-only NumPy view of scene memory; `self` (the Python Scene) keeps it alive.
py::array View(py::handle self, const float* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides) {
  py::array a(py::dtype::of<float>(), std::move(shape), std::move(strides), data, self);
  a.attr("flags").attr("writeable") = false;
  return a;
}

template <class M>
py::array ColumnMajorView(py::handle self, const M& m) {  // Eigen's SoA columns: (N, C), Fortran order
  return View(self, m.data(), {m.rows(), m.cols()}, {py::ssize_t(sizeof(float)), py::ssize_t(sizeof(float) * m.rows())});
}

const char* kSceneDoc = R"(A 3D Gaussian Splatting scene (index space = row order of every mask).

Scene.load(path) reads a .ply or .splat file; Scene.from_arrays(...) takes NumPy arrays.
The properties xyz, opacity, scales, rotations, sh and features are read-only NumPy views of the
scene's memory (no copy).)";

const char* kFromArraysDoc = R"(Builds a scene from arrays of N Gaussians, raw values as 3DGS stores them:
xyz (N, 3); opacity (N,) logits; scales (N, 3) log sigma; rotations (N, 4) quaternions w x y z
(not normalised); sh (N, K, 3) as 3DGS's get_features, or (N, 3K), K = 1, 4, 9 or 16;
features (N, D) optional per-Gaussian features (e.g. Feature 3DGS's semantic features).

Copies: the scene owns its geometry and colour columns (xyz, opacity, scales, rotations, sh are
copied, 59 floats per Gaussian at SH degree 3). The features, usually the largest array
(D up to 512), are used in place when they are C-contiguous float32: no copy, and
scene.features is the same array. Otherwise they are converted once and a CopyWarning says so.
scene.copied lists what was copied.)";

}  // namespace

void BindScene(py::module_& m) {
  py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", kSceneDoc)
      .def_static("load", &Load, py::arg("path"), "Reads a scene (.ply or .splat); features from the PLY's "
                  "feature columns (semantic_*, obj_dc_*, ...) when present.")
      .def_static("from_arrays", &FromArrays, py::arg("xyz"), py::arg("opacity"), py::arg("scales"),
                  py::arg("rotations"), py::arg("sh"), py::arg("features") = py::none(), kFromArraysDoc)
      .def("__len__", [](const PyScene& s) { return s.scene->size(); })
      .def("__repr__", [](const PyScene& s) {
        return "<al_refine.Scene " + std::to_string(s.scene->size()) + " Gaussians, SH degree " +
               std::to_string(s.scene->sh_degree) + ", " +
               (s.features.is_none() ? std::to_string(s.scene->features.cols()) : py::str(s.features.attr("shape")[py::int_(1)]).cast<std::string>()) +
               " feature dims>";
      })
      .def_property_readonly("xyz", [](py::object self) { return ColumnMajorView(self, self.cast<PyScene&>().scene->means); })
      .def_property_readonly("scales", [](py::object self) { return ColumnMajorView(self, self.cast<PyScene&>().scene->log_scales); })
      .def_property_readonly("rotations", [](py::object self) { return ColumnMajorView(self, self.cast<PyScene&>().scene->rotations); })
      .def_property_readonly("opacity", [](py::object self) {
        const Scene& s = *self.cast<PyScene&>().scene;
        return View(self, s.opacity_logits.data(), {s.opacity_logits.size()}, {py::ssize_t(sizeof(float))});
      })
      .def_property_readonly("sh", [](py::object self) {
        const Scene& s = *self.cast<PyScene&>().scene;
        const py::ssize_t k = s.sh.cols() / 3;
        return View(self, s.sh.data(), {s.sh.rows(), k, 3}, {py::ssize_t(sizeof(float)) * s.sh.cols(), 3 * py::ssize_t(sizeof(float)), py::ssize_t(sizeof(float))});
      })
      .def_property_readonly("features", [](py::object self) -> py::object {
        const PyScene& p = self.cast<PyScene&>();
        if (!p.features.is_none()) return p.features;
        const RowMatXf& f = p.scene->features;
        if (f.cols() == 0) return py::none();
        return View(self, f.data(), {f.rows(), f.cols()}, {py::ssize_t(sizeof(float)) * f.cols(), py::ssize_t(sizeof(float))});
      }, "The (N, D) features: the array given to from_arrays (same object, no copy) or a view of the file's.")
      .def_property_readonly("sh_degree", [](const PyScene& s) { return s.scene->sh_degree; })
      .def_property_readonly("source_path", [](const PyScene& s) { return s.scene->source_path; })
      .def_property_readonly("copied", [](const PyScene& s) { return py::tuple(py::cast(s.copied)); },
                             "Names of the caller's arrays from_arrays copied.");
}

}  // namespace al::python
