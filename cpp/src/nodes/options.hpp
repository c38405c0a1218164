// A node's options from an options struct's description (mereo/core/options.hpp): its option
// list, and the struct filled from the validated values, with no field written twice.
//
//   s.options = options_of<signal::DepthFilterOptions>();
//   s.make = [](const graph::Options& o) {
//     const auto f = options_from<signal::DepthFilterOptions>(o);
//     ...
#pragma once

#include <vector>

#include "mereo/core/options.hpp"
#include "mereo/graph/node.hpp"

namespace mereo::nodes {

/// The node option of a described field: Bool, Int and Real as such, Text as a string, Choice as
/// a string with its choices, List as a comma-separated string.
graph::OptionSpec option_spec(const FieldInfo& f);
/// A validated option's value as the field value of `kind`.
FieldValue field_value(const graph::Options& o, const std::string& name, FieldKind kind);

/// The option list of a node whose options are the fields of T.
template <class T>
std::vector<graph::OptionSpec> options_of(const Fields<T>& fields = T::fields()) {
  std::vector<graph::OptionSpec> out;
  for (const auto& f : describe(fields)) out.push_back(option_spec(f));
  return out;
}

/// T filled from a node's validated options (every described field; the others keep their
/// defaults). Throws InputError naming the option for a bad list item.
template <class T>
T options_from(const graph::Options& o, const Fields<T>& fields = T::fields()) {
  T out{};
  for (const auto& f : fields) assign(out, f, field_value(o, f.name, f.kind));
  return out;
}

}  // namespace mereo::nodes
