#pragma once

// Private to the sweep (sweep.cpp, sweep_progress.cpp, sweep_adaptive.cpp): the cells to run and
// their cost classes, the committer that stores their records and shows the progress, the loops
// that simulate them, a Distributor beside this process's threads, and the adaptive search of one
// grid.

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/distribute.hpp"
#include "emrm/campaign/eta.hpp"
#include "emrm/campaign/records.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"

namespace emrm::campaign::detail {

using Clock = std::chrono::steady_clock;

struct WorkItem {
  std::uint32_t grid;
  std::uint32_t index;
  int cost = 0;        ///< expected_cost()
  bool probe = false;  ///< among the first cells of its class (order_work)
};

// Results wait here until one thread commits them. Any worker that finds 64 results waiting, or
// 0.5 s since the last commit, commits them itself (try_lock: the others keep simulating), so no
// thread ever waits for a batch to end and memory holds at most a batch or two.
class Committer {
 public:
  /// `log`: the open --progress-log, or null.
  Committer(ResultStore& store, std::size_t total, bool progress, std::string unit, EtaModel eta, std::FILE* log);
  Committer(const Committer&) = delete;
  Committer& operator=(const Committer&) = delete;

  /// A cell's record, its cost class and the seconds its worker spent on it.
  void add(CellRecord record, int cost, double seconds);

  /// Commits what is left; called once the workers are done.
  void finish();

  [[nodiscard]] std::size_t simulated() const noexcept { return simulated_.load(); }

  /// An adaptive search decides as it goes how many cells it simulates: no estimate then.
  void drop_estimate() { estimate_ = false; }

 private:
  static constexpr std::size_t kBatchCells = 64;
  static constexpr std::int64_t kBatchNs = 500'000'000;

  std::int64_t now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start_).count();
  }

  void flush_locked();
  [[nodiscard]] std::optional<double> remaining_s();
  // One JSON line per commit: what a user without a terminal (or a benchmark) reads.
  void log_line();
  void draw();

  ResultStore& store_;
  std::size_t total_;
  bool progress_;
  std::string unit_;
  Clock::time_point start_;
  std::mutex pending_mutex_;
  std::vector<CellRecord> pending_;
  std::mutex commit_mutex_;
  std::atomic<std::int64_t> last_commit_ns_{0};
  std::atomic<std::size_t> simulated_{0};
  bool drew_ = false;
  EtaModel eta_;  // guarded by pending_mutex_
  bool estimate_ = true;
  std::FILE* log_ = nullptr;
};

struct CloseFile {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// The --progress-log, opened before the store: a path that cannot be written is bad input and fails
// with nothing written. A log is a stream read while the sweep runs, so it is written in place.
std::unique_ptr<std::FILE, CloseFile> open_progress_log(const std::filesystem::path& log);

// The threads of this process that simulate: --threads, or every core.
int local_threads(int threads);

// 2: braking alone (through the scene's actuators) cannot stop in time, so every search runs;
// 1: feasible; 0: infeasible, nothing is simulated.
int expected_cost(const Campaign& campaign, const WorkItem& item);

// The order cells run in (results do not depend on it): within each cost class shuffled with a
// fixed seed, so the cells done early are a fair sample of their class for the ETA; first a probe
// of 5 % of every class, so every class's cost is known early; then the dearest first, so
// the run ends with cheap cells and no worker idles long behind a dear one at the end.
std::array<std::size_t, EtaModel::kClasses> order_work(std::vector<WorkItem>& work);

// `loops` loops, each a task of its own so that each can run on a thread of its own: each
// simulates the cells `take` gives until it gives none and hands each record to `done` with the
// seconds it took. Returns the thread-seconds spent simulating.
template <class Take, class Done>
double simulate_in_loops(const Campaign& campaign, int loops, Take&& take, Done&& done) {
  std::atomic<std::int64_t> busy_ns{0};
  tbb::parallel_for(
      0, loops,
      [&](int) {
        while (const auto task = take()) {
          const auto start = Clock::now();
          CellRecord record = simulate_task(campaign, *task);
          const auto spent = Clock::now() - start;
          busy_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(spent).count();
          done(std::move(record), task->cost, std::chrono::duration<double>(spent).count());
        }
      },
      tbb::simple_partitioner());
  return static_cast<double>(busy_ns.load()) * 1e-9;
}

// `distributor` works on this thread (an MPI library may want its calls on the main one) while
// `here` runs on another; `stop` makes both end early when one fails. Rethrows what either threw.
template <class Here, class Stop>
void beside_distributor(Distributor& distributor, const Campaign& campaign, TaskQueue& queue, Here&& here,
                        Stop&& stop) {
  std::exception_ptr failed;
  {
    std::jthread local([&] {
      try {
        here();
      } catch (...) {
        failed = std::current_exception();
        stop();
      }
    });
    try {
      distributor.distribute(campaign, queue);
    } catch (...) {
      stop();
      throw;
    }
  }
  if (failed) std::rethrow_exception(failed);
}

// One grid by the adaptive search: the cells it asks for are simulated (or read back), the
// others stored as inferred in batches, then the summary.
AdaptiveSummary sweep_adaptive(const Campaign& campaign, std::size_t g, ResultStore& store, Committer& committer,
                               const SweepOptions& options, double& simulation_seconds);

}  // namespace emrm::campaign::detail
