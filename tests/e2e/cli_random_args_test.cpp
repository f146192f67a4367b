// Property: whatever the argument vector, emrm ends with exit code 0, 1 or 2 — never "internal
// error" (70), never a signal — and says something on exit 2. The vectors are drawn (fixed seed)
// from every command, every option name, and values that have broken readers before: NaN,
// infinities, huge and negative numbers, a 10 000-digit number, bytes that are not UTF-8, missing
// files, a folder, an endless device. The files given are tiny, so every run is quick.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "run_emrm.hpp"
#include "small_example.hpp"
#include "test_scale.hpp"

namespace emrm::e2e {
namespace cli_random_args_test {

// One word of shell text, quoted unless it is an option name.
std::string word(const std::string& text) { return text.rfind("--", 0) == 0 ? text : quoted(text); }

TEST(CliRandomArguments, ExitCodesAreOnlyZeroOneOrTwo) {
  const auto dir = small_example("random_args");
  write_text(
      dir / "tiny.yaml",
      "scene: scene.yaml\nstrategies: [emergency_stop]\ngrids:\n  - name: g\n    speed_kph: 40\n    ttc_s: 2.0\n");
  const std::vector<std::string> commands{
      "analyze", "fsm",      "simulate",  "sweep",    "merge",  "reproduce", "ca",     "plan",   "run",      "report",
      "verify",  "diagnose", "calibrate", "boundary", "export", "assess",    "nosuch", "--help", "--version"};
  const std::vector<std::string> options{
      "--speed-kph",      "--ttc-s",   "--mu",         "--passage-m", "--truck-speed-kph",
      "--seed",           "--threads", "--output",     "-o",          "--levels",
      "--strength",       "--effort",  "--sample",     "--profile",   "--format",
      "--words",          "--json",    "--shard",      "--force",     "--scene",
      "--strategy",       "--fit",     "--stops",      "--match",     "--examples",
      "--no-certify",     "--check",   "--bogus",      "--adaptive",  "--verify-sample",
      "--initial-levels", "--stride",  "--brackets",   "--spread",    "--max-figures",
      "--no-figures",     "--plan",    "--tolerance-m"};
  const std::string out = (dir.parent_path() / "out").string();
  const std::vector<std::string> values{"nan",
                                        "-nan",
                                        "inf",
                                        "-1",
                                        "0",
                                        "1",
                                        "3",
                                        "0.5",
                                        "1e300",
                                        "-1e300",
                                        "18446744073709551616",
                                        std::string(10000, '9'),
                                        "3,3",
                                        "2/1",
                                        "0/0",
                                        "1/2",
                                        "\xff\xfe",
                                        "",
                                        "x",
                                        "ideal",
                                        "emrm",
                                        "all",
                                        "openscenario",
                                        "esmini",
                                        (dir / "safety.yaml").string(),
                                        (dir / "emrm_fsm.yaml").string(),
                                        (dir / "odd.yaml").string(),
                                        (dir / "tiny.yaml").string(),
                                        (dir / "scene.yaml").string(),
                                        (dir / "nosuch.yaml").string(),
                                        dir.string(),
                                        "/dev/zero",
                                        out};
  std::mt19937_64 random(20261124);
  const auto pick = [&](const std::vector<std::string>& from) {
    return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(random)];
  };
  for (int run = 0; run < test::sample(1000, 300); ++run) {
    std::string args = pick(commands);
    const int words = std::uniform_int_distribution<int>(0, 5)(random);
    for (int w = 0; w < words; ++w)
      args += " " + word(std::uniform_int_distribution<int>(0, 2)(random) == 0 ? pick(options) : pick(values));
    const auto r = run_emrm(args);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1 || r.exit_code == 2)
        << r.exit_code << ": emrm " << args.substr(0, 300) << "\n"
        << r.err.substr(0, 500);
    if (r.exit_code == 2) {
      EXPECT_FALSE(r.err.empty()) << args.substr(0, 300);
    }
    EXPECT_LT(r.err.size(), 20000u) << "a message echoes too much: " << args.substr(0, 300);
  }
}

// The vectors that broke before, each bad input (exit 2) in a short message.
TEST(CliRandomArguments, ValuesThatBrokeTheCliBeforeAreBadInputInAShortMessage) {
  const std::string huge(10000, '9');
  const std::vector<std::pair<std::string, std::string>> cases{
      {"ca --levels 3,3 --effort nan", "--effort: expected a number in [0, 1e+06], got 'nan'"},
      {"simulat --speed-kph 30", "unknown command 'simulat' (did you mean 'simulate'?)"},
      {"sweep x.yaml -o out --threads -1", "--threads: Value -1 not in range 0 to 1024"},
      {"simulate --speed-kph 30 --ttc-s 1 --seed 99999999999999999999999", "--seed: expected a whole number"},
      {"simulate --speed-kph 30 --ttc-s 1 --seed -1", "--seed: expected a whole number"},
      {"simulate --ttc-s 1 --speed-kph " + huge, "speed_kph must be a finite ego speed with 0 < speed_kph <= 400"},
      {"simulate --ttc-s 1 --speed-kph x" + huge, "Could not convert"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_emrm(args);
    EXPECT_EQ(r.exit_code, 2) << args.substr(0, 100) << "\n" << r.err.substr(0, 300);
    EXPECT_THAT(r.err, ::testing::HasSubstr(message)) << args.substr(0, 100);
    EXPECT_LT(r.err.size(), 300u) << args.substr(0, 100);
  }
}

}  // namespace cli_random_args_test
}  // namespace emrm::e2e
