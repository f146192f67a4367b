// End-to-end: what every user meets first — help, version, usage errors and exit codes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace general_cli_test {

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

// Every command that reads a file says in one format that it is missing, a folder or too large:
// "PATH: error: …", exit 2, no CLI11 "Run with --help" (issue: `analyze nosuch.yaml` differed).
TEST(Cli, AMissingOrWrongInputFileIsOneMessageInOneFormat) {
  const auto dir = scratch_dir("input-files");
  const std::string missing = (dir / "nosuch.yaml").string();
  for (const std::string& command :
       {"analyze " + missing, "fsm " + missing, "sweep " + missing + " -o " + (dir / "out").string(),
        "simulate --speed-kph 30 --ttc-s 1 --scene " + missing, "ca " + missing,
        "calibrate --stops " + missing + " --fit brake_dead_time_s -o " + (dir / "p.yaml").string()}) {
    const auto r = run_emrm(command);
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_EQ(r.err, missing + ": error: the file does not exist\n") << command;
  }
  const auto folder = run_emrm("analyze " + dir.string());
  EXPECT_EQ(folder.exit_code, 2);
  EXPECT_EQ(folder.err, dir.string() + ": error: this is a folder; expected a file\n");
  const auto endless = run_emrm("fsm /dev/zero");
  EXPECT_EQ(endless.exit_code, 2);
  EXPECT_THAT(endless.err, HasSubstr("/dev/zero: error: the file is larger than 64 MiB"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

// Text that is not UTF-8 inside a name is bad input where it stands, for every reader, and no
// output is left behind (it used to reach the JSON writers: "internal error", exit 70, and a
// half-written plan folder).
TEST(Cli, ABytesThatIsNotUtf8IsBadInputAtItsPlaceAndWritesNothing) {
  const auto dir = scratch_dir("not-utf8");
  const auto broken = [&](const std::string& name, const std::string& key) {
    std::string text = read_text(example(name));
    const auto at = text.find(key);
    text.insert(at + key.size() + 1, "\xC3(");
    const auto file = dir / name;
    write_text(file, text);
    return file;
  };
  // Files that name other files are written beside copies of them.
  for (const char* name : {"safety.yaml", "emrm_fsm.yaml", "loss_evaluation_fsm.yaml", "scene.yaml"})
    std::filesystem::copy_file(example(name), dir / name, std::filesystem::copy_options::overwrite_existing);
  const auto odd = broken("odd.yaml", "\nname:");
  const auto fsm = broken("emrm_fsm.yaml", "\nname:");
  for (const auto& [command, file] : {std::pair{"plan " + odd.string() + " -o " + (dir / "plan").string(), odd},
                                      std::pair{"fsm " + fsm.string() + " --format json", fsm}}) {
    const auto r = run_emrm(command);
    EXPECT_EQ(r.exit_code, 2) << command << r.err;
    EXPECT_THAT(r.err, ::testing::MatchesRegex(file.string() + ":[0-9]+:7: error: byte 0xC3 is not UTF-8.*\n"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "plan"));
}

// Small inputs that asked for unbounded work: a covering array with 3·10⁹ pairs (ran out of
// memory), a scene step of 10⁻⁹ s (ran for days). Each is refused at once, naming the limit.
TEST(Cli, SmallInputsThatAskForUnboundedWorkAreRefusedNamingTheLimit) {
  const auto ca = run_emrm("ca --levels 3,1000000000");
  EXPECT_EQ(ca.exit_code, 2);
  EXPECT_THAT(ca.err, HasSubstr("more than the limit of 20000000 (ca --max-tuples raises it"));
  EXPECT_EQ(run_emrm("ca --levels 3,3,3 --max-tuples 27").exit_code, 0);  // exactly at the limit
  EXPECT_EQ(run_emrm("ca --levels 3,3,3 --max-tuples 26").exit_code, 2);

  const auto dir = scratch_dir("tiny-step");
  std::string scene = read_text(example("scene.yaml"));
  const auto at = scene.find("dt_s:");
  ASSERT_NE(at, std::string::npos);
  scene.replace(at, scene.find('#', at) - at, "dt_s: 1e-9 ");
  write_text(dir / "scene.yaml", scene);
  const auto simulate = run_emrm("simulate --speed-kph 40 --ttc-s 1 --scene " + quoted(dir / "scene.yaml"));
  EXPECT_EQ(simulate.exit_code, 2);
  EXPECT_THAT(simulate.err, HasSubstr("simulation.dt_s: expected a value in [0.0001, 0.1], got 1e-09"));
}

}  // namespace general_cli_test
}  // namespace emrm::e2e
