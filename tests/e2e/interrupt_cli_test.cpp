// Interrupts (docs/campaign.md, "Interrupts"): SIGINT during `sweep` and `run` keeps every cell
// finished, says how to resume and exits 130; the rerun completes with no cell lost or duplicated,
// byte for byte what an uninterrupted run writes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <thread>
#include <vector>

#include "run_emrm.hpp"
#include "small_example.hpp"
#include "spawn_process.hpp"
#include "test_scale.hpp"

namespace emrm::e2e {
namespace interrupt_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// Starts `emrm ARGS` (no shell, so SIGINT is not ignored as in a shell's background job), sends
// `signal` `delay` after `ready` exists, and waits for it.
RunResult interrupted_emrm(const std::vector<std::string>& args, const fs::path& ready, std::chrono::milliseconds delay,
                           int signal, const fs::path& dir) {
  std::vector<std::string> words{EMRM_BINARY};
  words.insert(words.end(), args.begin(), args.end());
  const pid_t pid = spawn_process(words, dir);
  for (int i = 0; i < 600 && !fs::exists(ready); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(delay);
  ::kill(pid, signal);
  return wait_for_process(pid, dir);
}

// 240 cells; 64 under the sanitizers, which run every cell five to ten times slower.
const std::string kCampaign = std::string("seed: 5\ngrids:\n  - name: map\n") +
                              "    speed_kph: {from: 30, to: 72, step: " + test::sample("3", "6") + "}\n" +
                              "    ttc_s: {from: 0.25, to: 1.45, step: " + test::sample("0.08", "0.16") + "}\n";

TEST(InterruptCli, SigintDuringSweepKeepsWhatIsDoneAndTheRerunCompletesIt) {
  const auto dir = scratch_dir("interrupt-sweep");
  write_text(dir / "campaign.yaml", kCampaign);
  const auto out = dir / "out";
  const auto r = interrupted_emrm({"sweep", (dir / "campaign.yaml").string(), "-o", out.string(), "--threads", "2"},
                                  out / "results.sqlite", std::chrono::milliseconds(700), SIGINT, dir);
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("interrupted: "));
  EXPECT_THAT(r.err, HasSubstr("cells stored in"));
  EXPECT_THAT(r.err, HasSubstr("rerun the same command to resume"));

  const auto resumed = run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.out, HasSubstr("already stored"));
  const auto fresh =
      run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "fresh") + " --threads 2");
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_EQ(read_text(out / "regions.csv"), read_text(dir / "fresh" / "regions.csv"));  // none lost, none twice
  EXPECT_EQ(read_text(out / "cells.csv"), read_text(dir / "fresh" / "cells.csv"));
}

TEST(InterruptCli, SigintDuringRunSaysScenariosAndResumes) {
  const auto example_dir = small_example("interrupt-run");
  const auto dir = example_dir.parent_path();
  const auto plan = run_emrm("plan " + quoted(example_dir / "odd.yaml") + " -o " + quoted(dir / "plan"));
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const auto out = dir / "results";
  const auto r =
      interrupted_emrm({"run", (dir / "plan" / "scenarios.csv").string(), "-o", out.string(), "--threads", "1"},
                       out / "results.sqlite", std::chrono::milliseconds(0), SIGINT, dir);
  if (r.exit_code == 0) GTEST_SKIP() << "the run ended before the interrupt";
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("scenarios stored in"));
  const auto resumed = run_emrm("run " + quoted(dir / "plan" / "scenarios.csv") + " -o " + quoted(out));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto fresh = run_emrm("run " + quoted(dir / "plan" / "scenarios.csv") + " -o " + quoted(dir / "fresh"));
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_EQ(read_text(out / "outcomes.csv"), read_text(dir / "fresh" / "outcomes.csv"));
}

}  // namespace interrupt_cli_test
}  // namespace emrm::e2e
