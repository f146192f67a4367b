// One writer for the FSM check JSON: `emrm reproduce` writes DIR/fsm/STEM_check.json byte for byte
// as `emrm fsm FILE --check --format json` prints it, on the shipped machines and on a
// non-deterministic copy (whose choices are listed, not counted).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace fsm_check_file_test {

namespace fs = std::filesystem;

/// Runs reproduce on `example_dir` and expects each FSM's check file to equal what `emrm fsm
/// --check --format json` prints for the same file; returns the parsed check of emrm_fsm.yaml.
nlohmann::json expect_same_check_json(const fs::path& example_dir, int expected_exit) {
  const auto out = example_dir.parent_path() / "out";
  const auto reproduce =
      run_emrm("reproduce -o " + quoted(out) + " --examples " + quoted(example_dir) + " --sample 1 --threads 2");
  EXPECT_EQ(reproduce.exit_code, expected_exit) << reproduce.out << reproduce.err;
  for (const char* stem : {"emrm_fsm", "loss_evaluation_fsm"}) {
    const fs::path fsm = example_dir / (std::string(stem) + ".yaml");
    const auto printed = run_emrm("fsm " + quoted(fsm) + " --check --format json");
    EXPECT_EQ(printed.err, "") << stem;
    EXPECT_EQ(read_text(out / "fsm" / (std::string(stem) + "_check.json")), printed.out) << stem;
  }
  return nlohmann::json::parse(read_text(out / "fsm" / "emrm_fsm_check.json"));
}

TEST(FsmCheckFile, ReproduceWritesWhatEmrmFsmPrintsForTheShippedMachines) {
  // small_example copies the shipped examples/tjunction/emrm_fsm.yaml and loss_evaluation_fsm.yaml.
  const auto example_dir = small_example("check-file-shipped");
  const auto check = expect_same_check_json(example_dir, 0);
  EXPECT_EQ(check["fsm"]["name"], "emrm");
  EXPECT_TRUE(check["check"]["ok"].get<bool>());
  EXPECT_TRUE(check["check"]["deterministic"]["choices"].is_array());
  EXPECT_TRUE(check["check"]["deterministic"]["choices"].empty());
}

TEST(FsmCheckFile, ReproduceListsTheChoicesOfANonDeterministicCopyAsEmrmFsmDoes) {
  const auto example_dir = small_example("check-file-nondeterministic");
  std::string text = read_text(example_dir / "emrm_fsm.yaml");
  const std::string edge = "  - {from: S2, event: high_risk, to: S3}";
  const auto at = text.find(edge);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + edge.size(), "\n  - {from: S2, event: high_risk, to: S5}");
  write_text(example_dir / "emrm_fsm.yaml", text);

  const auto check = expect_same_check_json(example_dir, 1);  // a failed FSM check: exit 1
  const auto& deterministic = check["check"]["deterministic"];
  EXPECT_FALSE(deterministic["ok"].get<bool>());
  ASSERT_TRUE(deterministic["choices"].is_array());
  ASSERT_EQ(deterministic["choices"].size(), 1U);
  EXPECT_EQ(deterministic["choices"][0]["state"], "S2");
  EXPECT_EQ(deterministic["choices"][0]["event"], "high_risk");
  ASSERT_EQ(deterministic["choices"][0]["transitions"].size(), 2U);
  EXPECT_EQ(deterministic["choices"][0]["transitions"][1]["to"], "S5");
}

}  // namespace fsm_check_file_test
}  // namespace emrm::e2e
