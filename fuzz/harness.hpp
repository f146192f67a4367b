#pragma once

// The fuzz targets' bodies (docs/fuzzing.md): one function per reader of user input and one for the
// command line's argument parser. A fuzzer (fuzz_target.cpp, built with clang's libFuzzer) calls
// them with its inputs; the test suite calls them with every saved input under
// tests/fuzz-regressions/, with any compiler.
//
// A target returns normally when emrm accepted the input or refused it the way the command line
// turns into exit 2 (emrm::Error, a filesystem error); any other exception escapes, and a crash,
// hang or leak is the sanitizers' to report: each is a bug.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace emrm::fuzz {

using TargetFunction = void (*)(std::string_view data);

struct Target {
  std::string_view name;  ///< its executable is fuzz_NAME, its seeds are fuzz/seeds/NAME/
  TargetFunction run;
};

/// Every target, in a fixed order.
[[nodiscard]] const std::vector<Target>& targets();

/// The target called `name`, or nullptr.
[[nodiscard]] const Target* find_target(std::string_view name);

/// Runs `target` on one input, turning emrm's refusals into a normal return.
void run_one(const Target& target, std::string_view data);

}  // namespace emrm::fuzz
