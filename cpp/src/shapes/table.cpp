// The shape table's generic functions (mereo/shapes/table.hpp) and the helpers of shape.hpp.
#include "mereo/shapes/table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace mereo {
namespace {

template <std::size_t... I>
Geometry make_at(std::size_t i, std::index_sequence<I...>) {
  Geometry out;
  ((i == I ? (out = std::variant_alternative_t<I, Geometry>{}, 0) : 0), ...);
  return out;
}

}  // namespace

PrimitiveClass PrimitiveClass::at(std::size_t index) {
  if (index >= count()) throw std::out_of_range("primitive class index out of range");
  return PrimitiveClass(index);
}

Geometry PrimitiveClass::make() const { return make_at(index_, std::make_index_sequence<count()>()); }

namespace {
/// The classes' static traits, gathered once (the detector asks for them per candidate).
struct Traits {
  const char* name;
  int sample_size;
  bool thin;
};
template <std::size_t... I>
std::array<Traits, sizeof...(I)> gather(std::index_sequence<I...>) {
  return {Traits{std::variant_alternative_t<I, Geometry>::name, std::variant_alternative_t<I, Geometry>::sample_size,
                 std::variant_alternative_t<I, Geometry>::thin}...};
}
const Traits& traits(std::size_t i) {
  static const auto table = gather(std::make_index_sequence<PrimitiveClass::count()>());
  return table[i];
}
}  // namespace

const char* PrimitiveClass::name() const { return traits(index_).name; }
int PrimitiveClass::sample_size() const { return traits(index_).sample_size; }
bool PrimitiveClass::thin() const { return traits(index_).thin; }

const char* to_string(PrimitiveClass c) { return c.name(); }

std::vector<PrimitiveClass> primitive_classes() {
  std::vector<PrimitiveClass> out;
  for (std::size_t i = 0; i < PrimitiveClass::count(); ++i) out.push_back(PrimitiveClass::at(i));
  return out;
}

std::vector<std::string> primitive_class_names() {
  std::vector<std::string> out;
  for (auto c : primitive_classes()) out.push_back(c.name());
  return out;
}

std::vector<std::string> shape_attribute_names() {
  std::vector<std::string> out;
  for (auto c : primitive_classes())
    std::visit(
        [&](const auto& s) {
          for (const char* n : std::decay_t<decltype(s)>::attributes)
            if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
        },
        c.make());
  return out;
}

PrimitiveClass primitive_class(const std::string& name) {
  for (auto c : primitive_classes())
    if (name == c.name()) return c;
  std::string known;
  for (const auto& n : primitive_class_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown primitive class '" + name + "' (known: " + known + ")");
}

namespace shapes {

std::vector<Eigen::Vector3d> circle(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius,
                                    int samples) {
  const Eigen::Vector3d e1 = axis.normalized().unitOrthogonal(), e2 = axis.normalized().cross(e1);
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < samples; ++k) {
    const double a = 2 * M_PI * k / samples;
    out.push_back(centre + radius * (std::cos(a) * e1 + std::sin(a) * e2));
  }
  return out;
}

void frustum_outline(const Eigen::Vector3d& point, const Eigen::Vector3d& axis, double height, double r0, double r1,
                     Outline& out) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d top = point + 0.5 * height * a, bottom = point - 0.5 * height * a;
  out.lines.push_back(circle(top, a, r1));
  out.lines.push_back(circle(bottom, a, r0));
  // silhouette: where the wall's normal is perpendicular to the ray to the axis
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const double phi = std::atan2(-e1.dot(point), e2.dot(point));
  for (double f : {phi, phi + M_PI}) {
    const Eigen::Vector3d u = std::cos(f) * e1 + std::sin(f) * e2;
    out.lines.push_back({top + r1 * u, bottom + r0 * u});
  }
  const Eigen::Vector3d up = a.dot(-Eigen::Vector3d::UnitY()) >= 0 ? top : bottom;
  if (!out.anchor) out.anchor = Eigen::Vector3d(up - std::max(r0, r1) * Eigen::Vector3d::UnitY());
}

std::optional<double> number(const FieldValue& v) {
  if (auto* d = std::get_if<double>(&v)) return *d;
  return std::nullopt;
}
std::optional<Eigen::Vector3d> vector3(const FieldValue& v) {
  if (auto* d = std::get_if<Eigen::Vector3d>(&v)) return *d;
  return std::nullopt;
}
std::optional<Eigen::Vector2d> vector2(const FieldValue& v) {
  if (auto* d = std::get_if<Eigen::Vector2d>(&v)) return *d;
  return std::nullopt;
}

}  // namespace shapes
}  // namespace mereo
