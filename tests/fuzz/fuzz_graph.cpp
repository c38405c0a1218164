// libFuzzer target: mereo::graph::Graph::parse on any text, with the library's node kinds
// registered (parse verifies the graph and makes its node bodies: options, model files). The
// file name lies in graphs/, so that `extends: tabletop.yaml` finds the shipped graph.
// Returns or throws GraphError (or InputError, the library's bad-input error); anything else
// is a finding (see fuzz_util.hpp).
//   build/fuzz/tests/fuzz/fuzz_graph -max_len=8192 tests/fuzz/corpus/graph
#include <cstdint>
#include <string>

#include "mereo/core/error.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/nodes/builtin.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  mereo::nodes::register_builtin();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    mereo::graph::Graph::parse(std::string(reinterpret_cast<const char*>(data), size),
                               MEREO_GRAPHS_DIR "/fuzz.yaml");
  } catch (const mereo::graph::GraphError&) {
  } catch (const mereo::InputError&) {
  }
  return 0;
}
