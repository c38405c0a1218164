// Frame sources and writers.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/io/io.hpp"
#include "mereo/io/visualize.hpp"
#include "numpy_view.hpp"

namespace py = pybind11;
using mereo::py_util::from_numpy;
using mereo::py_util::to_numpy;

namespace {

mereo::io::ReadOptions read_options(const py::object& intrinsics, double depth_scale, int frames,
                                    const py::object& noise, const py::object& distractors,
                                    const py::object& scene, const std::string& depth_format) {
  mereo::io::ReadOptions o;
  o.depth_format = mereo::io::depth_format(depth_format);
  if (py::isinstance<mereo::Intrinsics>(intrinsics))
    o.intrinsics = intrinsics.cast<mereo::Intrinsics>();
  else if (!intrinsics.is_none()) {
    const std::string text = py::str(intrinsics).cast<std::string>();
    o.intrinsics = mereo::io::read_intrinsics(text);
    o.depth_camera = mereo::io::read_depth_camera(text);  // a file's second camera, if it has one
  }
  o.depth_scale = depth_scale;
  o.synthetic_frames = frames;
  if (!scene.is_none()) o.synthetic = scene.cast<mereo::synthetic::SceneOptions>();
  if (!noise.is_none()) o.synthetic.noise = noise.cast<bool>();
  // None: the scene's; False: none; True or "beside": tori beside some jars; "leaning": rings
  // leaning on jars
  if (py::isinstance<py::str>(distractors)) {
    const auto kind = distractors.cast<std::string>();
    if (kind != "beside" && kind != "leaning")
      throw py::value_error("distractors: '" + kind + "' is not one of False, True, 'beside', 'leaning'");
    o.synthetic.distractors = kind == "beside";
    o.synthetic.ambiguous_distractors = kind == "leaning";
  } else if (!distractors.is_none()) {
    o.synthetic.distractors = distractors.cast<bool>();
    o.synthetic.ambiguous_distractors = false;
  }
  return o;
}

}  // namespace

