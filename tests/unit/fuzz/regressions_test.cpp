// Every input a fuzzer found a bug with, replayed through the same target with any compiler
// (tests/fuzz-regressions/TARGET/*), and every seed of every target: each must be read or refused
// as bad input, never crash, abort or escape with another exception (docs/fuzzing.md).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "harness.hpp"

namespace emrm::fuzz {
namespace regressions_test {

namespace fs = std::filesystem;

const fs::path kSource = EMRM_SOURCE_DIR;

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// The seeds of `target`: fuzz/seeds/NAME/, shipped examples among them as links.
std::vector<fs::path> seeds_of(const Target& target) {
  std::vector<fs::path> files;
  const fs::path folder = kSource / "fuzz" / "seeds" / target.name;
  if (fs::is_directory(folder))
    for (const auto& e : fs::directory_iterator(folder))
      if (fs::is_regular_file(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, TheBuildHasAnExecutableForEveryTargetAndNoOther) {
  std::vector<std::string> names;
  for (const Target& t : targets()) names.emplace_back(t.name);
  std::vector<std::string> built;
  std::istringstream list{std::string(EMRM_FUZZ_TARGETS)};
  for (std::string name; std::getline(list, name, ',');) built.push_back(name);
  EXPECT_EQ(names, built);
}

TEST(FuzzRegressions, EveryTargetHasSeeds) {
  for (const Target& t : targets()) EXPECT_FALSE(seeds_of(t).empty()) << t.name;
}

TEST(FuzzRegressions, EverySavedInputIsReadOrRefused) {
  std::size_t replayed = 0;
  for (const auto& folder : fs::directory_iterator(kSource / "tests" / "fuzz-regressions")) {
    if (!folder.is_directory()) continue;
    const Target* target = find_target(folder.path().filename().string());
    ASSERT_NE(target, nullptr) << folder.path() << " names no fuzz target";
    for (const auto& file : fs::directory_iterator(folder.path())) {
      SCOPED_TRACE(file.path().string());
      run_one(*target, contents(file.path()));
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 0u);
}

TEST(FuzzRegressions, EverySeedIsReadOrRefused) {
  for (const Target& t : targets())
    for (const fs::path& seed : seeds_of(t)) {
      SCOPED_TRACE(std::string(t.name) + ": " + seed.string());
      run_one(t, contents(seed));
    }
}

}  // namespace regressions_test
}  // namespace emrm::fuzz
