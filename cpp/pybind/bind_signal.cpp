// The signal layer: per-image preprocessing (an edge-preserving depth filter).
#include <pybind11/pybind11.h>

#include "mereo/signal/depth_filter.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;

void bind_signal(py::module_& m) {
  namespace sig = mereo::signal;
  auto options = [](int radius, double sigma_space, double sigma_depth, double factor) {
    sig::DepthFilterOptions o;
    o.radius = radius;
    o.sigma_space = sigma_space;
    o.sigma_depth = sigma_depth;
    o.depth_change_factor = factor;
    return o;
  };
  const char* doc =
      "Edge-preserving bilateral filter of depth (metres, NaN = missing): Gaussian weights on pixel "
      "distance and on depth difference (sigma_depth * z^2); depth jumps stay sharp, holes stay holes.";
  m.def("filter_depth",
        [options](const mereo::Frame& f, int radius, double sigma_space, double sigma_depth, double factor) {
          py::gil_scoped_release release;
          return sig::filter_depth(f, options(radius, sigma_space, sigma_depth, factor));
        },
        py::arg("frame"), py::arg("radius") = 2, py::arg("sigma_space") = 1.5, py::arg("sigma_depth") = 0.004,
        py::arg("depth_change_factor") = 0.02, "The frame with its depth (and its own cloud, if any) filtered; see the array overload.");
  m.def("filter_depth",
        [options](py::handle depth, int radius, double sigma_space, double sigma_depth, double factor) {
          const auto d = mereo::py_util::from_numpy<float, 1>(depth, "depth");
          mereo::DepthImage out;
          {
            py::gil_scoped_release release;
            out = sig::filter_depth(d, options(radius, sigma_space, sigma_depth, factor));
          }
          return mereo::py_util::to_numpy(out);
        },
        py::arg("depth"), py::arg("radius") = 2, py::arg("sigma_space") = 1.5, py::arg("sigma_depth") = 0.004,
        py::arg("depth_change_factor") = 0.02, doc);
}
