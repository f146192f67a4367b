// End-to-end: what every user meets first — help, version, usage errors and exit codes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace {

using ::testing::HasSubstr;

TEST(Cli, HelpListsTheCommandsAndExitsZero) {
  const auto r = run_emrm("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("analyze"));
  EXPECT_THAT(r.out, HasSubstr("fsm"));
  EXPECT_THAT(r.out, HasSubstr("Exit codes"));
}

TEST(Cli, CommandHelpDescribesItsOptions) {
  const auto r = run_emrm("analyze --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, HasSubstr("--format"));
  EXPECT_THAT(r.out, HasSubstr("--output"));
  EXPECT_EQ(run_emrm("fsm --help").exit_code, 0);
}

TEST(Cli, VersionPrintsTheVersion) {
  const auto r = run_emrm("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.out, ::testing::MatchesRegex("emrm [0-9]+\\.[0-9]+\\.[0-9]+\n"));
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run_emrm("").exit_code, 2);
  EXPECT_EQ(run_emrm("frobnicate").exit_code, 2);
  EXPECT_EQ(run_emrm("analyze").exit_code, 2);
  EXPECT_EQ(run_emrm("analyze " + quoted(example("safety.yaml")) + " --format xml").exit_code, 2);
  EXPECT_EQ(run_emrm("analyze " + quoted(example("safety.yaml")) + " --no-such-flag").exit_code, 2);
}

}  // namespace
}  // namespace emrm::e2e
