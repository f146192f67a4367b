// `mpirun -n N emrm sweep|run|reproduce ... --mpi` (docs/cluster.md): the outputs of one process
// for any number of ranks, the adaptive search's included; a worker rank or the whole job killed
// with SIGKILL loses nothing the rerun cannot complete, and nothing is stored twice; a hung
// worker's cells go to the others; what MPI cannot run is refused with exit 2 and one message.
// Registered only when emrm is built with MPI (EMRM_WITH_MPI).

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "run_emrm.hpp"
#include "small_example.hpp"
#include "spawn_process.hpp"
#include "test_scale.hpp"

namespace emrm::e2e {
namespace mpi_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// 64 cells, infeasible, cheap and dear; 16 under the sanitizers.
const std::string kSmall = std::string("seed: 5\ngrids:\n  - name: map\n") +
                           "    speed_kph: {from: 30, to: 72, step: " + test::sample("6", "14") + "}\n" +
                           "    ttc_s: {from: 0.25, to: 1.45, step: " + test::sample("0.16", "0.3") + "}\n";
// 128 cells (64 under the sanitizers): long enough to be killed halfway.
const std::string kLonger = std::string("seed: 5\ngrids:\n  - name: map\n") +
                            "    speed_kph: {from: 30, to: 72, step: 6}\n" +
                            "    ttc_s: {from: 0.25, to: 1.45, step: " + test::sample("0.08", "0.16") + "}\n";

// mpirun's words before emrm's: more ranks than cores; as root too, as in a CI container; and
// shared-memory messages copied through a buffer, since a container's seccomp profile may forbid
// one process reading another's memory (Open MPI's single copy).
std::vector<std::string> mpirun_words(int ranks) {
  return {EMRM_MPIEXEC,
          "--oversubscribe",
          "--allow-run-as-root",
          "--mca",
          "btl_vader_single_copy_mechanism",
          "none",
          "-n",
          std::to_string(ranks),
          EMRM_BINARY};
}

std::string mpirun(int ranks) {
  std::string command;
  for (const std::string& word : mpirun_words(ranks)) command += (command.empty() ? "" : " ") + quoted(word);
  return command;
}

// The planner's wall-clock guard (planner.max_time_ms, 5 s) out of reach: with more ranks than
// cores beside the other tests a dear cell's search may take longer, and a search it stops is the
// one thing that makes a cell's record depend on the machine, not only on its seed.
constexpr const char* kNoTimeGuard = "planner:\n  max_time_ms: 3600000\n";

// `campaign` written to FILE, its scene beside it: the built-in one without the time guard.
void write_campaign(const fs::path& file, const std::string& campaign) {
  write_text(file.parent_path() / "scene.yaml", kNoTimeGuard);
  write_text(file, "scene: scene.yaml\n" + campaign);
}

// The small example copied for `name`, its scene's time guard out of reach.
fs::path example_without_time_guard(const std::string& name) {
  const fs::path example = small_example(name);
  std::string scene = read_text(example / "scene.yaml");
  const std::string guard = "max_time_ms: 5000.0";
  const auto at = scene.find(guard);
  EXPECT_NE(at, std::string::npos) << "the example's scene no longer sets " << guard;
  if (at != std::string::npos) scene.replace(at, guard.size(), "max_time_ms: 3600000.0");
  write_text(example / "scene.yaml", scene);
  return example;
}

// Runs `command` through the shell, its output kept in DIR.
RunResult run_shell(const std::string& command, const fs::path& dir) {
  const int status = std::system(
      (command + " >'" + (dir / "mpi.out").string() + "' 2>'" + (dir / "mpi.err").string() + "' </dev/null").c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = read_text(dir / "mpi.out");
  result.err = read_text(dir / "mpi.err");
  return result;
}

// Runs `mpirun -n RANKS emrm ARGS` through the shell, as run_emrm runs emrm.
RunResult run_mpi(int ranks, const std::string& args, const fs::path& dir) {
  return run_shell(mpirun(ranks) + " " + args, dir);
}

// The number of cells in a store, as text; empty while there is no store.
std::string stored_cells(const fs::path& store) {
  if (!fs::exists(store)) return {};
  std::FILE* count =
      ::popen(("sqlite3 '" + store.string() + "' 'SELECT count(*) FROM cells' 2>/dev/null").c_str(), "r");
  std::string text;
  for (int c = std::fgetc(count); c != EOF; c = std::fgetc(count)) text += static_cast<char>(c);
  return ::pclose(count) == 0 ? text : std::string();
}

// Every stored row, in key order: the whole store, not only what the exports show (maneuvers,
// traces, certificates), must survive the trip between ranks.
std::string store_rows(const fs::path& store) {
  const fs::path dump = store.string() + ".rows";
  const std::string command = "sqlite3 '" + store.string() +
                              "' 'SELECT * FROM cells ORDER BY grid, cell_index; SELECT * FROM outcomes ORDER BY "
                              "grid, cell_index, position' > '" +
                              dump.string() + "'";
  EXPECT_EQ(std::system(command.c_str()), 0);
  return read_text(dump);
}

// The process ids of the ranks, children of mpirun (Open MPI starts local ranks itself, each in a
// process group of its own), by rank.
std::map<int, pid_t> rank_pids(pid_t mpirun_pid) {
  const std::string key = "OMPI_COMM_WORLD_RANK=";
  std::map<int, pid_t> ranks;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string pid, comm, state;
    pid_t parent = 0;
    if (!(stat >> pid >> comm >> state >> parent) || parent != mpirun_pid) continue;
    const std::string env = read_text(entry.path() / "environ");
    for (std::size_t at = 0; at < env.size();) {
      const std::size_t end = std::min(env.find('\0', at), env.size());
      if (env.compare(at, key.size(), key) == 0)
        ranks[std::stoi(env.substr(at + key.size(), end - at - key.size()))] = static_cast<pid_t>(std::stoi(name));
      at = end + 1;
    }
  }
  return ranks;
}

// Starts `mpirun -n RANKS emrm ARGS`; once the store holds a cell, sends `signal` to rank `victim`,
// or SIGKILL to every rank and mpirun when `victim` < 0; waits for mpirun.
RunResult signalled_mpi(int ranks, const std::vector<std::string>& args, const fs::path& store, int victim, int signal,
                        const fs::path& dir) {
  std::vector<std::string> words = mpirun_words(ranks);
  words.insert(words.end(), args.begin(), args.end());
  const pid_t pid = spawn_process(words, dir);
  for (int i = 0; i < 1200; ++i) {  // up to a minute (the sanitizers start slowly)
    const std::string count = stored_cells(store);
    if (!count.empty() && std::stoi(count) > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const auto pids = rank_pids(pid);  // none when the job has ended already: the caller skips
  if (victim < 0) {
    for (const auto& [rank, rank_pid] : pids) ::kill(rank_pid, SIGKILL);
    ::kill(pid, SIGKILL);
  } else if (const auto it = pids.find(victim); it != pids.end()) {
    ::kill(it->second, signal);
  }
  return wait_for_process(pid, dir);
}

// The folder of a plain sweep of `campaign` (2 threads): what every MPI run must write.
fs::path plain_sweep(const fs::path& dir, const std::string& campaign) {
  write_campaign(dir / "campaign.yaml", campaign);
  const auto plain =
      run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "plain") + " --threads 2");
  EXPECT_EQ(plain.exit_code, 0) << plain.err;
  return dir / "plain";
}

void expect_same_results(const fs::path& got, const fs::path& want) {
  for (const char* file : {"regions.csv", "cells.csv", "cells.json"})
    EXPECT_EQ(read_text(got / file), read_text(want / file)) << file;
  EXPECT_EQ(store_rows(got / "results.sqlite"), store_rows(want / "results.sqlite"));
}

TEST(MpiCli, OneTwoAndFourRanksWriteWhatOneProcessWrites) {
  const auto dir = scratch_dir("mpi-ranks");
  const auto plain = plain_sweep(dir, kSmall);
  for (int ranks : {1, 2, 4}) {
    const auto out = dir / ("ranks" + std::to_string(ranks));
    const auto r =
        run_mpi(ranks, "sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(out) + " --mpi --threads 1", dir);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_THAT(r.out, HasSubstr("on " + std::to_string(ranks) + " MPI rank"));
    EXPECT_THAT(r.out, HasSubstr("Simulation seconds per rank: "));
    EXPECT_THAT(r.out, HasSubstr("above the mean per thread"));
    if (ranks > 1) {
      EXPECT_THAT(r.out, HasSubstr("Coordination on rank 0: "));
    }
    expect_same_results(out, plain);
  }
}

// `mpirun -n RANKS emrm sweep` of the 128 cells into DIR/out with the rank `victim` sent `signal`
// once the store holds a cell (every rank and mpirun killed when `victim` < 0): what it printed.
RunResult signalled_sweep(const fs::path& dir, int ranks, int victim, int signal,
                          const std::vector<std::string>& more_args = {}) {
  std::vector<std::string> args{
      "sweep", (dir / "campaign.yaml").string(), "-o", (dir / "out").string(), "--mpi", "--threads", "1"};
  args.insert(args.end(), more_args.begin(), more_args.end());
  return signalled_mpi(ranks, args, dir / "out" / "results.sqlite", victim, signal, dir);
}

// The store in DIR/out holds every cell once, and its rows and exports are a plain sweep's.
void expect_complete(const fs::path& dir, const fs::path& plain) {
  EXPECT_EQ(stored_cells(dir / "out" / "results.sqlite"), stored_cells(plain / "results.sqlite"));
  expect_same_results(dir / "out", plain);
}

// The same command again completes what a killed job left.
void expect_rerun_completes(const fs::path& dir, int ranks, const fs::path& plain) {
  const auto resumed = run_mpi(
      ranks, "sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "out") + " --mpi --threads 1", dir);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  EXPECT_THAT(resumed.out, HasSubstr("already stored"));
  expect_complete(dir, plain);  // none lost, none twice
}

TEST(MpiCli, AWorkerKilledMidRunLosesNothingTheRerunCompletes) {
  const auto dir = scratch_dir("mpi-kill-worker");
  const auto plain = plain_sweep(dir, kLonger);
  if (signalled_sweep(dir, 3, 1, SIGKILL).exit_code == 0) GTEST_SKIP() << "the sweep ended before the kill";
  expect_rerun_completes(dir, 3, plain);
}

TEST(MpiCli, TheWholeJobKilledLosesNothingTheRerunCompletes) {
  const auto dir = scratch_dir("mpi-kill-job");
  const auto plain = plain_sweep(dir, kLonger);
  if (signalled_sweep(dir, 2, -1, SIGKILL).exit_code == 0) GTEST_SKIP() << "the sweep ended before the kill";
  expect_rerun_completes(dir, 2, plain);
}

TEST(MpiCli, AHungWorkersCellsGoToTheOthers) {
  const auto dir = scratch_dir("mpi-hung-worker");
  const auto plain = plain_sweep(dir, kLonger);
  const auto stopped = signalled_sweep(dir, 3, 1, SIGSTOP, {"--mpi-hung-after", "3"});  // ended by MPI_Abort(0)
  // Open MPI 4.1's mpirun now and then crashes in its own cleanup after an MPI_Abort
  // (PMIx_server_finalize); the ranks' work is done by then, and what is checked below is theirs.
  const bool mpirun_crashed = stopped.err.find("PMIx_server_finalize") != std::string::npos;
  if (!mpirun_crashed) {
    EXPECT_EQ(stopped.exit_code, 0) << stopped.out << stopped.err;
  }
  if (stopped.out.find("Rank 1 said nothing for 3 s and was given up") == std::string::npos)
    GTEST_SKIP() << "the sweep ended before rank 1 stopped:\n" << stopped.out;
  expect_complete(dir, plain);
}

// A rank that stops half-way through sending a message (a large one, in fragments its sender must
// push) is given up by the receiver after its patience: rank 0 used to wait for the rest for ever,
// and the whole job with it (seen once in a thousand runs of the test above). The transport alone,
// in a program of its own (mpi_stall_probe.cpp), so that the stop falls where it must.
TEST(MpiCli, ARankStoppedHalfWayThroughAMessageIsGivenUp) {
  std::vector<std::string> words = mpirun_words(2);
  words.back() = EMRM_MPI_STALL_PROBE;
  std::string command;
  for (const std::string& word : words) command += (command.empty() ? "" : " ") + quoted(word);
  const RunResult r = run_shell(command, scratch_dir("mpi-stall"));
  if (r.exit_code == 77) GTEST_SKIP() << "the stop fell before or after the message: " << r.out;
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("gave up after"));
}

// One line of emrm's own on stderr (mpirun adds its banner about the exit code around it).
void expect_one_message(const RunResult& r, const std::string& message) {
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  std::size_t count = 0;
  for (auto at = r.err.find(message); at != std::string::npos; at = r.err.find(message, at + 1)) ++count;
  EXPECT_EQ(count, 1u) << r.err;
}

// 150 cells of the shipped scene for the adaptive search (about 30 simulated).
const std::string kAdaptive = std::string("seed: 5\ngrids:\n  - name: map\n") +
                              "    speed_kph: {from: 30, to: 72, step: 6}\n" +
                              "    ttc_s: {from: 0.25, to: 1.45, step: " + test::sample("0.07", "0.2") + "}\n";

// The search on rank 0 asks the ranks for its simulations one by one: the same cells simulated,
// the same cells inferred, the same store, whichever rank simulated each.
TEST(MpiCli, TheAdaptiveSearchOnTwoRanksWritesWhatOneProcessWrites) {
  const auto dir = scratch_dir("mpi-adaptive");
  write_campaign(dir / "campaign.yaml", kAdaptive);
  const auto plain =
      run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "plain") + " --adaptive --threads 2");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto r = run_mpi(
      2, "sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "out") + " --adaptive --mpi --threads 1",
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string search = plain.out.substr(plain.out.find("grid 'map'"));
  EXPECT_THAT(r.out, HasSubstr(search.substr(0, search.find("Wrote"))));  // simulated, inferred, verified alike
  EXPECT_THAT(r.out, HasSubstr("Coordination on rank 0: "));              // rank 1 simulated some of them
  expect_same_results(dir / "out", dir / "plain");
}

TEST(MpiCli, TheAdaptiveSearchKilledResumesToTheSameMap) {
  const auto dir = scratch_dir("mpi-adaptive-kill");
  write_campaign(dir / "campaign.yaml", kAdaptive);
  ASSERT_EQ(
      run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "plain") + " --adaptive").exit_code, 0);
  const std::vector<std::string> args{
      "sweep", (dir / "campaign.yaml").string(), "-o", (dir / "out").string(), "--adaptive", "--mpi", "--threads", "1"};
  if (signalled_mpi(2, args, dir / "out" / "results.sqlite", -1, SIGKILL, dir).exit_code == 0)
    GTEST_SKIP() << "the search ended before the kill";
  const auto resumed = run_mpi(
      2, "sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "out") + " --adaptive --mpi --threads 1",
      dir);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
  expect_same_results(dir / "out", dir / "plain");
}

