// Small file-system helpers shared by the readers (private to cpp/src/io).
#pragma once

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "mereo/core/error.hpp"

namespace mereo::io {

/// Throws InputError unless `path` is an existing regular file.
inline void require_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
}

/// `scale` (depth units per metre) when finite and positive; an InputError naming `where` otherwise.
inline double checked_depth_scale(double scale, const std::string& where) {
  if (!(scale > 0) || !std::isfinite(scale)) {
    std::ostringstream s;
    s << where << ": depth scale " << scale << " is not a finite positive number of depth units per metre";
    throw InputError(s.str());
  }
  return scale;
}

/// "scene/0003_depth.png" -> "0003_depth".
inline std::string file_stem(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

}  // namespace mereo::io
