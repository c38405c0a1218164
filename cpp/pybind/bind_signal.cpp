// The signal layer: per-image preprocessing (an edge-preserving depth filter, edge chains).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "mereo/signal/depth_filter.hpp"
#include "mereo/signal/edges.hpp"
#include "mereo/signal/register.hpp"
#include "numpy_view.hpp"
#include "options.hpp"

namespace py = pybind11;
namespace pu = mereo::py_util;

void bind_signal(py::module_& m) {
  namespace sig = mereo::signal;
  m.def("register_depth",
        [](py::handle depth, const mereo::Intrinsics& depth_intrinsics, const Eigen::Matrix4d& to_color,
           const mereo::Intrinsics& color_intrinsics, int rows, int cols) {
          mereo::DepthCamera cam;
          cam.intrinsics = depth_intrinsics;
          cam.to_color.matrix() = to_color;
          const auto d = mereo::py_util::from_numpy<float, 1>(depth, "depth");
          mereo::DepthImage out;
          {
            py::gil_scoped_release release;
            out = sig::register_depth(d, cam, color_intrinsics, rows, cols);
          }
          return mereo::py_util::to_numpy(out);
        },
        py::arg("depth"), py::arg("depth_intrinsics"), py::arg("to_color"), py::arg("color_intrinsics"), py::arg("rows"),
        py::arg("cols"),
        "The depth image (metres, NaN = missing) of a camera with depth_intrinsics, as the colour camera with "
        "color_intrinsics and a rows x cols image sees it; to_color: the 4x4 transform from the depth camera's frame to "
        "the colour camera's. NaN where no point lands (OpenCV's rgbd::registerDepth).");
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
  pu::register_options<sig::EdgeOptions>("EdgeOptions");
  m.def("detect_edges",
        [](py::handle color, py::kwargs options) {
          const auto o = pu::options_from_kwargs<sig::EdgeOptions>("detect_edges", options);
          const auto c = mereo::py_util::from_numpy<std::uint8_t, 3>(color, "color");
          std::vector<sig::EdgeChain> chains;
          {
            py::gil_scoped_release release;
            chains = sig::detect_edges(c, o);
          }
          py::list out;
          for (const auto& ch : chains) {
            py::array_t<float> a({py::ssize_t(ch.points.size()), py::ssize_t(2)});
            auto w = a.mutable_unchecked<2>();
            for (std::size_t k = 0; k < ch.points.size(); ++k) w(k, 0) = ch.points[k].x(), w(k, 1) = ch.points[k].y();
            out.append(a);
          }
          return out;
        },
        py::arg("color"),
        pu::takes_options(m, "detect_edges", "EdgeOptions",
                          "The edge chains of an (H, W, 3) uint8 RGB image, longest first: a list of (N, 2) float32 "
                          "arrays of (x, y) image coordinates, sub-pixel, in the order the points are connected (Edge "
                          "Drawing, OpenCV ximgproc).")
            .c_str());
}
