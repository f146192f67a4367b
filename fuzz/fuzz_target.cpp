// One libFuzzer target (docs/fuzzing.md): EMRM_FUZZ_TARGET names which of harness.hpp's.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "harness.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const emrm::fuzz::Target* const target = [] {
    const emrm::fuzz::Target* t = emrm::fuzz::find_target(EMRM_FUZZ_TARGET);
    if (t == nullptr) {
      std::fprintf(stderr, "no fuzz target '%s'\n", EMRM_FUZZ_TARGET);
      std::abort();
    }
    return t;
  }();
  emrm::fuzz::run_one(*target, {reinterpret_cast<const char*>(data), size});
  return 0;
}
