// al_refine.Camera and load_cameras: pinhole cameras in the INRIA/OpenCV convention
// (X_cam = R X_world + t; x right, y down, z forward), as the library reads them.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "al/io/cameras.hpp"
#include "python/common.hpp"

namespace al::python {

void BindCameras(py::module_& m) {
  py::class_<Camera>(m, "Camera", "A pinhole camera: X_cam = R @ X_world + t (INRIA/OpenCV convention).")
      .def(py::init([](std::string name, int width, int height, double fx, double fy, const Eigen::Matrix3d& R,
                       const Eigen::Vector3d& t) {
             Camera c;
             c.name = std::move(name);
             c.width = width;
             c.height = height;
             c.fx = fx;
             c.fy = fy;
             c.cx = width / 2.0;
             c.cy = height / 2.0;
             c.R = R;
             c.t = t;
             return c;
           }),
           py::arg("name"), py::arg("width"), py::arg("height"), py::arg("fx"), py::arg("fy"), py::arg("R"),
           py::arg("t"), "A centred pinhole camera (world -> camera rotation R and translation t).")
      .def_readwrite("name", &Camera::name)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height)
      .def_readwrite("fx", &Camera::fx)
      .def_readwrite("fy", &Camera::fy)
      .def_readwrite("cx", &Camera::cx)
      .def_readwrite("cy", &Camera::cy)
      .def_readwrite("R", &Camera::R)
      .def_readwrite("t", &Camera::t)
      .def("__repr__", [](const Camera& c) {
        return "<al_refine.Camera '" + c.name + "' " + std::to_string(c.width) + "x" + std::to_string(c.height) + ">";
      });
  m.def(
      "load_cameras",
      [](const std::string& path, const std::string& views) {
        CameraLoadResult r;
        {
          py::gil_scoped_release release;
          r = ReadCameras(path);
        }
        for (const auto& w : r.warnings) PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1);
        return SelectViews(r.cameras, views);
      },
      py::arg("path"), py::arg("views") = "all",
      "Cameras from INRIA cameras.json, a COLMAP text folder or al-refine's JSON list; views: 'all' or "
      "comma-separated names.");
}

}  // namespace al::python