// A planned run's scenarios handed out as a sweep's cells: every file `emrm run` writes is one
// process's.
TEST(MpiCli, RunOnOneAndTwoRanksWritesWhatOneProcessWrites) {
  const auto example = example_without_time_guard("mpi-run");
  const auto dir = example.parent_path();
  ASSERT_EQ(run_emrm("plan " + quoted(example / "odd.yaml") + " -o " + quoted(dir / "plan")).exit_code, 0);
  const std::string run = "run " + quoted(dir / "plan" / "scenarios.csv") + " -o ";
  const auto plain = run_emrm(run + quoted(dir / "plain") + " --threads 2");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  for (int ranks : {1, 2}) {
    const auto out = dir / ("ranks" + std::to_string(ranks));
    const auto r = run_mpi(ranks, run + quoted(out) + " --mpi --threads 1", dir);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_THAT(r.out, HasSubstr("8 simulated"));
    for (const char* file : {"outcomes.csv", "estimates.csv", "estimates.json", "traceability.csv"})
      EXPECT_EQ(read_text(out / file), read_text(dir / "plain" / file)) << file;
    expect_same_results(out, dir / "plain");
  }
}

// Every sweep of reproduce (the campaign's, each profile's, the planned run's) on the ranks, the
// rest on rank 0: the tables and stores of one process. Bad input: exit 2 on every rank, said once.
TEST(MpiCli, ReproduceOnTwoRanksWritesWhatOneProcessWrites) {
  const auto example = example_without_time_guard("mpi-reproduce");
  const auto dir = example.parent_path();
  const std::string reproduce = "reproduce --examples " + quoted(example) + " --sample 1 -o ";
  const auto plain = run_emrm(reproduce + quoted(dir / "plain") + " --threads 2");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto r = run_mpi(2, reproduce + quoted(dir / "out") + " --mpi --threads 1", dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("Report: "));
  for (const char* file : {"tables/emrm_vs_baseline.csv", "tables/regions.csv", "tables/regions_by_profile.csv",
                           "tables/coverage.csv", "tables/kpis.csv", "diagnostics.json", "verify.json",
                           "plan_results/estimates.csv", "plan_results/outcomes.csv", "profiles/index.json"})
    EXPECT_EQ(read_text(dir / "out" / file), read_text(dir / "plain" / file)) << file;
  expect_same_results(dir / "out", dir / "plain");
  expect_same_results(dir / "out" / "plan_results", dir / "plain" / "plan_results");
  for (const auto& profile : fs::directory_iterator(dir / "plain" / "profiles"))
    if (profile.is_directory())
      expect_same_results(dir / "out" / "profiles" / profile.path().filename(), profile.path());

  expect_one_message(
      run_mpi(3, "reproduce --examples " + quoted(dir / "nowhere") + " --mpi -o " + quoted(dir / "x"), dir),
      "is not a folder");
  EXPECT_FALSE(fs::exists(dir / "x"));
}

