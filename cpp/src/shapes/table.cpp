// The shape table's generic functions (mereo/shapes/table.hpp) and the helpers of shape.hpp.
#include "mereo/shapes/table.hpp"

#include <algorithm>
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

const char* PrimitiveClass::name() const {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::name; }, make());
}
int PrimitiveClass::sample_size() const {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::sample_size; }, make());
}
bool PrimitiveClass::thin() const {
  return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::thin; }, make());
}

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

std::optional<double> number(const FieldValue& v) {
  if (auto* d = std::get_if<double>(&v)) return *d;
  return std::nullopt;
}
std::optional<Eigen::Vector3d> vector3(const FieldValue& v) {
  if (auto* d = std::get_if<Eigen::Vector3d>(&v)) return *d;
  return std::nullopt;
}

}  // namespace shapes
}  // namespace mereo
