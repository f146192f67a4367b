// End-to-end: `emrm sweep` and `emrm merge` as a user runs them, including a sweep killed with
// SIGKILL and resumed.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace sweep_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// Cheap cells: green (slow, early hazard) and infeasible (too far) ones.
constexpr const char* kSmallCampaign =
    "seed: 7\n"
    "grids:\n"
    "  - name: a\n"
    "    speed_kph: [30, 36, 42]\n"
    "    ttc_s: {from: 2.0, to: 2.9, levels: 3}\n"
    "  - name: b\n"
    "    speed_kph: 72\n"
    "    ttc_s: [1.5, 2.9]\n"
    "    mu: [0.8, 1.0]\n";

// 16 red/orange cells (60–72 km/h, TTC ≤ 0.55 s) of about 0.1 s each: long enough to be killed.
constexpr const char* kSlowCampaign =
    "seed: 3\n"
    "grids:\n"
    "  - name: red\n"
    "    speed_kph: {from: 60, to: 72, levels: 4}\n"
    "    ttc_s: {from: 0.25, to: 0.55, levels: 4}\n";

// Runs the sqlite3 shell on a store; nullopt when the shell is not installed.
std::optional<std::string> sqlite_query(const fs::path& db, const std::string& sql) {
  const std::string command = "sqlite3 -readonly " + quoted(db) + " \"" + sql + "\" 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string out;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  const int status = ::pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) == 127) return std::nullopt;
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

bool have_sqlite_shell() { return std::system("command -v sqlite3 >/dev/null 2>&1") == 0; }

std::size_t count_lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

TEST(SweepCli, AKilledSweepResumesWithNothingLostOrWrittenTwice) {
  if (!have_sqlite_shell()) GTEST_SKIP() << "the sqlite3 shell is needed to watch the store";
  const auto dir = scratch_dir("sweep_kill");
  const auto campaign = dir / "slow.yaml";
  write_text(campaign, kSlowCampaign);

  const auto full = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "full") + " --threads 2");
  ASSERT_EQ(full.exit_code, 0) << full.err;

  const auto killed_dir = dir / "killed";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    const std::string campaign_arg = campaign.string();
    const std::string out_arg = killed_dir.string();
    ::execl(EMRM_BINARY, "emrm", "sweep", campaign_arg.c_str(), "-o", out_arg.c_str(), "--threads", "1",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Kill it once some, but not all, cells are committed.
  long stored = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(killed_dir / "results.sqlite")) {
      const auto count = sqlite_query(killed_dir / "results.sqlite", "SELECT COUNT(*) FROM cells");
      if (count && !count->empty()) stored = std::stol(*count);
      if (stored > 0) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the sweep ended before it could be killed";
  const auto after_kill = sqlite_query(killed_dir / "results.sqlite", "SELECT COUNT(*) FROM cells");
  ASSERT_TRUE(after_kill.has_value());
  const long kept = std::stol(*after_kill);
  ASSERT_GT(kept, 0);
  ASSERT_LT(kept, 16) << "the sweep finished before it was killed; make the test campaign slower";

  const auto resumed = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(killed_dir) + " --threads 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.out, HasSubstr(std::to_string(16 - kept) + " simulated, " + std::to_string(kept) +
                                     " already stored (skipped)"));
  EXPECT_EQ(read_text(killed_dir / "cells.csv"), read_text(dir / "full" / "cells.csv"));
  EXPECT_EQ(read_text(killed_dir / "regions.csv"), read_text(dir / "full" / "regions.csv"));
  EXPECT_EQ(count_lines(read_text(killed_dir / "regions.csv")), 17u);
  EXPECT_EQ(sqlite_query(killed_dir / "results.sqlite",
                         "SELECT COUNT(*), COUNT(DISTINCT grid || ' ' || cell_index) FROM cells"),
            "16|16");
  EXPECT_EQ(sqlite_query(killed_dir / "results.sqlite",
                         "SELECT (SELECT COUNT(*) FROM outcomes) = 6 * (SELECT SUM(feasible) FROM cells)"),
            "1");
}

TEST(SweepCli, ThreadCountAndShardingDoNotChangeTheResults) {
  const auto dir = scratch_dir("sweep_threads");
  const auto campaign = dir / "small.yaml";
  write_text(campaign, kSmallCampaign);
  const auto one = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "one") + " --threads 1");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_THAT(one.out, HasSubstr("Swept 13 cells"));
  // No progress bar when stderr is not a terminal: only the warning that grid 'b' (72 km/h, TTC
  // from 1.5 s) has no feasible cell.
  EXPECT_THAT(one.err, HasSubstr("warning: grid 'b' has no feasible cell"));
  EXPECT_EQ(std::count(one.err.begin(), one.err.end(), '\n'), 1) << one.err;
  const auto two = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "two") + " --threads 2");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  for (const char* file : {"cells.csv", "regions.csv", "cells.json"})
    EXPECT_EQ(read_text(dir / "two" / file), read_text(dir / "one" / file)) << file;
  EXPECT_EQ(count_lines(read_text(dir / "one" / "regions.csv")), 14u);

  for (const char* shard : {"1/2", "2/2"}) {
    const auto r = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / ("shard" + std::string(1, shard[0]))) +
                            " --shard " + shard);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr(std::string("(shard ") + shard + ")"));
  }
  EXPECT_EQ(count_lines(read_text(dir / "shard1" / "regions.csv")), 8u);  // 7 of 13 cells + header
  const auto merged =
      run_emrm("merge -o " + quoted(dir / "merged") + " " + quoted(dir / "shard1") + " " + quoted(dir / "shard2"));
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_THAT(merged.out, HasSubstr("13 cells"));
  for (const char* file : {"cells.csv", "regions.csv"})
    EXPECT_EQ(read_text(dir / "merged" / file), read_text(dir / "one" / file)) << file;
}