TEST(MpiCli, RefusesWhatItCannotDistributeOnceWithExit2) {
  const auto dir = scratch_dir("mpi-refused");
  write_campaign(dir / "campaign.yaml", kSmall);
  const std::string sweep = "sweep " + quoted(dir / "campaign.yaml") + " --mpi -o ";
  expect_one_message(run_mpi(2, sweep + quoted(dir / "shard") + " --shard 1/2", dir), "--mpi with --shard");
  write_text(dir / "broken.yaml", "grids: [\n");
  expect_one_message(run_mpi(3, "sweep " + quoted(dir / "broken.yaml") + " --mpi -o " + quoted(dir / "broken"), dir),
                     "broken.yaml:");

  // A store of another configuration, as without MPI.
  ASSERT_EQ(run_mpi(2, sweep + quoted(dir / "out") + " --threads 1", dir).exit_code, 0);
  write_campaign(dir / "other.yaml", "seed: 6\n" + kSmall.substr(kSmall.find('\n') + 1));
  expect_one_message(run_mpi(2, "sweep " + quoted(dir / "other.yaml") + " --mpi -o " + quoted(dir / "out"), dir),
                     "come from another configuration");
}

TEST(MpiCli, WithoutALauncherSaysHowToStartIt) {
  const auto dir = scratch_dir("mpi-alone");
  write_campaign(dir / "campaign.yaml", kSmall);
  const auto r = run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "out") + " --mpi");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("not started by an MPI launcher"));
  EXPECT_THAT(r.err, HasSubstr("mpirun -n N"));
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace mpi_cli_test
}  // namespace emrm::e2e
