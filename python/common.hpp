// Shared pieces of the Python module al_refine (python/): conversions between NumPy / Python
// values and the library's types. The module is thin: every function calls one library entry
// point; what is here only moves data across the language boundary.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "al/io/camera.hpp"
#include "al/io/npy.hpp"
#include "al/scene/scene.hpp"

namespace al::python {

namespace py = pybind11;

// A scene as Python sees it: the library's Scene (shared with refinements, never copied) and,
// when Scene.from_arrays was given float32 C-order features, that very array (used in place).
struct PyScene {
  std::shared_ptr<Scene> scene;
  py::object features = py::none();  // the caller's (N, D) float32 array, or None
  std::vector<std::string> copied;   // names of the caller's arrays that were copied
};

// JSON <-> Python (dict, list, str, int, float, bool, None; NumPy scalars via __index__/__float__).
nlohmann::json ToJson(py::handle value);
py::object FromJson(const nlohmann::json& value);

// A read-only view of a C-contiguous NumPy array as the library's NpyArray (no copy). The array
// must stay alive while the view is used (the caller holds it). Throws al::Error (bad input) for
// dtypes the library does not read; `what` names the argument in messages.
NpyArray ViewOf(const py::array& array, const std::string& what);

// A C-contiguous version of `array` (the same object when it already is; else a copy, announced
// with al_refine.CopyWarning naming `what`).
py::array Contiguous(const py::array& array, const std::string& what);

// NumPy arrays that own C++ memory (no copy: the vector moves into the array's base capsule).
py::array_t<float> TakeFloats(std::vector<float>&& data, std::vector<py::ssize_t> shape);
py::array_t<std::int32_t> TakeInts(std::vector<std::int32_t>&& data, std::vector<py::ssize_t> shape);
// std::vector<bool> is bit-packed, so masks are always copied into a NumPy bool array.
py::array_t<bool> MaskToNumpy(const std::vector<bool>& mask);
// A 1-D mask of N Gaussians from a bool array (N,) or integer indices (as a --removed .npy).
std::vector<bool> MaskFromPython(const py::array& array, std::size_t num_gaussians, const std::string& what);

// Ground truth as the CLI reads it from --labels / --object-id: an integer array (a float array is
// refused, as the CLI refuses a float .npy: bad input), and an id that must be an int of 32 bits
// (usage error otherwise) present among the labels (bad input otherwise).
std::vector<std::int32_t> LabelsFrom(const py::object& labels, const std::string& what);
int ObjectIdFrom(const py::object& object_id, const std::vector<std::int32_t>& labels, const std::string& what);

// Cameras: one Camera or a sequence of them.
std::vector<Camera> CameraList(py::handle cameras);

// Registration of the module's parts (one file each).
void BindErrors(py::module_& m);
void BindScene(py::module_& m);
void BindCameras(py::module_& m);
void BindRefine(py::module_& m);
void BindRender(py::module_& m);
void BindEval(py::module_& m);
void BindSynth(py::module_& m);

// The Python exception type for an ExitCode (al_refine.UsageError, BadInputError, ...).
py::handle ErrorType(int exit_code);

}  // namespace al::python
