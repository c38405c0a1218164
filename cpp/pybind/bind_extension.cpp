// The extension layer: back-projection and intrinsics fitting.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/extension/projection.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using mereo::py_util::from_numpy;
using mereo::py_util::to_numpy;

void bind_extension(py::module_& m) {
  namespace ext = mereo::extension;
  m.def("back_project",
        [](const mereo::Frame& f) {
          mereo::Cloud cloud;
          {
            py::gil_scoped_release release;
            cloud = ext::back_project(f);
          }
          return to_numpy(cloud);
        },
        py::arg("frame"), "The frame's organized XYZ cloud, (H, W, 3) float32, NaN where missing.");
  m.def("back_project",
        [](py::handle depth, const mereo::Intrinsics& K) {
          const auto d = from_numpy<float, 1>(depth, "depth");
          mereo::Cloud cloud;
          {
            py::gil_scoped_release release;
            cloud = ext::back_project(d, K);
          }
          return to_numpy(cloud);
        },
        py::arg("depth"), py::arg("intrinsics"), "Back-projects an (H, W) depth image in metres.");
  m.def("fit_intrinsics",
        [](py::handle cloud) {
          double residual = 0;
          const auto K = ext::fit_intrinsics(from_numpy<float, 3>(cloud, "cloud"), &residual);
          return py::make_tuple(K, residual);
        },
        py::arg("cloud"), "Least-squares pinhole fit to an organized cloud: (Intrinsics, max residual px).");
}
