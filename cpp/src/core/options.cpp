#include "mereo/core/options.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mereo {

const char* to_string(FieldKind k) {
  switch (k) {
    case FieldKind::Bool: return "bool";
    case FieldKind::Int: return "int";
    case FieldKind::Real: return "float";
    case FieldKind::Text: return "str";
    case FieldKind::Choice: return "choice";
    case FieldKind::List: return "list";
  }
  return "?";
}

std::string to_text(const FieldValue& v) {
  std::ostringstream s;
  s << std::boolalpha;
  if (const auto* l = std::get_if<std::vector<std::string>>(&v)) {
    for (std::size_t i = 0; i < l->size(); ++i) s << (i ? "," : "") << (*l)[i];
  } else {
    std::visit([&](const auto& x) {
      if constexpr (!std::is_same_v<std::decay_t<decltype(x)>, std::vector<std::string>>) s << x;
    }, v);
  }
  return s.str();
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream list(text);
  for (std::string n; std::getline(list, n, ',');) {
    const auto b = n.find_first_not_of(" \t"), e = n.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(n.substr(b, e - b + 1));
  }
  return out;
}

namespace detail {

void throw_option_error(const std::string& name, const std::string& what) {
  throw InputError("option '" + name + "': " + what);
}

FieldValue checked_value(const std::string& name, FieldKind kind, double min, double max,
                         const std::vector<std::string>& choices, const FieldValue& v) {
  auto type_error = [&]() {
    throw_option_error(name, std::string("must be ") + (kind == FieldKind::Choice ? "str" : to_string(kind)) +
                                 ", got '" + to_text(v) + "'");
  };
  auto in_range = [&](double x, const FieldValue& out) {
    if (!(x >= min && x <= max)) {
      std::ostringstream s;
      s << to_text(out) << " is outside its range [" << min << ", " << max << "]";
      throw_option_error(name, s.str());
    }
    return out;
  };
  switch (kind) {
    case FieldKind::Bool:
      if (!std::holds_alternative<bool>(v)) type_error();
      return v;
    case FieldKind::Int:
      if (const auto* i = std::get_if<long long>(&v)) return in_range(double(*i), v);
      if (const auto* d = std::get_if<double>(&v); d && *d == std::floor(*d) && std::abs(*d) < 9e15)
        return in_range(*d, FieldValue(static_cast<long long>(*d)));
      type_error();
      break;
    case FieldKind::Real:
      if (const auto* d = std::get_if<double>(&v)) return in_range(*d, v);
      if (const auto* i = std::get_if<long long>(&v)) return in_range(double(*i), FieldValue(double(*i)));
      type_error();
      break;
    case FieldKind::Text:
      if (!std::holds_alternative<std::string>(v)) type_error();
      return v;
    case FieldKind::Choice: {
      const auto* s = std::get_if<std::string>(&v);
      if (!s) type_error();
      if (std::find(choices.begin(), choices.end(), *s) == choices.end()) {
        std::string list;
        for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
        throw_option_error(name, "unknown " + name + " '" + *s + "' (known: " + list + ")");
      }
      return v;
    }
    case FieldKind::List:
      if (const auto* s = std::get_if<std::string>(&v)) return FieldValue(split_list(*s));
      if (!std::holds_alternative<std::vector<std::string>>(v)) type_error();
      return v;
  }
  type_error();
  return v;
}

}  // namespace detail
}  // namespace mereo
