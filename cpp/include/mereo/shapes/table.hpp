// mereo/shapes/table.hpp: the shape table, the one list of primitive classes. A class is one file
// pair (mereo/shapes/<name>.hpp, cpp/src/shapes/<name>.cpp, see shape.hpp for what it gives) and
// one entry in `Geometry` below; detection, matching, JSON, drawing, tracking and Python reach it
// through this list. The order is the order in which the bottom-up search draws candidates.
#pragma once

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "mereo/shapes/arc.hpp"
#include "mereo/shapes/cone.hpp"
#include "mereo/shapes/cylinder.hpp"
#include "mereo/shapes/line.hpp"
#include "mereo/shapes/patch.hpp"
#include "mereo/shapes/plane.hpp"
#include "mereo/shapes/region.hpp"
#include "mereo/shapes/sphere.hpp"
#include "mereo/shapes/torus.hpp"

namespace mereo {

/// A primitive's class and its parameter block: the list of classes, one entry per line.
using Geometry = std::variant<
    shapes::Plane,
    shapes::Cylinder,
    shapes::Sphere,
    shapes::Torus,
    shapes::Line,
    shapes::Arc,
    shapes::Cone,
    shapes::Region,
    shapes::Patch>;

namespace shapes::detail {
template <class S, class V>
struct index_of;
template <class S, class... T>
struct index_of<S, std::variant<T...>> {
  static constexpr std::size_t value = [] {
    constexpr bool same[] = {std::is_same_v<S, T>...};
    for (std::size_t i = 0; i < sizeof...(T); ++i)
      if (same[i]) return i;
    return sizeof...(T);
  }();
  static_assert(value < sizeof...(T), "not a class of the shape table (mereo/shapes/table.hpp)");
};
}  // namespace shapes::detail

/// A primitive class: an entry of the shape table.
class PrimitiveClass {
 public:
  constexpr PrimitiveClass() = default;
  template <class S>
  static constexpr PrimitiveClass of() {
    return PrimitiveClass(shapes::detail::index_of<S, Geometry>::value);
  }
  static constexpr std::size_t count() { return std::variant_size_v<Geometry>; }
  /// The class of entry `index` (0 .. count() - 1).
  static PrimitiveClass at(std::size_t index);
  constexpr std::size_t index() const { return index_; }
  /// The shape's name ("cylinder").
  const char* name() const;
  /// A default-constructed parameter block of this class.
  Geometry make() const;
  /// Points of a RANSAC minimal set (0: not detected bottom-up), a thin part.
  int sample_size() const;
  bool thin() const;
  friend constexpr bool operator==(PrimitiveClass a, PrimitiveClass b) { return a.index_ == b.index_; }
  friend constexpr bool operator!=(PrimitiveClass a, PrimitiveClass b) { return a.index_ != b.index_; }

 private:
  constexpr explicit PrimitiveClass(std::size_t i) : index_(i) {}
  std::size_t index_ = 0;
};

/// The name of a class, e.g. "cylinder" (the JSON output's "class").
const char* to_string(PrimitiveClass c);
/// The class of a name; throws std::invalid_argument listing the known names.
PrimitiveClass primitive_class(const std::string& name);
/// Every class, in the table's order, and their names.
std::vector<PrimitiveClass> primitive_classes();
std::vector<std::string> primitive_class_names();
/// The class-specific attribute names of all classes (shapes' `attributes`), each once.
std::vector<std::string> shape_attribute_names();

}  // namespace mereo
