// al_refine.refine: RunRefine on in-memory arrays (the same code path as `al-refine refine` after
// loading). Keyword options come from the options tables; help(al_refine.refine) lists them.
#include <pybind11/stl.h>

#include "al/core/error.hpp"
#include "al/decision.hpp"
#include "al/refine/refine.hpp"
#include "python/common.hpp"
#include "python/options.hpp"
#include "solvers/cut_pursuit/cut_pursuit.hpp"
#include "solvers/exact/exact_solver.hpp"

namespace al::python {
namespace {

struct PyRefineResult {
  py::object refined, removed, added, restored, summary, report;
  std::string status, message;
};

// Keywords the named solver's table declares go to solver_options (as --solver-options would).
void TakeSolverOptions(const std::string& solver, nlohmann::json& solver_options, py::dict& kwargs) {
  auto take = [&](const auto& table) {
    for (const auto& field : table.fields()) {
      const std::string keyword = KeywordOf(field.name, kwargs);
      if (keyword.empty()) continue;
      const py::str key(keyword);
      solver_options[field.name] = FieldValue(field, kwargs[key]);
      PyDict_DelItem(kwargs.ptr(), key.ptr());
    }
  };
  if (solver == "cp" || solver.empty()) take(cp::CutPursuitOptions::Table());
  if (solver == "exact") take(ExactOptions::Table());
}

std::string KnownKeywords() {
  std::string known = "graph: " + TableNames(GraphOptions::Table()) + "; decision: " +
                      TableNames(DecisionOptions::Table()) + "; cp solver: " +
                      TableNames(cp::CutPursuitOptions::Table()) + "; exact solver: " +
                      TableNames(ExactOptions::Table());
  return TableNamesIfAny<RefineOptions>("refine") + known;
}

RefineOptions OptionsFrom(const std::string& method, const py::object& k, const py::object& delta, const std::string& solver,
                          const py::object& removed_is, const py::object& solver_options, py::dict kwargs) {
  RefineOptions o;
  RefineOptions::Table().Set(o, "method", method);
  RefineOptions::Table().Set(o, "solver", solver);
  if (!removed_is.is_none())
    o.removed_is = removed_is.cast<std::string>() == "remaining" ? RemovedIs::kRemaining : RemovedIs::kRemoved;
  if (!solver_options.is_none()) o.solver_options = ToJson(solver_options);
  kwargs["k"] = k;
  kwargs["delta"] = delta;
  TakeTableOptions(o, kwargs);  // RefineOptions, once it has a table
  TakeOptions(GraphOptions::Table(), o.graph, kwargs);
  TakeOptions(DecisionOptions::Table(), o.decision, kwargs);
  TakeSolverOptions(o.solver, o.solver_options, kwargs);
  for (const auto& [key, value] : kwargs)
    throw Error("refine: unknown option '" + py::str(key).cast<std::string>() + "' for solver '" + o.solver +
                    "' (" + KnownKeywords() + ")",
                ExitCode::kUsage);
  return o;
}

PyRefineResult ToPython(const RefineResult& r) {
  PyRefineResult p;
  p.refined = MaskToNumpy(r.refined);
  p.removed = MaskToNumpy(r.removed);
  p.added = py::array_t<std::int64_t>(py::ssize_t(r.added.size()), r.added.data());
  p.restored = py::array_t<std::int64_t>(py::ssize_t(r.restored.size()), r.restored.data());
  p.summary = FromJson(r.Summary());
  p.report = FromJson(r.report);
  p.status = r.status;
  p.message = r.message;
  return p;
}

// k and delta are plain objects: the graph table converts and checks them, with the CLI's messages.
PyRefineResult Refine(const PyScene& scene, const py::array& removed, const std::string& method, const py::object& k,
                      const py::object& delta,
                      const std::string& solver, const py::object& features, const py::object& labels,
                      const py::object& object_id, const py::object& removed_is, const py::object& out,
                      const py::object& solver_options, const py::kwargs& kwargs) {
  RefineOptions o = OptionsFrom(method, k, delta, solver, removed_is, solver_options, py::dict(kwargs));
  if (!out.is_none()) o.out_dir = py::str(out).cast<std::string>();
  RefineData d;
  d.scene = scene.scene;
  const py::array removed_c = Contiguous(removed, "removed");
  d.removed = ViewOf(removed_c, "removed");
  py::array features_c;
  const py::object f = features.is_none() ? scene.features : features;
  if (!f.is_none()) {
    features_c = Contiguous(f.cast<py::array>(), "features");
    d.features = ViewOf(features_c, "features");
  }
  if (!labels.is_none()) {
    d.labels = LabelsFrom(labels, "refine: labels");
    if (object_id.is_none()) throw Error("refine: labels need object_id", ExitCode::kUsage);
    d.object_id = ObjectIdFrom(object_id, d.labels, "refine");
  }
  RefineResult r;
  {
    py::gil_scoped_release release;  // the arrays above stay referenced by this frame
    r = RunRefine(d, o);
  }
  PyRefineResult result = ToPython(r);
  if (r.exit_code != 0) {
    py::object error = ErrorType(r.exit_code)(r.message);
    error.attr("result") = py::cast(result);
    PyErr_SetObject(ErrorType(r.exit_code).ptr(), error.ptr());
    throw py::error_already_set();
  }
  return result;
}

// The defaults of refine()'s named parameters: the CLI's, from the same option tables.
struct RefineDefaults {
  std::string method = SpellOptionValue(RefineOptions::Table().Find("method").get(RefineOptions{}));
  std::string solver = SpellOptionValue(RefineOptions::Table().Find("solver").get(RefineOptions{}));
  int k = GraphOptions{}.k;
  double delta = GraphOptions{}.delta;
};

std::string RefineDoc() {
  const RefineDefaults d;
  std::string doc = "refine(scene, removed, method=\"" + d.method + "\", k=" + std::to_string(d.k) + ", delta=" +
                    FormatOptionNumber(d.delta) + ", solver=\"" + d.solver + "\", *, features=None,\n";
  doc += R"(       labels=None, object_id=None, removed_is=None, out=None, solver_options=None, **options)

Refines a removal: the same pipeline as `al-refine refine` (one code path after loading, so the
masks are identical for the same input; every default is the CLI's, from the same option tables). removed: the removal method's output as a bool mask
(N,) or integer indices (as a --removed .npy); with method "gc" float arrays with 0 = removed.
method: fgs | gg | sags | gc | generic (the presets of docs/methods.md: features, polarity).
features: (N, D) array overriding the scene's (float32 C-order: used in place, no copy).
labels, object_id: ground truth (int per Gaussian, the target's id): adds gt scores.
out: a folder to write refined.npy, refined.txt, added.txt, remaining.ply, report.json into.
The GIL is released while the graph is built and solved.

Returns a RefineResult: refined (bool mask), removed (the input as read), added and restored
(indices), summary (dict), report (the report.json dict), status, message. An empty graph
raises EmptyGraphError (its .result holds the result, refined == the input).

Keyword options (each a field of an options table; the CLI flag's name with _ for -; a
trailing _ is allowed for Python keywords, e.g. lambda_=2; solver options go to the solver):
)";
  doc += TableDoc<RefineOptions>();
  doc += OptionsDoc(GraphOptions::Table()) + OptionsDoc(DecisionOptions::Table()) +
         OptionsDoc(cp::CutPursuitOptions::Table()) + OptionsDoc(ExactOptions::Table());
  return doc;
}

}  // namespace

void BindRefine(py::module_& m) {
  py::class_<PyRefineResult>(m, "RefineResult", "What refine() returns (see help(al_refine.refine)).")
      .def_readonly("refined", &PyRefineResult::refined, "bool (N,): the refined removed set")
      .def_readonly("removed", &PyRefineResult::removed, "bool (N,): the input removed set as read")
      .def_readonly("added", &PyRefineResult::added, "int64 indices refinement added")
      .def_readonly("restored", &PyRefineResult::restored, "int64 indices refinement returned to the scene")
      .def_readonly("summary", &PyRefineResult::summary, "dict: status, counts, ground-truth scores, seconds")
      .def_readonly("report", &PyRefineResult::report, "dict: the same JSON as the CLI's report.json")
      .def_readonly("status", &PyRefineResult::status)
      .def_readonly("message", &PyRefineResult::message)
      .def("__repr__", [](const PyRefineResult& r) { return "<al_refine.RefineResult " + r.status + ": " + r.message + ">"; });
  static const std::string doc = RefineDoc();
  const RefineDefaults d;
  m.def("refine", &Refine, py::arg("scene"), py::arg("removed"), py::arg("method") = d.method, py::arg("k") = d.k,
        py::arg("delta") = d.delta, py::arg("solver") = d.solver, py::kw_only(), py::arg("features") = py::none(),
        py::arg("labels") = py::none(), py::arg("object_id") = py::none(), py::arg("removed_is") = py::none(),
        py::arg("out") = py::none(), py::arg("solver_options") = py::none(), doc.c_str());
}

}  // namespace al::python
