// mereo/core/parse.hpp: numbers from text given on a command line or in a value list.
#pragma once

#include <cctype>
#include <optional>
#include <string>

namespace mereo {

/// `text` as a number (NaN and inf too; trailing blanks allowed), or nothing when it is not one.
inline std::optional<double> parse_number(const std::string& text) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  while (used < text.size() && std::isspace(static_cast<unsigned char>(text[used]))) ++used;
  if (used != text.size()) return std::nullopt;
  return x;
}

}  // namespace mereo
