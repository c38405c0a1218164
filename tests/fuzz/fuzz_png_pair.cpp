// libFuzzer target: mereo::io::read on a colour/depth image pair (and its intrinsics file) cut
// from any bytes, then the depth filter that every pipeline applies first. The input:
//   byte 0      flags: bits 0-1 the depth format (units, sun3d, nyu-raw, units), bit 2 the
//               depth image as .pgm (else .png), bit 3 the intrinsics as camera-intrinsics.txt
//               (else intrinsics.json), bits 4-5 the colour image as .png, .jpg, .ppm, .png
//   bytes 1-2   the colour image's length n (little-endian), bytes 3-4 the depth image's m
//   then        n bytes of colour image, m bytes of depth image, and the intrinsics file's text
//               (none when empty: the intrinsics are then given as an option)
// Returns or throws mereo::InputError; anything else is a finding (see fuzz_util.hpp).
//   build/fuzz/tests/fuzz/fuzz_png_pair -max_len=65536 tests/fuzz/corpus/png_pair
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>

#include "fuzz_util.hpp"
#include "mereo/core/error.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/depth_filter.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  if (size < 5) return 0;
  const std::uint8_t flags = data[0];
  std::size_t n = data[1] | (data[2] << 8), m = data[3] | (data[4] << 8);
  data += 5, size -= 5;
  n = std::min(n, size);
  m = std::min(m, size - n);
  const std::size_t k = size - n - m;

  // a fresh folder per input: no file of the previous input is left to be found
  static const fs::path dir = mereo::fuzz::scratch_dir() / "pair";
  fs::remove_all(dir);
  fs::create_directory(dir);
  static const char* const color_ext[] = {".png", ".jpg", ".ppm", ".png"};
  const fs::path color = dir / (std::string("f_rgb") + color_ext[(flags >> 4) & 3]);
  const fs::path depth = dir / (flags & 4 ? "f_depth.pgm" : "f_depth.png");
  mereo::fuzz::write_file(color, data, n);
  mereo::fuzz::write_file(depth, data + n, m);
  mereo::io::ReadOptions options;
  static const mereo::io::DepthFormat formats[] = {mereo::io::DepthFormat::Units, mereo::io::DepthFormat::Sun3d,
                                                   mereo::io::DepthFormat::NyuRaw, mereo::io::DepthFormat::Units};
  options.depth_format = formats[flags & 3];
  if (k > 0)
    mereo::fuzz::write_file(dir / (flags & 8 ? "camera-intrinsics.txt" : "intrinsics.json"), data + n + m, k);
  else
    options.intrinsics = mereo::Intrinsics{525, 525, 319.5, 239.5};
  try {
    const mereo::Frame frame = mereo::io::read(depth.string(), options);
    mereo::signal::filter_depth(frame);
  } catch (const mereo::InputError&) {
  }
  return 0;
}
