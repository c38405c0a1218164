// mereo.options_of: the options of an options struct, a Python function or a node kind, with
// their defaults (one description each: mereo/core/options.hpp), for users and for the test
// that checks that the nodes and the functions agree.
#include <map>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mereo/cognitive/odometry.hpp"
#include "mereo/cognitive/tracking.hpp"
#include "mereo/graph/node.hpp"
#include "options.hpp"

namespace py = pybind11;

namespace mereo::py_util {

namespace {

std::map<std::string, std::vector<FieldInfo>>& structs() {
  static std::map<std::string, std::vector<FieldInfo>> s;
  return s;
}
/// "mereo._mereo.features.detect_primitives" -> "DetectOptions"
std::map<std::string, std::string>& functions() {
  static std::map<std::string, std::string> f;
  return f;
}

const char* python_type(FieldKind k) {
  switch (k) {
    case FieldKind::Bool: return "bool";
    case FieldKind::Int: return "int";
    case FieldKind::Real: return "float";
    case FieldKind::Text:
    case FieldKind::Choice: return "str";
    case FieldKind::List: return "list";
  }
  return "?";
}

py::object to_python(const FieldValue& v) {
  return std::visit([](const auto& x) -> py::object { return py::cast(x); }, v);
}

py::dict info_dict(const char* type, py::object def, bool ranged, double min, double max,
                   const std::vector<std::string>& choices, const std::string& name, const std::string& doc) {
  py::dict d;
  d["name"] = name;
  d["type"] = type;
  d["default"] = def;
  d["min"] = ranged ? py::object(py::float_(min)) : py::object(py::none());
  d["max"] = ranged ? py::object(py::float_(max)) : py::object(py::none());
  d["choices"] = choices;
  d["doc"] = doc;
  return d;
}

py::list struct_options(const std::vector<FieldInfo>& fields) {
  py::list out;
  for (const auto& f : fields) {
    const bool ranged = f.kind == FieldKind::Int || f.kind == FieldKind::Real;
    out.append(info_dict(python_type(f.kind), to_python(f.default_value), ranged, f.min, f.max, f.choices, f.name, f.doc));
  }
  return out;
}

py::list node_options(const graph::NodeSpec& spec) {
  py::list out;
  for (const auto& o : spec.options) {
    const bool ranged = o.type == graph::OptionType::Int || o.type == graph::OptionType::Double;
    py::object def = std::visit([](const auto& x) -> py::object { return py::cast(x); }, o.default_value);
    out.append(info_dict(graph::to_string(o.type), def, ranged, o.min, o.max, o.choices, o.name, o.doc));
  }
  return out;
}

std::string known() {
  std::string s;
  for (const auto& [name, f] : structs()) s += (s.empty() ? "" : ", ") + name;
  for (const auto& spec : graph::node_specs())
    if (!spec.options.empty()) s += ", " + spec.kind;
  return s;
}

py::list options_of(const py::object& what, const std::string& nodes_module) {
  if (py::isinstance<py::str>(what)) {
    const auto name = what.cast<std::string>();
    if (auto it = structs().find(name); it != structs().end()) return struct_options(it->second);
    for (const auto& spec : graph::node_specs())
      if (spec.kind == name) return node_options(spec);
    throw py::value_error("'" + name + "' is no options struct or node kind (known: " + known() + ")");
  }
  const auto module = py::str(py::getattr(what, "__module__", py::str(""))).cast<std::string>();
  const auto name = py::str(py::getattr(what, "__name__", py::str(""))).cast<std::string>();
  if (module == nodes_module) return node_options(graph::node_spec(name));
  if (auto it = functions().find(module + "." + name); it != functions().end())
    return struct_options(structs().at(it->second));
  throw py::value_error(py::repr(what).cast<std::string>() + " takes no described options");
}

}  // namespace

void register_options(const std::string& name, std::vector<FieldInfo> fields) { structs()[name] = std::move(fields); }

std::string takes_options(const py::module_& m, const std::string& function, const std::string& struct_name,
                          const std::string& doc) {
  const auto it = structs().find(struct_name);
  if (it == structs().end()) throw std::logic_error("options struct " + struct_name + " is not registered");
  functions()[m.attr("__name__").cast<std::string>() + "." + function] = struct_name;
  std::string out = doc + "\n\nOptions (keyword arguments; mereo.options_of lists them):\n";
  for (const auto& f : it->second) {
    out += "    " + f.name + " (" + python_type(f.kind) + ", default " + to_text(f.default_value);
    if (f.kind == FieldKind::Int || f.kind == FieldKind::Real)
      out += ", " + to_text(f.min) + ".." + to_text(f.max);
    if (!f.choices.empty()) {
      out += ", one of";
      for (const auto& c : f.choices) out += " " + c;
    }
    out += "): " + f.doc + "\n";
  }
  return out;
}

FieldValue field_value_from_python(const std::string& function, const std::string& name, FieldKind kind,
                                   const py::handle& h) {
  auto wrong = [&]() -> FieldValue {
    throw py::type_error(function + "(): option '" + name + "' must be " + python_type(kind) + ", got " +
                         py::str(py::type::of(h)).cast<std::string>());
  };
  const auto type = py::type::of(h);
  const auto type_name = type.attr("__name__").cast<std::string>();
  const bool is_bool = py::isinstance<py::bool_>(h) ||  // or NumPy's (numpy.bool_, numpy.bool in NumPy 2)
                       (py::str(py::getattr(type, "__module__", py::str(""))).cast<std::string>() == "numpy" &&
                        (type_name == "bool_" || type_name == "bool"));
  switch (kind) {
    case FieldKind::Bool:
      return is_bool ? FieldValue(h.cast<bool>()) : wrong();
    case FieldKind::Int:
    case FieldKind::Real:
      if (is_bool || py::isinstance<py::str>(h)) return wrong();
      if (py::hasattr(h, "__index__")) return FieldValue(h.cast<long long>());  // int, NumPy integers
      try {
        return FieldValue(h.cast<double>());  // checked by assign(): an Int takes integral reals only
      } catch (const py::cast_error&) {
        return wrong();
      }
    case FieldKind::Text:
    case FieldKind::Choice:
      return py::isinstance<py::str>(h) ? FieldValue(h.cast<std::string>()) : wrong();
    case FieldKind::List:
      if (py::isinstance<py::str>(h)) return FieldValue(h.cast<std::string>());
      if (!py::isinstance<py::sequence>(h)) return wrong();
      try {
        return FieldValue(h.cast<std::vector<std::string>>());
      } catch (const py::cast_error&) {
        return wrong();
      }
  }
  return wrong();
}

}  // namespace mereo::py_util

void bind_options(py::module_& m) {
  namespace pu = mereo::py_util;
  // the structs of the nodes that have no Python function of their own (the others are
  // registered by their modules' bind files)
  pu::register_options<mereo::cognitive::TrackOptions>("TrackOptions");
  pu::register_options<mereo::cognitive::OdometryOptions>("OdometryOptions");
  const std::string nodes_module = m.attr("nodes").attr("__name__").cast<std::string>();
  m.def("options_of", [nodes_module](const py::object& what) { return pu::options_of(what, nodes_module); },
        py::arg("what"),
        "The options of an options struct ('DetectOptions'), a function that takes keyword options "
        "(mereo.features.detect_primitives) or a node kind ('detect_primitives', mereo.nodes.detect_primitives): "
        "a list of {'name', 'type', 'default', 'min', 'max', 'choices', 'doc'}.");
}
