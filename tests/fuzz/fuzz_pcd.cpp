// libFuzzer target: mereo::io::read_pcd on any bytes (written to a .pcd file), then the depth
// filter that every pipeline applies first, so that a corrupt file's values reach it too.
// Returns or throws mereo::InputError; anything else is a finding (see fuzz_util.hpp).
//   build/fuzz/tests/fuzz/fuzz_pcd -max_len=65536 tests/fuzz/corpus/pcd
#include <cstdint>
#include <string>

#include "fuzz_util.hpp"
#include "mereo/core/error.hpp"
#include "mereo/io/io.hpp"
#include "mereo/signal/depth_filter.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = (mereo::fuzz::scratch_dir() / "input.pcd").string();
  mereo::fuzz::write_file(path, data, size);
  try {
    const mereo::Frame frame = mereo::io::read_pcd(path);
    mereo::signal::filter_depth(frame);
  } catch (const mereo::InputError&) {
  }
  return 0;
}
