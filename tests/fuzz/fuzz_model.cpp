// libFuzzer target: mereo::knowledge::parse_models on any text, over the shipped models (so that
// `parent:` resolves, as in a user's model file; parsing validates every concept). Returns or
// throws mereo::InputError; anything else is a finding (fuzz_util.hpp).
//   build/fuzz/tests/fuzz/fuzz_model -max_len=8192 tests/fuzz/corpus/model
#include <cstdint>
#include <string>

#include "mereo/core/error.hpp"
#include "mereo/knowledge/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mereo::knowledge::KnowledgeBase builtin = mereo::knowledge::builtin_models();
  mereo::knowledge::KnowledgeBase kb = builtin;
  try {
    mereo::knowledge::parse_models(kb, std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
  } catch (const mereo::InputError&) {
  }
  return 0;
}
