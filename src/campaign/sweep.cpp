#include "emrm/campaign/sweep.hpp"

#include <fmt/format.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <optional>
#include <string_view>

#include "emrm/campaign/distribute.hpp"
#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/interrupt.hpp"
#include "sweep_parts.hpp"

namespace emrm::campaign {
namespace {

using Clock = std::chrono::steady_clock;
using detail::beside_distributor;
using detail::Committer;
using detail::expected_cost;
using detail::local_threads;
using detail::open_progress_log;
using detail::order_work;
using detail::simulate_in_loops;
using detail::sweep_adaptive;
using detail::WorkItem;

// The work of a sweep as a Distributor sees it: the same counter the sweep's threads take cells
// from, so other processes get cells in the same dearest-first order, and the same committer.
class SweepQueue final : public TaskQueue {
 public:
  SweepQueue(const std::vector<WorkItem>& work, Committer& committer) : work_(work), committer_(committer) {}

  std::optional<CellTask> next() override {
    // After an interrupt (or a failure on the other side) no cell is handed out.
    if (core::interrupt_signal() != 0 || stopped_.load()) return std::nullopt;
    const std::size_t w = next_++;
    if (w >= work_.size()) return std::nullopt;
    return CellTask{work_[w].grid, work_[w].index, work_[w].cost};
  }
  [[nodiscard]] std::size_t remaining() const override {
    const std::size_t taken = next_.load();
    return taken < work_.size() ? work_.size() - taken : 0;
  }
  void deliver(CellRecord record, int cost, double seconds) override {
    committer_.add(std::move(record), cost, seconds);
  }
  /// No more cells for anyone: the distributor or this process's threads failed.
  void stop() noexcept { stopped_ = true; }

  /// This process's threads: simulate cells until none is left; returns the thread-seconds spent.
  double simulate(const Campaign& campaign, int workers) {
    // More worker loops than threads is harmless: a loop that starts late finds nothing left.
    return simulate_in_loops(
        campaign, workers, [&] { return next(); },
        [&](CellRecord record, int cost, double seconds) { committer_.add(std::move(record), cost, seconds); });
  }

 private:
  const std::vector<WorkItem>& work_;
  Committer& committer_;
  std::atomic<std::size_t> next_{0};
  std::atomic<bool> stopped_{false};
};

}  // namespace

CellRecord simulate_task(const Campaign& campaign, const CellTask& task) {
  const GridSpec& grid = campaign.grids[task.grid];
  const sim::CellInput& cell = grid.cells[task.index];
  sim::CellOptions options;
  options.strategies = campaign.strategies;
  options.seed = cell_seed(campaign, grid, task.index);
  options.keep_trees = grid.keep_trees;
  const sim::CellResult result = sim::simulate_cell(campaign.scene, cell, options);
  return to_record(campaign.scene, grid.name, static_cast<std::int64_t>(task.index), options.seed, result,
                   grid.keep_trees);
}

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
  std::vector<char> adaptive(campaign.grids.size(), 0);
  for (std::size_t g = 0; g < campaign.grids.size(); ++g)
    adaptive[g] =
        static_cast<char>((options.adaptive || campaign.grids[g].adaptive) && !campaign.grids[g].levels.empty());
  const bool any_adaptive = std::find(adaptive.begin(), adaptive.end(), 1) != adaptive.end();
  if (any_adaptive && options.shard_count > 1)
    throw UsageError(
        "--shard cannot split an adaptive sweep: the search picks each cell from the ones simulated "
        "before; run it on one machine (every core: --threads 0)");
  const auto start = Clock::now();
  CampaignMeta meta = make_meta(campaign);
  meta.shard_index = options.shard_index;
  meta.shard_count = options.shard_count;
  const auto store_path = options.output_dir / kStoreFile;

  SweepSummary summary;
  {
    const auto log = open_progress_log(options.progress_log);
    ResultStore store = ResultStore::open_for_writing(store_path, meta);
    std::vector<std::vector<char>> done(campaign.grids.size());
    for (std::size_t g = 0; g < campaign.grids.size(); ++g) done[g].assign(campaign.grids[g].cells.size(), 0);
    store.for_each_key([&](std::size_t g, std::int64_t i) {
      if (g < done.size() && i >= 0 && static_cast<std::size_t>(i) < done[g].size())
        done[g][static_cast<std::size_t>(i)] = 1;
    });

    std::vector<WorkItem> work;
    std::size_t position = 0;        // global position over all grids, for sharding
    std::size_t adaptive_cells = 0;  // at most this many simulations (the progress bar's total)
    for (std::size_t g = 0; g < campaign.grids.size(); ++g) {
      const GridSpec& grid = campaign.grids[g];
      if (adaptive[g]) {
        summary.cells_total += grid.cells.size();
        for (std::size_t i = 0; i < grid.cells.size(); ++i) summary.cells_done_before += done[g][i];
        adaptive_cells += grid.cells.size();
        position += grid.cells.size();
        continue;
      }
      store.delete_inferred(grid.name);  // simulated this time
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

    const auto counts = order_work(work);
    std::optional<tbb::global_control> limit;
    if (options.threads > 0)
      limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(options.threads));
    const int workers = std::max(options.threads, tbb::info::default_concurrency());
    Committer committer(store, work.size() + adaptive_cells, options.progress && ::isatty(2) == 1, options.unit,
                        EtaModel(counts), log.get());
    if (any_adaptive) committer.drop_estimate();
    SweepQueue queue(work, committer);
    if (options.distributor == nullptr) {
      summary.simulation_seconds = queue.simulate(campaign, workers);
    } else {
      // The local threads end with the cell in hand when either side fails.
      beside_distributor(
          *options.distributor, campaign, queue,
          [&] { summary.simulation_seconds = queue.simulate(campaign, workers); }, [&] { queue.stop(); });
    }
    committer.finish();
    if (any_adaptive && options.distributor != nullptr) {
      // A search thread per simulation in flight on any process (sweep_adaptive): more than this
      // process's threads, most of them waiting.
      limit.reset();
      limit.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(local_threads(options.threads) + options.distributor->threads()));
    }
    for (std::size_t g = 0; g < campaign.grids.size() && core::interrupt_signal() == 0; ++g) {
      if (!adaptive[g]) continue;
      AdaptiveSummary grid_summary = sweep_adaptive(campaign, g, store, committer, options, summary.simulation_seconds);
      committer.finish();
      if (core::interrupt_signal() == 0) summary.adaptive.push_back(std::move(grid_summary));
    }
    summary.cells_simulated = committer.simulated();
  }
  if (const int signal = core::interrupt_signal(); signal != 0)
    throw core::Interrupted(
        signal, fmt::format("interrupted: {} of {} {} stored in {}; rerun the same command to resume",
                            summary.cells_done_before + summary.cells_simulated, summary.cells_total, options.unit,
                            store_path.string()));
  summary.grids = write_exports(store_path, options.output_dir);
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

}  // namespace emrm::campaign
