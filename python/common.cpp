// Conversions between Python / NumPy values and the library's types (python/common.hpp).
#include "python/common.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <climits>

#include "al/core/error.hpp"
#include "al/io/masks.hpp"

namespace al::python {
namespace {

// An int beyond 64 bits becomes the double it rounds to, so the options table reports it as out
// of range (a UsageError naming the option), as the CLI does for the same digits.
nlohmann::json IntToJson(const py::int_& value) {
  int overflow = 0;
  const long long exact = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow == 0 && !PyErr_Occurred()) return static_cast<std::int64_t>(exact);
  PyErr_Clear();
  const double rounded = PyLong_AsDouble(value.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    throw Error("the integer " + py::str(py::handle(value)).cast<std::string>().substr(0, 40) + "... is too large for any option",
                ExitCode::kUsage);
  }
  return rounded;
}

}  // namespace

nlohmann::json ToJson(py::handle v) {
  if (v.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::dict>(v)) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [key, value] : v.cast<py::dict>()) j[py::str(key).cast<std::string>()] = ToJson(value);
    return j;
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& item : v) j.push_back(ToJson(item));
    return j;
  }
  if (py::isinstance<py::array>(v) && v.cast<py::array>().ndim() == 0) return ToJson(v.attr("item")());
  if (py::hasattr(v, "dtype") && py::str(v.attr("dtype").attr("kind")).cast<std::string>() == "b")
    return v.cast<bool>();  // numpy.bool_ is neither int nor bool
  if (py::isinstance<py::int_>(v) || py::hasattr(v, "__index__")) return IntToJson(py::int_(py::reinterpret_borrow<py::object>(v)));
  if (py::isinstance<py::float_>(v) || py::hasattr(v, "__float__")) return py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
  throw Error("cannot pass a value of type " + py::str(v.get_type().attr("__name__")).cast<std::string>() +
                  " as an option (numbers, strings, booleans, lists and dicts are accepted)",
              ExitCode::kUsage);
}

py::object FromJson(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list out;
      for (const auto& item : j) out.append(FromJson(item));
      return out;
    }
    case nlohmann::json::value_t::object: {
      py::dict out;
      for (const auto& [key, value] : j.items()) out[py::str(key)] = FromJson(value);
      return out;
    }
    default: return py::none();
  }
}

NpyArray ViewOf(const py::array& array, const std::string& what) {
  static const std::pair<char, const char*> kKinds[] = {{'b', "b1"}, {'f', "f"}, {'i', "i"}, {'u', "u"}};
  const py::dtype dt = array.dtype();
  std::string descr;
  for (const auto& [kind, prefix] : kKinds)
    if (dt.kind() == kind) descr = kind == 'b' ? std::string(prefix) : prefix + std::to_string(dt.itemsize());
  if (descr.empty() || !(array.flags() & py::array::c_style))
    throw Error(what + ": expected a C-contiguous bool, integer or float array, got dtype " +
                    py::str(py::object(dt)).cast<std::string>(),
                ExitCode::kBadInput);
  if (dt.byteorder() == '>') throw Error(what + ": big-endian arrays are not supported", ExitCode::kBadInput);
  NpyArray a;
  a.descr = descr;
  a.item_size = std::size_t(dt.itemsize());
  for (py::ssize_t d = 0; d < array.ndim(); ++d) a.shape.push_back(array.shape(d));
  a.data = static_cast<const std::uint8_t*>(array.data());
  return a;
}

py::array Contiguous(const py::array& array, const std::string& what) {
  if (array.flags() & py::array::c_style) return array;
  const py::module_ warnings = py::module_::import("warnings");
  warnings.attr("warn")(what + " is not C-contiguous: copied", py::module_::import("al_refine").attr("CopyWarning"),
                        2);
  return py::module_::import("numpy").attr("ascontiguousarray")(array);
}

namespace {

template <class T>
py::array_t<T> Take(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  py::capsule base(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), base);
}

}  // namespace

py::array_t<float> TakeFloats(std::vector<float>&& data, std::vector<py::ssize_t> shape) {
  return Take(std::move(data), std::move(shape));
}

py::array_t<std::int32_t> TakeInts(std::vector<std::int32_t>&& data, std::vector<py::ssize_t> shape) {
  return Take(std::move(data), std::move(shape));
}

py::array_t<bool> MaskToNumpy(const std::vector<bool>& mask) {
  py::array_t<bool> out(py::ssize_t(mask.size()));
  bool* p = out.mutable_data();
  for (std::size_t i = 0; i < mask.size(); ++i) p[i] = mask[i];
  return out;
}

std::vector<bool> MaskFromPython(const py::array& array, std::size_t n, const std::string& what) {
  const py::array a = Contiguous(array, what);
  return RemovalSetFromArray(ViewOf(a, what), what, n).removed;
}

std::vector<std::int32_t> LabelsFrom(const py::object& labels, const std::string& what) {
  const py::array array = py::array::ensure(labels);
  if (!array || array.ndim() != 1 || (array.dtype().kind() != 'i' && array.dtype().kind() != 'u'))
    throw Error(what + ": expected a 1-D integer array (an object id per Gaussian), got " +
                    (array ? "dtype " + py::str(py::object(array.dtype())).cast<std::string>() + " with " +
                                 std::to_string(array.ndim()) + " dimensions"
                           : std::string("something else")),
                ExitCode::kBadInput);
  const py::array contiguous = Contiguous(array, what);
  const std::vector<std::int64_t> wide = ViewOf(contiguous, what).ToInt64();
  std::vector<std::int32_t> out(wide.size());
  for (std::size_t i = 0; i < wide.size(); ++i) {
    if (wide[i] < INT32_MIN || wide[i] > INT32_MAX)
      throw Error(what + ": label " + std::to_string(wide[i]) + " at row " + std::to_string(i) +
                      " does not fit an int32 object id", ExitCode::kBadInput);
    out[i] = static_cast<std::int32_t>(wide[i]);
  }
  return out;
}

int ObjectIdFrom(const py::object& object_id, const std::vector<std::int32_t>& labels, const std::string& what) {
  const nlohmann::json id = ToJson(object_id);
  if (!id.is_number_integer() || id.get<std::int64_t>() < INT32_MIN || id.get<std::int64_t>() > INT32_MAX)
    throw Error(what + ": object_id must be an integer of 32 bits, not " + id.dump(), ExitCode::kUsage);
  const int target = static_cast<int>(id.get<std::int64_t>());
  if (std::find(labels.begin(), labels.end(), target) == labels.end())
    throw Error(what + ": object_id " + std::to_string(target) + " is not among the labels", ExitCode::kBadInput);
  return target;
}

std::vector<Camera> CameraList(py::handle cameras) {
  if (py::isinstance<Camera>(cameras)) return {cameras.cast<Camera>()};
  return cameras.cast<std::vector<Camera>>();
}

}  // namespace al::python
