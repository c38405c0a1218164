#include "mereo/core/camera.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "mereo/core/error.hpp"
#include "mereo/core/parse.hpp"

namespace mereo {

std::string Intrinsics::to_string() const {
  std::ostringstream s;
  s.precision(10);
  s << fx << ',' << fy << ',' << cx << ',' << cy;
  return s.str();
}

std::string Intrinsics::problem(int cols, int rows) const {
  auto num = [](double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  };
  for (const auto& [name, f] : {std::pair{"fx", fx}, std::pair{"fy", fy}})
    if (!(f > 0 && f <= kMaxFocal))
      return std::string(name) + " " + num(f) + " is not a focal length in pixels (expected 0 < " + name +
             " <= " + num(kMaxFocal) + ")";
  if (!std::isfinite(cx) || !std::isfinite(cy)) return "the principal point cx, cy must be finite";
  if (cols > 0 && rows > 0 && !(cx >= 0 && cx <= cols && cy >= 0 && cy <= rows))
    return "the principal point (" + num(cx) + ", " + num(cy) + ") is outside the " + std::to_string(cols) + "x" +
           std::to_string(rows) + " image";
  return {};
}

Intrinsics Intrinsics::parse(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    const auto x = parse_number(item);
    if (!x || !std::isfinite(*x))
      throw InputError("intrinsics '" + text + "': '" + item + "' is not a number (expected fx,fy,cx,cy)");
    v.push_back(*x);
  }
  if (v.size() != 4)
    throw InputError("intrinsics '" + text + "': expected 4 numbers fx,fy,cx,cy, got " +
                     std::to_string(v.size()));
  Intrinsics K{v[0], v[1], v[2], v[3]};
  if (const std::string p = K.problem(); !p.empty()) throw InputError("intrinsics '" + text + "': " + p);
  return K;
}

}  // namespace mereo
