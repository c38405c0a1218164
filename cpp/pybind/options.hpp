// The keyword options of the Python functions, from the options structs' descriptions
// (mereo/core/options.hpp): the same names, defaults and ranges as the graph nodes'.
//
//   pu::register_options<sig::DepthFilterOptions>("DepthFilterOptions");
//   m.def("filter_depth",
//         [](const Frame& f, py::kwargs kw) {
//           const auto o = pu::options_from_kwargs<sig::DepthFilterOptions>("filter_depth", kw);
//           ...
//         },
//         py::arg("frame"), pu::takes_options(m, "filter_depth", "DepthFilterOptions", doc).c_str());
#pragma once

#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "mereo/core/options.hpp"

namespace mereo::py_util {

namespace py = pybind11;

/// Records the options of struct `name` for mereo.options_of(name).
void register_options(const std::string& name, std::vector<FieldInfo> fields);
template <class T>
void register_options(const std::string& name) {
  register_options(name, describe<T>());
}

/// Records that `function` of module `m` takes the keyword options of the registered struct
/// `struct_name` (mereo.options_of(m.function) lists them); returns `doc` followed by the
/// options with their types, defaults, ranges and docs.
std::string takes_options(const py::module_& m, const std::string& function, const std::string& struct_name,
                          const std::string& doc);

/// A keyword argument as the value of a field of `kind`: bool; int; float (or int); str; for a
/// list, a sequence of str or one comma-separated str. Raises TypeError naming the option.
FieldValue field_value_from_python(const std::string& function, const std::string& name, FieldKind kind,
                                   const py::handle& h);

/// T with the fields named in `kw` set and the others at their defaults. An unknown name raises
/// TypeError listing the options; a value out of range or not allowed raises InputError.
template <class T>
T options_from_kwargs(const std::string& function, const py::kwargs& kw, const Fields<T>& fields = T::fields()) {
  T o{};
  for (auto item : kw) {
    const auto name = item.first.cast<std::string>();
    const Field<T>* f = nullptr;
    for (const auto& x : fields)
      if (x.name == name) f = &x;
    if (!f)
      throw py::type_error(function + "() got an unexpected keyword argument '" + name + "' (its options: " +
                           field_names(fields) + ")");
    assign(o, *f, field_value_from_python(function, name, f->kind, item.second));
  }
  return o;
}

}  // namespace mereo::py_util
