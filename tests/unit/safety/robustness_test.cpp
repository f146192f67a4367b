// Bad input never crashes: thousands of mutated copies of the shipped safety case either load or
// throw InputError naming a place in the file, and nothing else. Seeded, so failures reproduce.

#include <gtest/gtest.h>

#include <random>

#include "emrm/safety/checks.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/safety/traceability.hpp"
#include "example_case.hpp"

namespace emrm::safety {
namespace robustness_test {

std::string mutate(std::string text, std::mt19937& rng) {
  static const std::string kAlphabet = " \n\t:-[]{},#'\"&*!|>%@`0123456789.eE+xyzSCHLUA_";
  std::uniform_int_distribution<int> kind(0, 3);
  std::uniform_int_distribution<std::size_t> pick(0, kAlphabet.size() - 1);
  const int edits = 1 + static_cast<int>(rng() % 3);
  for (int i = 0; i < edits && !text.empty(); ++i) {
    std::uniform_int_distribution<std::size_t> at(0, text.size() - 1);
    const std::size_t pos = at(rng);
    switch (kind(rng)) {
      case 0:
        text[pos] = kAlphabet[pick(rng)];
        break;  // replace a byte
      case 1:
        text.erase(pos, 1 + rng() % 8);
        break;  // delete a run
      case 2:
        text.insert(pos, 1, kAlphabet[pick(rng)]);
        break;    // insert a byte
      default: {  // swap two lines' worth
        const std::size_t len = std::min<std::size_t>(40, text.size() - pos);
        text.insert(at(rng) % text.size(), text.substr(pos, len));
      }
    }
  }
  return text;
}

TEST(SafetyRobustness, MutatedCasesLoadOrFailWithALocatedInputError) {
  const std::string original = testing::example_text();
  std::mt19937 rng(20261121);
  int loaded = 0;
  int rejected = 0;
  for (int i = 0; i < 3000; ++i) {
    const std::string text = mutate(original, rng);
    try {
      const auto sc = parse_safety_case(text, "mutant.yaml");
      // A case that loads must also survive every later stage.
      (void)analysis_json(sc, check(sc));
      ++loaded;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "mutant.yaml");
      EXPECT_GT(e.where().line, 0) << e.what();
      ++rejected;
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(rejected, 0);
}

}  // namespace robustness_test
}  // namespace emrm::safety
