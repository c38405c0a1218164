#include "mereo/core/camera.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "mereo/core/error.hpp"

namespace mereo {

std::string Intrinsics::to_string() const {
  std::ostringstream s;
  s.precision(10);
  s << fx << ',' << fy << ',' << cx << ',' << cy;
  return s.str();
}

Intrinsics Intrinsics::parse(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw InputError("intrinsics '" + text + "': '" + item + "' is not a number (expected fx,fy,cx,cy)");
    v.push_back(x);
  }
  if (v.size() != 4)
    throw InputError("intrinsics '" + text + "': expected 4 numbers fx,fy,cx,cy, got " +
                     std::to_string(v.size()));
  Intrinsics K{v[0], v[1], v[2], v[3]};
  if (!K.valid()) throw InputError("intrinsics '" + text + "': fx and fy must be positive");
  return K;
}

}  // namespace mereo
