// The synthetic scene renderer and its ground truth.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/synthetic/scene.hpp"
#include "numpy_view.hpp"
#include "options.hpp"

namespace py = pybind11;
using mereo::py_util::to_numpy;

void bind_synthetic(py::module_& m) {
  namespace syn = mereo::synthetic;
  namespace pu = mereo::py_util;
  using O = syn::SceneOptions;

  // every option of the description (SceneOptions::fields()) is a checked attribute and a
  // keyword of the constructor; the intrinsics are not described
  pu::register_options<O>("SceneOptions");
  py::class_<O> options(
      m, "SceneOptions",
      pu::takes_options(m, "SceneOptions", "SceneOptions",
                        "Options of the synthetic tabletop scene: SceneOptions(depth_model='stereo', ...) or "
                        "attribute by attribute.")
          .c_str());
  options.def(py::init([](const py::kwargs& kw) { return pu::options_from_kwargs<O>("SceneOptions", kw); }))
      .def_readwrite("intrinsics", &O::intrinsics)
      .def("__repr__", [](const O& o) {
        std::string s;
        const O def{};
        for (const auto& f : O::fields())
          if (f.get(o) != f.get(def))
            s += (s.empty() ? "" : ", ") + f.name + "=" +
                 (f.kind == mereo::FieldKind::Text || f.kind == mereo::FieldKind::Choice ? "'" + mereo::to_text(f.get(o)) + "'"
                  : f.kind == mereo::FieldKind::Bool ? (std::get<bool>(f.get(o)) ? "True" : "False")
                                                     : mereo::to_text(f.get(o)));
        return "SceneOptions(" + s + ")";
      });
  for (const auto& f : O::fields()) {
    auto set = [&f](O& o, const py::object& v) {
      mereo::assign(o, f, pu::field_value_from_python("SceneOptions", f.name, f.kind, v));
    };
    // typed getters (the stubs show the types); the setter checks type and range
    switch (f.kind) {
      case mereo::FieldKind::Bool:
        options.def_property(f.name.c_str(), [&f](const O& o) { return std::get<bool>(f.get(o)); }, set, f.doc.c_str());
        break;
      case mereo::FieldKind::Int:
        options.def_property(f.name.c_str(), [&f](const O& o) { return std::get<long long>(f.get(o)); }, set, f.doc.c_str());
        break;
      case mereo::FieldKind::Real:
        options.def_property(f.name.c_str(), [&f](const O& o) { return std::get<double>(f.get(o)); }, set, f.doc.c_str());
        break;
      default:
        options.def_property(f.name.c_str(), [&f](const O& o) { return std::get<std::string>(f.get(o)); }, set, f.doc.c_str());
    }
  }

  py::class_<syn::GroundTruth>(m, "GroundTruth",
                               "Exact ground truth: clean depth, analytic normals, object and part labels.")
      .def_property_readonly("depth", [](const syn::GroundTruth& t) { return to_numpy(t.depth); })
      .def_property_readonly("normals", [](const syn::GroundTruth& t) { return to_numpy(t.normals); })
      .def_property_readonly("objects", [](const syn::GroundTruth& t) { return to_numpy(t.objects); })
      .def_property_readonly("parts", [](const syn::GroundTruth& t) { return to_numpy(t.parts); })
      .def_property_readonly("camera_pose",
                             [](const syn::GroundTruth& t) { return Eigen::Matrix4d(t.camera_pose.matrix()); });

  py::class_<syn::SyntheticFrame>(m, "SyntheticFrame", "A rendered frame and its ground truth.")
      .def_readonly("frame", &syn::SyntheticFrame::frame)
      .def_readonly("truth", &syn::SyntheticFrame::truth)
      .def("truth_json", [](const syn::SyntheticFrame& f) { return syn::truth_to_json(f); },
           "Objects, parts (camera and world frames), intrinsics and pose as JSON text.");

  py::class_<syn::Scene>(m, "Scene", "A generated scene (world frame: z up, origin at the table top centre).")
      .def_readonly("seed", &syn::Scene::seed)
      .def_property_readonly("models", [](const syn::Scene& s) {
        std::vector<std::string> out;
        for (const auto& o : s.objects) out.push_back(o.model);
        return out;
      })
      .def_readonly("camera_distance", &syn::Scene::camera_distance)
      .def_readonly("camera_elevation_deg", &syn::Scene::camera_elevation_deg);
  m.def("generate_scene", &syn::generate_scene, py::arg("seed"), py::arg("options") = syn::SceneOptions{},
        "The scene of `seed` (deterministic).");
  m.def("render_view",
        [](const syn::Scene& s, int index, const syn::SceneOptions& o) {
          return syn::render(s, syn::orbit_view(s, index, o), o, index);
        },
        py::arg("scene"), py::arg("index"), py::arg("options") = syn::SceneOptions{},
        py::call_guard<py::gil_scoped_release>(), "Frame `index` of the camera's orbit around the table.");
  m.def("render",
        [](std::uint64_t seed, const syn::SceneOptions& o) { return syn::render(seed, o); },
        py::arg("seed"), py::arg("options") = syn::SceneOptions{}, py::call_guard<py::gil_scoped_release>(),
        "Renders the first frame of the scene of `seed`.");
  m.def("render_sequence",
        [](std::uint64_t seed, int frames, const syn::SceneOptions& o) { return syn::render_sequence(seed, frames, o); },
        py::arg("seed"), py::arg("frames"), py::arg("options") = syn::SceneOptions{},
        py::call_guard<py::gil_scoped_release>(), "`frames` frames with the camera orbiting the table.");
}
