// The signal layer: per-image preprocessing (an edge-preserving depth filter).
#include <pybind11/pybind11.h>

#include "mereo/signal/depth_filter.hpp"
#include "numpy_view.hpp"
#include "options.hpp"

namespace py = pybind11;
namespace pu = mereo::py_util;

void bind_signal(py::module_& m) {
  namespace sig = mereo::signal;
  pu::register_options<sig::DepthFilterOptions>("DepthFilterOptions");
  const std::string doc = pu::takes_options(
      m, "filter_depth", "DepthFilterOptions",
      "Edge-preserving bilateral filter of depth (metres, NaN = missing): Gaussian weights on pixel distance and on "
      "depth difference (sigma_depth * z^2); depth jumps stay sharp, holes stay holes.");
  m.def("filter_depth",
        [](const mereo::Frame& f, py::kwargs options) {
          const auto o = pu::options_from_kwargs<sig::DepthFilterOptions>("filter_depth", options);
          py::gil_scoped_release release;
          return sig::filter_depth(f, o);
        },
        py::arg("frame"), "The frame with its depth (and its own cloud, if any) filtered; see the array overload.");
  m.def("filter_depth",
        [](py::handle depth, py::kwargs options) {
          const auto o = pu::options_from_kwargs<sig::DepthFilterOptions>("filter_depth", options);
          const auto d = mereo::py_util::from_numpy<float, 1>(depth, "depth");
          mereo::DepthImage out;
          {
            py::gil_scoped_release release;
            out = sig::filter_depth(d, o);
          }
          return mereo::py_util::to_numpy(out);
        },
        py::arg("depth"), doc.c_str());
}
