// Helpers shared by the libFuzzer targets: a scratch folder of the process's own, whole-file
// writes, and the one rule every target checks.
//
// The contract: a reader given any bytes returns or throws one of the library's documented
// bad-input errors. Every other exception (std::bad_alloc, a yaml-cpp or filesystem error,
// std::out_of_range...) escapes the target, std::terminate aborts (printing its type and
// message) and libFuzzer saves the input as a crash; so do the sanitizers' reports.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace mereo::fuzz {

/// A fresh folder under the temporary directory, made on first use and removed at exit
/// (a crash leaves it behind, with the input that crashed). The path is never destroyed: the
/// exit handler that removes the folder runs after the static destructors.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path* const dir = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "mereo_fuzz_XXXXXX").string();
    if (!mkdtemp(tmpl.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return new std::filesystem::path(tmpl);
  }();
  return *dir;
}

/// Writes `size` bytes to `path` (a harness failure, not a finding, aborts with a message).
inline void write_file(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
}

}  // namespace mereo::fuzz
