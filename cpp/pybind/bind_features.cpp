// The feature layer: RANSAC primitives of an organized cloud with normals; lines and arcs of the
// colour image.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/features/edges.hpp"
#include "mereo/features/legs.hpp"
#include "mereo/features/patches.hpp"
#include "mereo/features/primitives.hpp"
#include "mereo/features/regions.hpp"
#include "numpy_view.hpp"
#include "options.hpp"

namespace py = pybind11;
namespace pu = mereo::py_util;
using mereo::py_util::from_numpy;

void bind_features(py::module_& m) {
  namespace ft = mereo::features;
  pu::register_options<ft::DetectOptions>("DetectOptions");
  pu::register_options<ft::RegionOptions>("RegionOptions");
  pu::register_options<ft::PatchOptions>("PatchOptions");
  pu::register_options<ft::LegOptions>("LegOptions");
  pu::register_options<ft::EdgePrimitiveOptions>("EdgePrimitiveOptions");
  const std::string edges_doc = pu::takes_options(
      m, "detect_edge_primitives", "EdgePrimitiveOptions",
      "Lines and elliptical arcs of a frame's colour image (mereo.knowledge.Segment objects of class line and arc: "
      "pixel coordinates, the colours on both sides, and where the depth allows the 3-D segment or circle; .pixels "
      "holds each one's edge pixels). Also takes an (H, W, 3) uint8 colour array and an optional (H, W, 3) cloud.");
  m.def("detect_edge_primitives",
        [](const mereo::Frame& f, py::kwargs options) {
          const auto o = pu::options_from_kwargs<ft::EdgePrimitiveOptions>("detect_edge_primitives", options);
          py::gil_scoped_release release;
          return ft::detect_edge_primitives(f, o);
        },
        py::arg("frame"), edges_doc.c_str());
  m.def("detect_edge_primitives",
        [](py::handle color, py::object cloud, py::kwargs options) {
          const auto o = pu::options_from_kwargs<ft::EdgePrimitiveOptions>("detect_edge_primitives", options);
          const auto c = from_numpy<std::uint8_t, 3>(color, "color");
          mereo::Cloud xyz;
          if (!cloud.is_none()) xyz = from_numpy<float, 3>(cloud, "cloud");
          py::gil_scoped_release release;
          return ft::fit_edge_primitives(mereo::signal::detect_edges(c, o.edges), c, xyz.empty() ? nullptr : &xyz, o);
        },
        py::arg("color"), py::arg("cloud") = py::none(), edges_doc.c_str());
  m.def("detect_primitives",
        [](py::handle cloud, py::handle normals, py::object roi, py::object color, py::object unfiltered,
           py::kwargs options) {
          auto o = pu::options_from_kwargs<ft::DetectOptions>("detect_primitives", options);
          if (!roi.is_none()) o.roi = from_numpy<std::uint8_t, 1>(roi, "roi");
          if (!unfiltered.is_none()) o.unfiltered = from_numpy<float, 3>(unfiltered, "unfiltered");
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          const auto n = from_numpy<float, 3>(normals, "normals");
          mereo::ColorImage col;
          if (!color.is_none()) col = from_numpy<std::uint8_t, 3>(color, "color");
          py::gil_scoped_release release;
          return ft::detect_primitives(c, n, o, col.empty() ? nullptr : &col);
        },
        py::arg("cloud"), py::arg("normals"), py::arg("roi") = py::none(), py::arg("color") = py::none(),
        py::arg("unfiltered") = py::none(),
        pu::takes_options(
            m, "detect_primitives", "DetectOptions",
            "Planes, cylinders, spheres and tori of an (H, W, 3) cloud with (H, W, 3) normals, largest first "
            "(mereo.knowledge.Segment objects; .pixels holds each one's inlier pixel indices). `roi`: an (H, W) "
            "mask of the pixels to use. `unfiltered`: the (H, W, 3) points of the unfiltered depth when the "
            "cloud's was filtered; cylinders and spheres are then measured on them (smoothing flattens curved "
            "surfaces).")
            .c_str());
  m.def("planar_patches",
        [](py::handle cloud, py::handle normals, py::object up, py::object color, py::kwargs options) {
          const auto o = pu::options_from_kwargs<ft::PatchOptions>("planar_patches", options);
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          const auto n = from_numpy<float, 3>(normals, "normals");
          std::optional<Eigen::Vector3d> u;
          if (!up.is_none()) u = up.cast<Eigen::Vector3d>();
          mereo::ColorImage col;
          if (!color.is_none()) col = from_numpy<std::uint8_t, 3>(color, "color");
          py::gil_scoped_release release;
          return ft::planar_patches(c, n, o, u ? &*u : nullptr, col.empty() ? nullptr : &col);
        },
        py::arg("cloud"), py::arg("normals"), py::arg("up") = py::none(), py::arg("color") = py::none(),
        pu::takes_options(m, "planar_patches", "PatchOptions",
                          "Bounded planar patches of an (H, W, 3) cloud with (H, W, 3) normals, largest first "
                          "(mereo.knowledge.Segment objects of class patch; .pixels holds each one's pixels). "
                          "`up`: the direction against gravity in the camera frame (upright patches then have a "
                          "horizontal u_axis).")
            .c_str());
  m.def("find_legs",
        [](py::handle cloud, const std::vector<mereo::Segment>& segments, const Eigen::Vector3d& up, double floor_d,
           py::kwargs options) {
          const auto o = pu::options_from_kwargs<ft::LegOptions>("find_legs", options);
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          py::gil_scoped_release release;
          return ft::find_legs(c, segments, up, floor_d, o);
        },
        py::arg("cloud"), py::arg("segments"), py::arg("up"), py::arg("floor_d"),
        pu::takes_options(m, "find_legs", "LegOptions",
                          "The legs under the level patches among `segments` (planar_patches) of an (H, W, 3) "
                          "cloud: thin upright supports as segments of class cylinder (axis up). `up`, `floor_d`: "
                          "the floor's normal and offset (up . x + floor_d is a point's height above it).")
            .c_str());
  m.def("label_image",
        [](const std::vector<mereo::Segment>& segments, int rows, int cols) {
          py::array_t<int> out({rows, cols});
          std::fill(out.mutable_data(), out.mutable_data() + out.size(), -1);
          for (std::size_t k = 0; k < segments.size(); ++k)
            for (int i : segments[k].pixels)
              if (i >= 0 && i < rows * cols) out.mutable_data()[i] = int(k);
          return out;
        },
        py::arg("segments"), py::arg("rows"), py::arg("cols"),
        "An (rows, cols) int32 image of the index of the segment owning each pixel (-1: none): the inlier masks.");
}
