#include "mereo/core/segment.hpp"

#include <stdexcept>

namespace mereo {

namespace {
constexpr const char* kNames[] = {"plane", "cylinder", "torus", "sphere", "line", "arc"};
}

const char* to_string(PrimitiveClass c) { return kNames[static_cast<int>(c)]; }

PrimitiveClass primitive_class(const std::string& name) {
  for (int i = 0; i < 6; ++i)
    if (name == kNames[i]) return static_cast<PrimitiveClass>(i);
  throw std::invalid_argument("unknown primitive class '" + name +
                              "' (known: plane, cylinder, torus, sphere, line, arc)");
}

}  // namespace mereo
