// Core types: Intrinsics and Frame. Images are NumPy views that share the C++ buffers.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/core/frame.hpp"
#include "mereo/extension/projection.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using mereo::py_util::from_numpy;
using mereo::py_util::to_numpy;

void bind_core(py::module_& m) {
  using mereo::Frame;
  using mereo::Intrinsics;

  py::class_<Intrinsics>(m, "Intrinsics", "Pinhole intrinsics in pixels: u = fx x/z + cx, v = fy y/z + cy.")
      .def(py::init<>())
      .def(py::init([](double fx, double fy, double cx, double cy) { return Intrinsics{fx, fy, cx, cy}; }),
           py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"))
      .def_readwrite("fx", &Intrinsics::fx)
      .def_readwrite("fy", &Intrinsics::fy)
      .def_readwrite("cx", &Intrinsics::cx)
      .def_readwrite("cy", &Intrinsics::cy)
      .def_static("parse", &Intrinsics::parse, py::arg("text"), "From 'fx,fy,cx,cy'.")
      .def("__eq__", &Intrinsics::operator==)
      .def("__repr__", [](const Intrinsics& K) { return "Intrinsics(" + K.to_string() + ")"; });

  py::class_<Frame>(m, "Frame",
                    "An RGB-D frame. color (H,W,3) uint8 RGB, depth (H,W) float32 metres with NaN where "
                    "missing, cloud (H,W,3) float32 XYZ; the arrays share memory with the frame.")
      .def(py::init<>())
      .def_readwrite("id", &Frame::id)
      .def_readwrite("source", &Frame::source)
      .def_readwrite("timestamp", &Frame::timestamp)
      .def_readwrite("intrinsics", &Frame::intrinsics)
      .def_property_readonly("shape", [](const Frame& f) { return py::make_tuple(f.rows(), f.cols()); })
      .def_property(
          "color", [](const Frame& f) { return to_numpy(f.color); },
          [](Frame& f, py::handle a) { f.color = from_numpy<std::uint8_t, 3>(a, "color"); })
      .def_property(
          "depth", [](const Frame& f) { return to_numpy(f.depth); },
          [](Frame& f, py::handle a) { f.depth = from_numpy<float, 1>(a, "depth"); })
      .def_property(
          "cloud",
          [](Frame& f) {
            // Computed once from depth and intrinsics when the source gave no cloud.
            if (f.cloud.empty() && !f.depth.empty()) f.cloud = mereo::extension::back_project(f);
            return to_numpy(f.cloud);
          },
          [](Frame& f, py::handle a) { f.cloud = from_numpy<float, 3>(a, "cloud"); })
      .def_property(
          "labels", [](const Frame& f) { return to_numpy(f.labels); },
          [](Frame& f, py::handle a) { f.labels = from_numpy<std::uint32_t, 1>(a, "labels"); })
      .def_property(
          "pose",
          [](const Frame& f) -> py::object {
            if (!f.pose) return py::none();
            return py::cast(Eigen::Matrix4d(f.pose->matrix()));
          },
          [](Frame& f, py::object m) {
            if (m.is_none()) return f.pose.reset();
            mereo::Pose P;
            P.matrix() = m.cast<Eigen::Matrix4d>();
            f.pose = P;
          },
          "Camera-to-world 4x4 matrix, or None.")
      .def_readwrite("gravity_aligned", &Frame::gravity_aligned,
                     "The pose's world z points against gravity (False for 7-Scenes/3DMatch poses: the "
                     "support plane then finds 'up' from the data).")
      .def("validate", &Frame::validate, "Raises ValueError if the images disagree in size.")
      .def("_buffer_address", [](const Frame& f, const std::string& which) -> std::uintptr_t {
        if (which == "color") return reinterpret_cast<std::uintptr_t>(f.color.data());
        if (which == "depth") return reinterpret_cast<std::uintptr_t>(f.depth.data());
        if (which == "cloud") return reinterpret_cast<std::uintptr_t>(f.cloud.data());
        if (which == "labels") return reinterpret_cast<std::uintptr_t>(f.labels.data());
        throw py::value_error("unknown image '" + which + "'");
      }, "Address of an image's C++ buffer (for tests of zero-copy sharing).")
      .def("__repr__", [](const Frame& f) {
        return "<mereo.Frame '" + f.id + "' " + std::to_string(f.cols()) + "x" + std::to_string(f.rows()) +
               " from " + f.source + ">";
      });
}
