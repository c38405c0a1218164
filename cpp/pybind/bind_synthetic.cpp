// The synthetic scene renderer and its ground truth.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/synthetic/scene.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using mereo::py_util::to_numpy;

void bind_synthetic(py::module_& m) {
  namespace syn = mereo::synthetic;

  py::class_<syn::SceneOptions>(m, "SceneOptions", "Options of the synthetic tabletop scene.")
      .def(py::init<>())
      .def_readwrite("width", &syn::SceneOptions::width)
      .def_readwrite("height", &syn::SceneOptions::height)
      .def_readwrite("intrinsics", &syn::SceneOptions::intrinsics)
      .def_readwrite("noise", &syn::SceneOptions::noise)
      .def_readwrite("distractors", &syn::SceneOptions::distractors)
      .def_readwrite("ambiguous_distractors", &syn::SceneOptions::ambiguous_distractors)
      .def_readwrite("tapered_cups", &syn::SceneOptions::tapered_cups,
                     "one or two tapered cups (cone bodies, 4-10 degrees) join the objects")
      .def_readwrite("min_objects", &syn::SceneOptions::min_objects)
      .def_readwrite("max_objects", &syn::SceneOptions::max_objects)
      .def_readwrite("min_distance", &syn::SceneOptions::min_distance)
      .def_readwrite("max_distance", &syn::SceneOptions::max_distance)
      .def_readwrite("min_elevation_deg", &syn::SceneOptions::min_elevation_deg)
      .def_readwrite("max_elevation_deg", &syn::SceneOptions::max_elevation_deg)
      .def_readwrite("orbit_step_deg", &syn::SceneOptions::orbit_step_deg);

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
