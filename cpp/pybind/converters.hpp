// Conversions of graph values (mereo::graph::Value) to and from Python, by port type name.
// Each bind_<module>.cpp registers the types it owns (bind_graph.cpp registers the core ones).
#pragma once

#include <functional>
#include <string>

#include <pybind11/pybind11.h>

#include "mereo/graph/value.hpp"

namespace mereo::py_util {

namespace py = pybind11;

struct Converter {
  std::function<py::object(const graph::Value&)> to_python;
  std::function<graph::Value(const py::handle&)> from_python;
};

/// Registers how values of port type `type_name` cross into and out of Python.
void register_converter(const std::string& type_name, Converter c);
/// The value as a Python object (a NumPy view for images; its describe() text if the type
/// has no converter).
py::object value_to_python(const graph::Value& v);
/// A Python object as a value of port type `type_name`; raises TypeError if it cannot be.
graph::Value value_from_python(const std::string& type_name, const py::handle& obj);

}  // namespace mereo::py_util
