#include "emrm/campaign/sweep.hpp"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>

#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::campaign {
namespace {

using Clock = std::chrono::steady_clock;

struct WorkItem {
  std::uint32_t grid;
  std::uint32_t index;
  int cost = 0;  ///< expected_cost()
};

// Results wait here until one thread commits them. Any worker that finds 64 results waiting, or
// 0.5 s since the last commit, commits them itself (try_lock: the others keep simulating), so no
// thread ever waits for a batch to end and memory holds at most a batch or two.
class Committer {
 public:
  Committer(ResultStore& store, std::size_t total, bool progress, std::string unit)
      : store_(store), total_(total), progress_(progress), unit_(std::move(unit)), start_(Clock::now()) {
    last_commit_ns_ = now_ns();
  }

  void add(CellRecord record) {
    std::size_t waiting = 0;
    {
      std::lock_guard lock(pending_mutex_);
      pending_.push_back(std::move(record));
      waiting = pending_.size();
    }
    ++simulated_;
    if (waiting < kBatchCells && now_ns() - last_commit_ns_.load() < kBatchNs) return;
    std::unique_lock lock(commit_mutex_, std::try_to_lock);
    if (lock) flush_locked();
  }

  /// Commits what is left; called once the workers are done.
  void finish() {
    std::lock_guard lock(commit_mutex_);
    flush_locked();
    if (progress_ && drew_) std::fputs("\n", stderr);
  }

  [[nodiscard]] std::size_t simulated() const noexcept { return simulated_.load(); }

 private:
  static constexpr std::size_t kBatchCells = 64;
  static constexpr std::int64_t kBatchNs = 500'000'000;

  std::int64_t now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start_).count();
  }

  void flush_locked() {
    std::vector<CellRecord> batch;
    {
      std::lock_guard lock(pending_mutex_);
      batch.swap(pending_);
    }
    store_.insert(batch);
    last_commit_ns_ = now_ns();
    if (progress_) draw();
  }

  void draw() {
    const std::size_t done = simulated_.load();
    const double seconds = static_cast<double>(now_ns()) * 1e-9;
    const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
    const double fraction = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string eta = "--:--";
    if (rate > 0.0) {
      const auto left = static_cast<long long>(static_cast<double>(total_ - done) / rate);
      eta = fmt::format("{}:{:02d}", left / 60, left % 60);
    }
    std::fprintf(stderr, "\r[%s%s] %zu/%zu %s  %.1f %s/s  ETA %s ", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), done, total_, unit_.c_str(), rate, unit_.c_str(),
                 eta.c_str());
    std::fflush(stderr);
    drew_ = true;
  }

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
};

// 2: braking alone cannot stop in time, every RRT strategy spends its budget (up to ~150 ms);
// 1: feasible; 0: infeasible, nothing is simulated.
int expected_cost(const Campaign& campaign, const WorkItem& item) {
  const sim::CellInput& cell = campaign.grids[item.grid].cells[item.index];
  const double v_mps = cell.speed_kph / 3.6;
  const double distance_m = v_mps * cell.ttc_s;
  if (!sim::Scene(campaign.scene, cell).feasible()) return 0;
  return v_mps * v_mps / (2.0 * cell.mu * sim::kGravity_mps2) > distance_m ? 2 : 1;
}

}  // namespace

void parse_shard(const std::string& text, int& index, int& count) {
  const auto slash = text.find('/');
  const auto parse = [&](std::string_view part, int& value) {
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    return ec == std::errc() && end == part.data() + part.size() && !part.empty();
  };
  int k = 0;
  int n = 0;
  if (slash == std::string::npos || !parse(std::string_view(text).substr(0, slash), k) ||
      !parse(std::string_view(text).substr(slash + 1), n) || n < 1 || k < 1 || k > n)
    throw UsageError(fmt::format("--shard: expected K/N with 1 <= K <= N (for example 1/4), got '{}'", text));
  index = k;
  count = n;
}

