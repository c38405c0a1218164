// mereo._mereo: the one PYBIND11_MODULE; each module binds itself in its own file.
#include <pybind11/pybind11.h>

#include "mereo/core/error.hpp"
#include "mereo/nodes/builtin.hpp"
#include "errors.hpp"

namespace py = pybind11;

void bind_core(py::module_& m);
void bind_io(py::module_& m);
void bind_signal(py::module_& m);
void bind_extension(py::module_& m);
void bind_synthetic(py::module_& m);
void bind_features(py::module_& m);
void bind_knowledge(py::module_& m);
void bind_graph(py::module_& m);
void bind_testing(py::module_& m);
void bind_options(py::module_& m);

PYBIND11_MODULE(_mereo, m) {
  m.doc() = "mereo's C++ core; import the names from the mereo package instead.";
  m.attr("__version__") = MEREO_VERSION_TEXT;
  mereo::nodes::register_builtin();  // the port types and node kinds, before bind_graph lists them
  mereo::py_util::register_error<mereo::InputError>(m, "InputError", PyExc_ValueError);
  bind_core(m);
  auto io = m.def_submodule("io", "Frame sources and writers (the hardware layer).");
  bind_io(io);
  auto sig = m.def_submodule("signal", "Per-image depth preprocessing (the signal layer).");
  bind_signal(sig);
  auto ext = m.def_submodule("extension", "Depth to XYZ, normals, support plane (the extension layer).");
  bind_extension(ext);
  auto syn = m.def_submodule("synthetic", "The built-in tabletop scene renderer with exact ground truth.");
  bind_synthetic(syn);
  auto ft = m.def_submodule("features", "RANSAC primitives of organized clouds (the feature layer).");
  bind_features(ft);
  auto kn = m.def_submodule("knowledge", "Object models, segments and matching (the object layer).");
  bind_knowledge(kn);
  bind_graph(m);  // Graph, FrameQueue, errors at the top level; node kinds in mereo._mereo.nodes
  auto testing = m.def_submodule("_testing", "For mereo's own tests only.");
  bind_testing(testing);
  bind_options(m);  // mereo.options_of (after the modules that register their options)
}
