// mereo/core/error.hpp: the error type for bad input.
#pragma once

#include <stdexcept>
#include <string>

namespace mereo {

/// Bad input (a missing or corrupt file, mismatched images, a bad option value).
/// The message is one line that names the file or value and says what is wrong.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mereo
