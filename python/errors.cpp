// Python exceptions for the library's errors: one class per CLI exit code (SPEC §1), all derived
// from al_refine.Error, each carrying `exit_code` and `category` and the library's message.
#include <new>

#include "al/core/error.hpp"
#include "python/common.hpp"

namespace al::python {
namespace {

struct Category {
  int code;
  const char* name;      // class name
  const char* category;  // as in the CLI's documentation
  const char* doc;
};
constexpr Category kCategories[] = {
    {1, "UsageError", "usage", "Bad options or arguments (CLI exit code 1)."},
    {2, "BadInputError", "bad_input", "Unreadable or inconsistent input data (CLI exit code 2)."},
    {3, "EmptyGraphError", "empty_graph",
     "No edge survived the semantic gate (CLI exit code 3); .result holds the refinement, whose mask "
     "equals the input mask."},
    {4, "InternalError", "internal", "A bug or resource exhaustion, e.g. out of memory (CLI exit code 4)."},
};
PyObject* g_types[5] = {nullptr, nullptr, nullptr, nullptr, nullptr};

void Raise(int code, const char* message) { PyErr_SetString(ErrorType(code).ptr(), message); }

}  // namespace

py::handle ErrorType(int exit_code) {
  return g_types[exit_code >= 1 && exit_code <= 4 ? exit_code : 4];
}

void BindErrors(py::module_& m) {
  PyObject* base = PyErr_NewExceptionWithDoc("al_refine.Error", "Base of al_refine's errors.", PyExc_Exception, nullptr);
  m.add_object("Error", py::handle(base));
  for (const Category& c : kCategories) {
    const std::string qualified = std::string("al_refine.") + c.name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), c.doc, base, nullptr);
    py::handle(type).attr("exit_code") = c.code;
    py::handle(type).attr("category") = c.category;
    g_types[c.code] = type;
    m.add_object(c.name, py::handle(type));
  }
  PyObject* copy = PyErr_NewExceptionWithDoc("al_refine.CopyWarning",
                                             "An input array had to be copied (layout or dtype).",
                                             PyExc_UserWarning, nullptr);
  m.add_object("CopyWarning", py::handle(copy));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const al::Error& e) {
      Raise(static_cast<int>(e.code()), e.what());
    } catch (const std::bad_alloc&) {
      Raise(4, "out of memory");
    } catch (const py::builtin_exception&) {
      throw;  // pybind11's own (cast errors, ...): its default translation
    } catch (const py::error_already_set&) {
      throw;
    } catch (const std::exception& e) {
      Raise(4, e.what());  // as the CLI: "internal error", exit code 4
    }
  });
}

}  // namespace al::python
