// The Python module al_refine (docs/python.md): the library's refine, render, evaluate and synth
// for NumPy arrays, with the library's errors as Python exceptions.
#include "python/common.hpp"

PYBIND11_MODULE(al_refine, m) {
  m.doc() = R"(al-refine for Python: refine the set of Gaussians a removal method deleted from a 3DGS scene,
render the scene on the CPU and score the removal with the paper's metrics.

    import al_refine as al
    s = al.synth("room", 20000, seed=1)
    r = al.refine(s.scene, s.removed["fgs"], method="fgs", labels=s.labels, object_id=s.target_id)

Errors raise al_refine.Error subclasses carrying the CLI's exit code: UsageError (1),
BadInputError (2), EmptyGraphError (3), InternalError (4).)";
  m.attr("__version__") = "0.1.0";
  al::python::BindErrors(m);
  al::python::BindScene(m);
  al::python::BindCameras(m);
  al::python::BindRefine(m);
  al::python::BindRender(m);
  al::python::BindEval(m);
  al::python::BindSynth(m);
}