void bind_io(py::module_& m) {
  namespace io = mereo::io;
  using io::Sequence;

  py::class_<Sequence>(m, "Sequence", "Frames loaded lazily, in order: len(seq), seq[i], iteration.")
      .def("__len__", &Sequence::size)
      .def("__getitem__",
           [](const Sequence& s, py::ssize_t i) {
             if (i < 0) i += py::ssize_t(s.size());
             if (i < 0 || std::size_t(i) >= s.size()) throw py::index_error("frame index out of range");
             py::gil_scoped_release release;
             return s.load(std::size_t(i));
           })
      .def_property_readonly("ids", [](const Sequence& s) {
        std::vector<std::string> ids;
        for (std::size_t i = 0; i < s.size(); ++i) ids.push_back(s.at(i).id);
        return ids;
      })
      .def_property_readonly("sources", [](const Sequence& s) {
        std::vector<std::string> out;
        for (std::size_t i = 0; i < s.size(); ++i) out.push_back(s.at(i).source);
        return out;
      });

  const char* kOptionsDoc =
      "intrinsics: Intrinsics, 'fx,fy,cx,cy' or a JSON file (its \"depth_camera\": depth from a second camera, "
      "registered to the colour camera); depth_scale: depth units per metre "
      "(0 = the format's default); depth_format: 'units', or 'sun3d' / 'nyu-raw' for those datasets' 16-bit "
      "depth (the files do not say); frames, scene, noise, distractors: for synthetic:SEED (scene: a "
      "mereo.synthetic.SceneOptions; noise and distractors, when given, override its: distractors False, True or "
      "'beside' for handle-like tori beside some jars, 'leaning' for rings leaning on jars).";
  m.def(
      "open",
      [](py::object inputs, py::object intrinsics, double depth_scale, int frames, py::object noise,
         py::object distractors, py::object scene, const std::string& depth_format) {
        std::vector<std::string> list;
        if (py::isinstance<py::str>(inputs) || py::hasattr(inputs, "__fspath__"))
          list.push_back(py::str(inputs));
        else
          for (auto item : inputs) list.push_back(py::str(item));
        const auto o = read_options(intrinsics, depth_scale, frames, noise, distractors, scene, depth_format);
        return io::open(list, o);
      },
      py::arg("inputs"), py::kw_only(), py::arg("intrinsics") = py::none(), py::arg("depth_scale") = 0.0,
      py::arg("frames") = 1, py::arg("noise") = py::none(), py::arg("distractors") = py::none(),
      py::arg("scene") = py::none(), py::arg("depth_format") = "units",
      (std::string("Opens files, folders or 'synthetic:SEED' as a Sequence. ") + kOptionsDoc).c_str());
  m.def(
      "read",
      [](py::object input, py::object intrinsics, double depth_scale, py::object noise, py::object distractors,
         py::object scene, const std::string& depth_format) {
        const auto o = read_options(intrinsics, depth_scale, 1, noise, distractors, scene, depth_format);
        const std::string path = py::str(input);
        py::gil_scoped_release release;
        return io::read(path, o);
      },
      py::arg("input"), py::kw_only(), py::arg("intrinsics") = py::none(), py::arg("depth_scale") = 0.0,
      py::arg("noise") = py::none(), py::arg("distractors") = py::none(), py::arg("scene") = py::none(),
      py::arg("depth_format") = "units",
      (std::string("The first frame of a .pcd file, a PNG pair, a folder, a TUM folder or 'synthetic:SEED'. ") +
       kOptionsDoc).c_str());
  m.def("write_pcd", [](py::object path, const mereo::Frame& f) { io::write_pcd(py::str(path), f); },
        py::arg("path"), py::arg("frame"), "Writes a binary-compressed organized PCD (xyz, rgba, label).");
  m.def("write_png_pair",
        [](py::object dir, const std::string& name, const mereo::Frame& f, double scale) {
          return io::write_png_pair(py::str(dir), name, f, scale);
        },
        py::arg("dir"), py::arg("name"), py::arg("frame"), py::arg("depth_scale") = 1000.0,
        "Writes DIR/NAME_rgb.png, DIR/NAME_depth.png (16-bit) and DIR/intrinsics.json.");
  m.def("read_intrinsics", [](const std::string& s) { return io::read_intrinsics(s); }, py::arg("text_or_path"));

  m.def("colorize_depth", [](py::handle d) { return to_numpy(io::colorize_depth(from_numpy<float, 1>(d, "depth"))); },
        py::arg("depth"), "Depth (H, W) metres as an (H, W, 3) uint8 false-colour image.");
  m.def("colorize_normals",
        [](py::handle n) { return to_numpy(io::colorize_normals(from_numpy<float, 3>(n, "normals"))); },
        py::arg("normals"), "Normals (H, W, 3) as colours (n + 1) / 2, black where missing.");
  m.def("colorize_labels",
        [](py::handle l) { return to_numpy(io::colorize_labels(from_numpy<std::uint32_t, 1>(l, "labels"))); },
        py::arg("labels"), "Integer labels (H, W) as distinct colours, 0 black.");
  m.def("write_image",
        [](py::object path, py::handle rgb) { io::write_image(py::str(path), from_numpy<std::uint8_t, 3>(rgb, "image")); },
        py::arg("path"), py::arg("image"), "Writes an (H, W, 3) uint8 RGB image (PNG by extension).");
  m.def("hstack",
        [](const std::vector<py::object>& images, int gap) {
          std::vector<mereo::ColorImage> list;
          for (const auto& im : images) list.push_back(from_numpy<std::uint8_t, 3>(im, "image"));
          return to_numpy(io::hstack(list, gap));
        },
        py::arg("images"), py::arg("gap") = 4, "RGB images side by side.");
  m.def("draw_objects",
        [](py::handle rgb, const mereo::Intrinsics& K,
           const std::vector<std::pair<std::string, std::vector<mereo::Segment>>>& objects,
           const std::vector<std::pair<std::string, std::array<int, 4>>>& boxes) {
          std::vector<io::DrawnObject> list;
          for (const auto& [label, parts] : objects) list.push_back({label, parts, std::nullopt});
          for (const auto& [label, box] : boxes) list.push_back({label, {}, box});
          return to_numpy(io::draw_objects(from_numpy<std::uint8_t, 3>(rgb, "image"), K, list));
        },
        py::arg("image"), py::arg("intrinsics"), py::arg("objects"), py::arg("boxes") = std::vector<std::pair<std::string, std::array<int, 4>>>{},
        "The image with each (label, [Segment, ...]) drawn: projected part outlines and the label; "
        "each (label, (u0, v0, u1, v1)) of `boxes` (objects without parts: unknown ones) as a grey box.");
}
