#include "nodes/options.hpp"

namespace mereo::nodes {

graph::OptionSpec option_spec(const FieldInfo& f) {
  using graph::OptionType;
  graph::OptionSpec s;
  s.name = f.name;
  s.doc = f.doc;
  switch (f.kind) {
    case FieldKind::Bool:
      s.type = OptionType::Bool, s.default_value = std::get<bool>(f.default_value);
      break;
    case FieldKind::Int:
      s.type = OptionType::Int, s.default_value = std::get<long long>(f.default_value);
      s.min = f.min, s.max = f.max;
      break;
    case FieldKind::Real:
      s.type = OptionType::Double, s.default_value = std::get<double>(f.default_value);
      s.min = f.min, s.max = f.max;
      break;
    case FieldKind::Text:
    case FieldKind::Choice:
      s.type = OptionType::String, s.default_value = std::get<std::string>(f.default_value);
      s.choices = f.choices;
      break;
    case FieldKind::List:
      s.type = OptionType::String, s.default_value = to_text(f.default_value);
      break;
  }
  return s;
}

FieldValue field_value(const graph::Options& o, const std::string& name, FieldKind kind) {
  switch (kind) {
    case FieldKind::Bool: return o.get_bool(name);
    case FieldKind::Int: return o.get_int(name);
    case FieldKind::Real: return o.get_double(name);
    case FieldKind::Text:
    case FieldKind::Choice:
    case FieldKind::List: return o.get_string(name);  // a List's text is split by assign()
  }
  return o.get_string(name);
}

}  // namespace mereo::nodes
