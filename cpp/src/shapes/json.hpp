// Internal: a segment's class fields (mereo/shapes/) as JSON members: what the results and the
// renderer's ground truth both write.
#pragma once

#include <variant>

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

/// Adds each field to the JSON object `j` (nlohmann's json or ordered_json), vectors as arrays.
template <class Json>
void fields_to_json(const FieldList& fields, Json& j) {
  for (const auto& [name, value] : fields)
    std::visit([&, key = name](const auto& v) {
      using V = std::decay_t<decltype(v)>;
      if constexpr (std::is_same_v<V, Eigen::Vector3d>) j[key] = Json::array({v.x(), v.y(), v.z()});
      else if constexpr (std::is_same_v<V, Eigen::Vector2d>) j[key] = Json::array({v.x(), v.y()});
      else j[key] = v;
    }, value);
}

}  // namespace mereo::shapes
