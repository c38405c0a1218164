// The extension layer: back-projection, intrinsics fitting, normals, the support plane.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "converters.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "numpy_view.hpp"
#include "options.hpp"

namespace py = pybind11;
using mereo::py_util::from_numpy;
using mereo::py_util::to_numpy;
namespace pu = mereo::py_util;

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

  pu::register_options<ext::NormalOptions>("NormalOptions");
  m.def("estimate_normals",
        [](py::handle cloud, py::kwargs options) {
          const auto o = pu::options_from_kwargs<ext::NormalOptions>("estimate_normals", options);
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          mereo::NormalMap n;
          {
            py::gil_scoped_release release;
            n = ext::estimate_normals(c, o);
          }
          return to_numpy(n);  // a view of the C++ result, no copy
        },
        py::arg("cloud"),
        pu::takes_options(m, "estimate_normals", "NormalOptions",
                          "Per-pixel unit normals of an (H, W, 3) cloud: (H, W, 3) float32, towards the camera, NaN "
                          "where undefined. Windows never cross a depth jump larger than depth_change_factor * z "
                          "(growing as z^2 beyond noise_depth metres).")
            .c_str());

  py::class_<ext::SupportPlane>(m, "SupportPlane",
                                "The table plane: normal (towards the camera), d (normal . x + d = 0), "
                                "polygon (N, 3), inliers and roi masks, world_from_camera (4x4, z up).")
      .def_property_readonly("normal", [](const ext::SupportPlane& p) { return p.normal; })
      .def_readonly("d", &ext::SupportPlane::d)
      .def_readonly("inlier_count", &ext::SupportPlane::inlier_count)
      .def_readonly("rms", &ext::SupportPlane::rms)
      .def_readonly("noise", &ext::SupportPlane::noise)
      .def_property_readonly("polygon",
                             [](const ext::SupportPlane& p) {
                               Eigen::MatrixX3d out(p.polygon.size(), 3);
                               for (std::size_t i = 0; i < p.polygon.size(); ++i) out.row(i) = p.polygon[i];
                               return out;
                             })
      .def_readonly("borders", &ext::SupportPlane::borders,
                    "per polygon vertex, the image borders its pixel lies on (bits: 1 left, 2 right, 4 top, 8 bottom)")
      .def_property_readonly("inliers", [](const ext::SupportPlane& p) { return to_numpy(p.inliers); })
      .def_property_readonly("roi", [](const ext::SupportPlane& p) { return to_numpy(p.roi); })
      .def_property_readonly("world_from_camera",
                             [](const ext::SupportPlane& p) { return Eigen::Matrix4d(p.world_from_camera.matrix()); })
      .def("height", [](const ext::SupportPlane& p, const Eigen::Vector3d& x) { return p.height(x); },
           py::arg("point"), "Signed height of a camera-frame point above the plane, metres.")
      .def("__repr__", [](const ext::SupportPlane& p) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "<mereo.SupportPlane n=(%.3f, %.3f, %.3f) d=%.3f, %zu inliers>",
                      p.normal.x(), p.normal.y(), p.normal.z(), p.d, p.inlier_count);
        return std::string(buf);
      });
  mereo::py_util::register_converter(
      "SupportPlane", {[](const mereo::graph::Value& v) { return py::cast(v.get<ext::SupportPlane>()); },
                       [](const py::handle& h) {
                         return mereo::graph::Value::make<ext::SupportPlane>(h.cast<ext::SupportPlane>());
                       }});

  pu::register_options<ext::SupportPlaneOptions>("SupportPlaneOptions");
  m.def("find_support_plane",
        [](py::handle cloud, py::handle normals, std::optional<Eigen::Vector3d> up, py::kwargs options) {
          auto o = pu::options_from_kwargs<ext::SupportPlaneOptions>("find_support_plane", options);
          o.up = up;
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          const auto n = from_numpy<float, 3>(normals, "normals");
          py::gil_scoped_release release;
          return ext::find_support_plane(c, n, o);
        },
        py::arg("cloud"), py::arg("normals"), py::arg("up") = py::none(),
        pu::takes_options(m, "find_support_plane", "SupportPlaneOptions",
                          "The dominant horizontal plane under the objects (the table) with its polygon, the mask "
                          "of the points above it (roi) and a world frame with z up. `up`: the camera-frame "
                          "direction against gravity when known. Raises InputError when there is no such plane.")
            .c_str());
}