// Issue 40, 5: a grid with its TTC in milliseconds has no feasible cell, and the sweep said nothing.
// It still succeeds (such a grid is legal), warning on stderr with the file, the grid and why its
// first cell is infeasible; a grid with a feasible cell draws no warning.
TEST(SweepCli, AGridWithoutAFeasibleCellIsWarnedOf) {
  const auto dir = scratch_dir("sweep_infeasible");
  const auto campaign = dir / "ms.yaml";
  write_text(campaign,
             "strategies: [emergency_stop]\ngrids:\n  - name: in_ms\n    speed_kph: [40, 60]\n    ttc_s: [800, 1200]\n"
             "  - name: fine_one\n    speed_kph: 40\n    ttc_s: 1.0\n");
  const auto r = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "out") + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("ms.yaml: warning: grid 'in_ms' has no feasible cell among its 4 cells; its first: "
                               "the truck would appear 8888.89 m ahead"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("fine_one")));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
}

TEST(SweepCli, RefusesAChangedConfigurationInTheSameFolder) {
  const auto dir = scratch_dir("sweep_changed");
  const auto campaign = dir / "small.yaml";
  write_text(campaign, "grids:\n  - name: far\n    speed_kph: 72\n    ttc_s: [2.5, 2.9]\n");
  ASSERT_EQ(run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "out")).exit_code, 0);
  write_text(campaign, "seed: 2\ngrids:\n  - name: far\n    speed_kph: 72\n    ttc_s: [2.5, 2.9]\n");
  const auto r = run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "out"));
  expect_bad_input(r, "another configuration (config hash ");
  EXPECT_THAT(r.err, HasSubstr((dir / "out").string()));
  // Both hashes, as 16 hex digits each.
  const auto hash_at = [&](const std::string& before) {
    const auto pos = r.err.find(before);
    return pos == std::string::npos ? std::string() : r.err.substr(pos + before.size(), 16);
  };
  const std::string stored = hash_at("config hash ");
  const std::string ours = hash_at("this campaign's is ");
  EXPECT_EQ(stored.find_first_not_of("0123456789abcdef"), std::string::npos) << r.err;
  EXPECT_EQ(ours.find_first_not_of("0123456789abcdef"), std::string::npos) << r.err;
  EXPECT_EQ(stored.size(), 16u);
  EXPECT_EQ(ours.size(), 16u);
  EXPECT_NE(stored, ours);
  // A merge of stores of different configurations is refused too.
  ASSERT_EQ(run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "other")).exit_code, 0);
  write_text(campaign, "seed: 3\ngrids:\n  - name: far\n    speed_kph: 72\n    ttc_s: [2.5, 2.9]\n");
  ASSERT_EQ(run_emrm("sweep " + quoted(campaign) + " -o " + quoted(dir / "third")).exit_code, 0);
  expect_bad_input(
      run_emrm("merge -o " + quoted(dir / "m") + " " + quoted(dir / "other") + " " + quoted(dir / "third")),
      "different configurations");
}

TEST(SweepCli, BadCampaignFilesExit2WithLineAndColumn) {
  const auto dir = scratch_dir("sweep_bad");
  const auto check = [&](const std::string& text, const std::string& what) {
    const auto file = dir / "bad.yaml";
    write_text(file, text);
    expect_bad_input(run_emrm("sweep " + quoted(file) + " -o " + quoted(dir / "out")), what);
  };
  check("grids:\n  - name: g\n    sped_kph: 30\n", "bad.yaml:3:5: error: unknown grid field 'sped_kph'");
  check("strategies: [dodge, swerve]\ngrids:\n  - name: g\n", "bad.yaml:1:21: error: ");
  check("grids:\n  - name: g\n    ttc_s: []\n", "bad.yaml:3:12: error: empty list");
  check("grids:\n  - name: g\n    ttc_s: {from: 2, to: 1, step: 0.1}\n", "bad.yaml:3:12: error: reversed range");
  check("grids:\n  - name: g\n    ttc_s: {from: 1, to: 2, step: 0}\n", "bad.yaml:3:35: error: step must be > 0");
  check("grids:\n  - name: g\n    ttc_s: {from: 1, to: 2, levels: 0}\n", "bad.yaml:3:37: error: levels must be >= 1");
  check("grids: [\n", "bad.yaml:");
  check("max_cells: 3\ngrids:\n  - name: g\n    speed_kph: 72\n    ttc_s: [2.0, 2.3, 2.6, 2.9]\n",
        "bad.yaml:3:5: error: grid 'g' has 4 cells, more than the maximum 3; raise max_cells or pass --force");
  EXPECT_FALSE(fs::exists(dir / "out" / "results.sqlite"));

  // The same grid goes through with --force (infeasible cells: nothing to simulate).
  const auto r = run_emrm("sweep " + quoted(dir / "bad.yaml") + " -o " + quoted(dir / "out") + " --force");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Swept 4 cells"));
}

TEST(SweepCli, BadShardsExit2) {
  const auto dir = scratch_dir("sweep_shard");
  const auto file = dir / "c.yaml";
  write_text(file, "grids:\n  - name: far\n    speed_kph: 72\n    ttc_s: 2.9\n");
  for (const char* shard : {"0/2", "3/2", "x", "1/0"})
    expect_bad_input(run_emrm("sweep " + quoted(file) + " -o " + quoted(dir / "out") + " --shard " + shard), "--shard");
}

}  // namespace sweep_cli_test
}  // namespace emrm::e2e