SweepSummary sweep(const Campaign& campaign, const SweepOptions& options) {
  // Once per sweep rather than per cell (simulate_cell validates the scene again, cheaply). The
  // max_cells limit guards loading; the cells here are already expanded.
  validate(campaign, /*force=*/true);
  if (options.shard_count < 1 || options.shard_index < 1 || options.shard_index > options.shard_count)
    throw UsageError(
        fmt::format("shard {}/{}: expected K/N with 1 <= K <= N", options.shard_index, options.shard_count));
  if (options.threads < 0) throw UsageError(fmt::format("--threads must be >= 0, got {}", options.threads));
  const auto start = Clock::now();
  CampaignMeta meta = make_meta(campaign);
  meta.shard_index = options.shard_index;
  meta.shard_count = options.shard_count;
  const auto store_path = options.output_dir / "results.sqlite";

  SweepSummary summary;
  {
    ResultStore store = ResultStore::open_for_writing(store_path, meta);
    std::vector<std::vector<char>> done(campaign.grids.size());
    for (std::size_t g = 0; g < campaign.grids.size(); ++g) done[g].assign(campaign.grids[g].cells.size(), 0);
    store.for_each_key([&](std::size_t g, std::int64_t i) {
      if (g < done.size() && i >= 0 && static_cast<std::size_t>(i) < done[g].size())
        done[g][static_cast<std::size_t>(i)] = 1;
    });

    std::vector<WorkItem> work;
    std::size_t position = 0;  // global position over all grids, for sharding
    for (std::size_t g = 0; g < campaign.grids.size(); ++g) {
      for (std::size_t i = 0; i < campaign.grids[g].cells.size(); ++i, ++position) {
        if (position % static_cast<std::size_t>(options.shard_count) !=
            static_cast<std::size_t>(options.shard_index - 1))
          continue;
        ++summary.cells_total;
        if (done[g][i]) {
          ++summary.cells_done_before;
          continue;
        }
        work.push_back({static_cast<std::uint32_t>(g), static_cast<std::uint32_t>(i)});
        work.back().cost = expected_cost(campaign, work.back());
      }
    }

    // Dearest cells first, then workers pull the next cell from a shared counter: the run ends
    // with cheap cells, so no thread idles long behind a 150 ms cell at the end.
    std::stable_sort(work.begin(), work.end(),
                     [&](const WorkItem& a, const WorkItem& b) { return a.cost > b.cost; });
    std::optional<tbb::global_control> limit;
    if (options.threads > 0)
      limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(options.threads));
    const int workers = std::max(options.threads, tbb::info::default_concurrency());
    Committer committer(store, work.size(), options.progress && ::isatty(2) == 1, options.unit);
    std::atomic<std::size_t> next{0};
    // More worker loops than threads is harmless: a loop that starts late finds nothing left.
    tbb::parallel_for(
        0, workers,
        [&](int) {
          // After an interrupt no worker takes another cell; the ones in flight finish.
          for (std::size_t w = next++; w < work.size() && core::interrupt_signal() == 0; w = next++) {
            const GridSpec& grid = campaign.grids[work[w].grid];
            const sim::CellInput& cell = grid.cells[work[w].index];
            sim::CellOptions cell_options;
            cell_options.strategies = campaign.strategies;
            cell_options.seed =
                grid.seeds.empty() ? cell_seed(campaign, grid.name, cell) : grid.seeds[work[w].index];
            cell_options.keep_trees = grid.keep_trees;
            const sim::CellResult result = sim::simulate_cell(campaign.scene, cell, cell_options);
            committer.add(to_record(grid.name, static_cast<std::int64_t>(work[w].index), cell_options.seed, result,
                                    grid.keep_trees));
          }
        },
        tbb::simple_partitioner());  // one task per worker loop, so each can run on its own thread
    committer.finish();
    summary.cells_simulated = committer.simulated();
  }
  if (const int signal = core::interrupt_signal(); signal != 0)
    throw core::Interrupted(signal, fmt::format("interrupted: {} of {} {} stored in {}; rerun the same command to resume",
                                                summary.cells_done_before + summary.cells_simulated,
                                                summary.cells_total, options.unit, store_path.string()));
  write_exports(store_path, options.output_dir);
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

}  // namespace emrm::campaign
