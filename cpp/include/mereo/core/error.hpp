// mereo/core/error.hpp: the error type for bad input.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace mereo {

/// Bad input (a missing or corrupt file, mismatched images, a bad option value).
/// The message is one line that names the file or value and says what is wrong.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// `text` from a file, for a message: in single quotes, cut at `max` bytes, every byte that is not
/// printable ASCII written as \xNN, so that a message stays one line of valid UTF-8 whatever the
/// file held (a binary file, another encoding).
inline std::string printable(std::string_view text, std::size_t max = 40) {
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += char(c);
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out + (text.size() > max ? "...'" : "'");
}

}  // namespace mereo
