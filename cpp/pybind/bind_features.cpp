// The feature layer: RANSAC primitives of an organized cloud with normals.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/features/primitives.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using mereo::py_util::from_numpy;

void bind_features(py::module_& m) {
  namespace ft = mereo::features;
  m.def("detect_primitives",
        [](py::handle cloud, py::handle normals, std::uint64_t seed, std::vector<std::string> classes,
           double epsilon, double normal_deviation_deg, int min_support, int min_support_torus, int max_primitives,
           bool handles_near_cylinders, py::object roi, py::object color, py::object unfiltered,
           bool fit_along_rays) {
          ft::DetectOptions o;
          o.seed = seed;
          o.classes.clear();
          for (const auto& c : classes) o.classes.push_back(mereo::primitive_class(c));
          o.epsilon = epsilon, o.normal_deviation_deg = normal_deviation_deg;
          o.min_support = min_support, o.min_support_torus = min_support_torus;
          o.max_primitives = max_primitives, o.handles_near_cylinders = handles_near_cylinders;
          o.fit_along_rays = fit_along_rays;
          if (!roi.is_none()) o.roi = from_numpy<std::uint8_t, 1>(roi, "roi");
          if (!unfiltered.is_none()) o.unfiltered = from_numpy<float, 3>(unfiltered, "unfiltered");
          const auto c = from_numpy<float, 3>(cloud, "cloud");
          const auto n = from_numpy<float, 3>(normals, "normals");
          mereo::ColorImage col;
          if (!color.is_none()) col = from_numpy<std::uint8_t, 3>(color, "color");
          py::gil_scoped_release release;
          return ft::detect_primitives(c, n, o, col.empty() ? nullptr : &col);
        },
        py::arg("cloud"), py::arg("normals"), py::arg("seed") = 0,
        py::arg("classes") = std::vector<std::string>{"plane", "cylinder", "sphere", "torus"},
        py::arg("epsilon") = 0.006, py::arg("normal_deviation_deg") = 25.0, py::arg("min_support") = 250,
        py::arg("min_support_torus") = 80, py::arg("max_primitives") = 64, py::arg("handles_near_cylinders") = true,
        py::arg("roi") = py::none(), py::arg("color") = py::none(), py::arg("unfiltered") = py::none(),
        py::arg("fit_along_rays") = true,
        "Planes, cylinders, spheres and tori of an (H, W, 3) cloud with (H, W, 3) normals, largest first "
        "(mereo.knowledge.Segment objects; .pixels holds each one's inlier pixel indices). `unfiltered`: "
        "the (H, W, 3) points of the unfiltered depth when the cloud's was filtered; cylinders and spheres "
        "are then measured on them (smoothing flattens curved surfaces). `fit_along_rays`: cylinders and spheres "
        "fitted along the rays (depth noise lies along them), else by geometric distance.");
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
