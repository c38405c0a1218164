// mereo/core/options.hpp: an options struct described once, so that its graph node and its
// Python function take the same options with the same defaults.
//
// A description lists a struct's option fields: name, kind, allowed range or choices, and a
// one-line doc, each bound to its member. A default is never written in it: it is the member's
// value in a default-constructed struct (describe()). Members that are not options (images
// that come from ports, internal state) are simply not described.
//
//   struct BlurOptions {
//     int radius = 2;
//     double sigma = 1.5;
//     static const Fields<BlurOptions>& fields();
//   };
//   inline const Fields<BlurOptions>& BlurOptions::fields() {
//     static const Fields<BlurOptions> f = {
//         field("radius", &BlurOptions::radius, 1, 10, "window half-size, pixels"),
//         field("sigma", &BlurOptions::sigma, 0.1, 20, "spatial sigma, pixels"),
//     };
//     return f;
//   }
//
// A struct that holds another one describes it with nested(&Outer::inner, Inner::fields(),
// "prefix_") joined to its own fields by concat(). Graph nodes build their option lists from a
// description (cpp/src/nodes/options.hpp), the Python functions their keyword arguments
// (cpp/pybind/options.hpp).
#pragma once

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "mereo/core/error.hpp"

namespace mereo {

/// What values a field takes: Bool; Int (any integer member); Real (double); Text (a string);
/// Choice (an enum, by name); List (a vector, by its items' names; "a,b" in graph files).
enum class FieldKind { Bool, Int, Real, Text, Choice, List };
/// "bool", "int", "float", "str", "choice", "list".
const char* to_string(FieldKind k);

/// A field's value whatever the member's type: bool (Bool), long long (Int), double (Real),
/// string (Text, Choice), vector of strings (List).
using FieldValue = std::variant<bool, long long, double, std::string, std::vector<std::string>>;

/// The value as text: true/false, numbers as iostreams print them, list items comma-separated.
std::string to_text(const FieldValue& v);
/// "a, b,c" -> {"a", "b", "c"}: items trimmed, empty ones dropped.
std::vector<std::string> split_list(const std::string& text);

/// One described field of options struct T.
template <class T>
struct Field {
  std::string name;
  FieldKind kind = FieldKind::Real;
  double min = -1e300;                ///< Int and Real: allowed range (inclusive)
  double max = 1e300;
  std::vector<std::string> choices;   ///< Choice: the allowed names
  std::string doc;                    ///< one line
  std::function<FieldValue(const T&)> get;
  /// Sets the member from a value of the kind's own alternative (assign() converts and checks).
  std::function<void(T&, const FieldValue&)> set;
};
template <class T>
using Fields = std::vector<Field<T>>;

/// A field with its default, as graph nodes and Python list it.
struct FieldInfo {
  std::string name;
  FieldKind kind = FieldKind::Real;
  FieldValue default_value;
  double min = -1e300;
  double max = 1e300;
  std::vector<std::string> choices;
  std::string doc;
};

namespace detail {
/// v converted to the kind's alternative (an integer for a Real, an integral real for an Int,
/// a comma-separated text for a List) and checked against range and choices; throws
/// InputError naming option `name`.
FieldValue checked_value(const std::string& name, FieldKind kind, double min, double max,
                         const std::vector<std::string>& choices, const FieldValue& v);
/// Throws InputError: "option 'name': what".
[[noreturn]] void throw_option_error(const std::string& name, const std::string& what);
}  // namespace detail

/// The fields with their defaults, read from a default-constructed T.
template <class T>
std::vector<FieldInfo> describe(const Fields<T>& fields = T::fields()) {
  const T def{};
  std::vector<FieldInfo> out;
  for (const auto& f : fields) out.push_back({f.name, f.kind, f.get(def), f.min, f.max, f.choices, f.doc});
  return out;
}

/// Sets field `f` of `o` to `v`; throws InputError naming the option when `v` is of another
/// type, out of range, not an allowed choice or not a known list item.
template <class T>
void assign(T& o, const Field<T>& f, const FieldValue& v) {
  const FieldValue x = detail::checked_value(f.name, f.kind, f.min, f.max, f.choices, v);
  try {
    f.set(o, x);
  } catch (const std::exception& e) {  // a list item's from-text conversion
    detail::throw_option_error(f.name, e.what());
  }
}

/// Throws InputError naming the option when a field of `o` is out of its range or choices (for
/// options set in C++, which no node or Python function checked).
template <class T>
void check_options(const T& o, const Fields<T>& fields = T::fields()) {
  T copy = o;
  for (const auto& f : fields) assign(copy, f, f.get(o));
}

/// The names of the fields, comma-separated (for error messages).
template <class T>
std::string field_names(const Fields<T>& fields) {
  std::string s;
  for (const auto& f : fields) s += (s.empty() ? "" : ", ") + f.name;
  return s;
}

// ---- building a description --------------------------------------------------------------

/// A Bool field.
template <class T>
Field<T> field(std::string name, bool T::*m, std::string doc) {
  return {std::move(name), FieldKind::Bool, 0, 0, {}, std::move(doc),
          [m](const T& o) { return FieldValue(o.*m); },
          [m](T& o, const FieldValue& v) { o.*m = std::get<bool>(v); }};
}

/// An Int field: any integer member (int, std::size_t, a std::uint64_t seed), in [min, max].
template <class T, class I, std::enable_if_t<std::is_integral_v<I> && !std::is_same_v<I, bool>, int> = 0>
Field<T> field(std::string name, I T::*m, double min, double max, std::string doc) {
  return {std::move(name), FieldKind::Int, min, max, {}, std::move(doc),
          [m](const T& o) { return FieldValue(static_cast<long long>(o.*m)); },
          [m](T& o, const FieldValue& v) { o.*m = static_cast<I>(std::get<long long>(v)); }};
}

/// A Real field in [min, max].
template <class T>
Field<T> field(std::string name, double T::*m, double min, double max, std::string doc) {
  return {std::move(name), FieldKind::Real, min, max, {}, std::move(doc),
          [m](const T& o) { return FieldValue(o.*m); },
          [m](T& o, const FieldValue& v) { o.*m = std::get<double>(v); }};
}

/// A Text field (any string).
template <class T>
Field<T> field(std::string name, std::string T::*m, std::string doc) {
  return {std::move(name), FieldKind::Text, 0, 0, {}, std::move(doc),
          [m](const T& o) { return FieldValue(o.*m); },
          [m](T& o, const FieldValue& v) { o.*m = std::get<std::string>(v); }};
}

/// A Choice field: an enum member, by the names in `values`.
template <class T, class E>
Field<T> choice(std::string name, E T::*m, std::vector<std::pair<std::string, E>> values, std::string doc) {
  std::vector<std::string> names;
  for (const auto& [n, e] : values) names.push_back(n);
  return {std::move(name), FieldKind::Choice, 0, 0, std::move(names), std::move(doc),
          [m, values](const T& o) {
            for (const auto& [n, e] : values)
              if (e == o.*m) return FieldValue(n);
            return FieldValue(std::string("?"));
          },
          [m, values](T& o, const FieldValue& v) {
            for (const auto& [n, e] : values)
              if (n == std::get<std::string>(v)) o.*m = e;
          }};
}

/// A List field: a vector member whose items convert to text with `to_text` and back with
/// `from_text` (which throws for an unknown name).
template <class T, class E, class ToText, class FromText>
Field<T> list(std::string name, std::vector<E> T::*m, ToText to_text, FromText from_text, std::string doc) {
  return {std::move(name), FieldKind::List, 0, 0, {}, std::move(doc),
          [m, to_text](const T& o) {
            std::vector<std::string> out;
            for (const auto& e : o.*m) out.emplace_back(to_text(e));
            return FieldValue(std::move(out));
          },
          [m, from_text](T& o, const FieldValue& v) {
            std::vector<E> items;
            for (const auto& s : std::get<std::vector<std::string>>(v)) items.push_back(from_text(s));
            o.*m = std::move(items);
          }};
}

/// A List field of strings.
template <class T>
Field<T> list(std::string name, std::vector<std::string> T::*m, std::string doc) {
  auto same = [](const std::string& s) { return s; };
  return list(std::move(name), m, same, same, std::move(doc));
}

/// The fields of a nested options struct (member `m`), their names prefixed by `prefix`; the
/// defaults are those of the outer struct's default value.
template <class T, class S>
Fields<T> nested(S T::*m, const Fields<S>& inner, const std::string& prefix = "") {
  Fields<T> out;
  for (const auto& f : inner) {
    out.push_back({prefix + f.name, f.kind, f.min, f.max, f.choices, f.doc,
                   [m, get = f.get](const T& o) { return get(o.*m); },
                   [m, set = f.set](T& o, const FieldValue& v) { set(o.*m, v); }});
  }
  return out;
}

/// a's fields, then b's.
template <class T>
Fields<T> concat(Fields<T> a, const Fields<T>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace mereo
