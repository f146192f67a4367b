#include "emrm/campaign/sweep.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <thread>
#include <unordered_map>

#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/distribute.hpp"
#include "emrm/campaign/eta.hpp"
#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/strategy.hpp"
#include "emrm/sim/vehicle.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace emrm::campaign {
namespace {

using Clock = std::chrono::steady_clock;

struct WorkItem {
  std::uint32_t grid;
  std::uint32_t index;
  int cost = 0;  ///< expected_cost()
  bool probe = false;  ///< among the first cells of its class (order_work)
};

// Results wait here until one thread commits them. Any worker that finds 64 results waiting, or
// 0.5 s since the last commit, commits them itself (try_lock: the others keep simulating), so no
// thread ever waits for a batch to end and memory holds at most a batch or two.
class Committer {
 public:
  /// `log`: the open --progress-log, or null.
  Committer(ResultStore& store, std::size_t total, bool progress, std::string unit, EtaModel eta, std::FILE* log)
      : store_(store),
        total_(total),
        progress_(progress),
        unit_(std::move(unit)),
        start_(Clock::now()),
        eta_(eta),
        log_(log) {
    last_commit_ns_ = now_ns();
  }
  Committer(const Committer&) = delete;
  Committer& operator=(const Committer&) = delete;

  /// A cell's record, its cost class and the seconds its worker spent on it.
  void add(CellRecord record, int cost, double seconds) {
    std::size_t waiting = 0;
    {
      std::lock_guard lock(pending_mutex_);
      pending_.push_back(std::move(record));
      waiting = pending_.size();
      eta_.record(cost, seconds);
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
    drew_ = false;  // called after every adaptive grid: one line break per bar
  }

  [[nodiscard]] std::size_t simulated() const noexcept { return simulated_.load(); }

  /// An adaptive search decides as it goes how many cells it simulates: no estimate then.
  void drop_estimate() { estimate_ = false; }

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
    if (log_ != nullptr) log_line();
  }

  [[nodiscard]] std::optional<double> remaining_s() {
    if (!estimate_) return std::nullopt;
    const double seconds = static_cast<double>(now_ns()) * 1e-9;
    std::lock_guard lock(pending_mutex_);
    return eta_.remaining_seconds(seconds);
  }

  // One JSON line per commit: what a user without a terminal (or a benchmark) reads.
  void log_line() {
    const auto left = remaining_s();
    std::fprintf(log_, "{\"done\": %zu, \"total\": %zu, \"elapsed_s\": %.3f, \"eta_s\": %s}\n", simulated_.load(),
                 total_, static_cast<double>(now_ns()) * 1e-9, left ? fmt::format("{:.3f}", *left).c_str() : "null");
    std::fflush(log_);
  }

  void draw() {
    const std::size_t done = simulated_.load();
    const double seconds = static_cast<double>(now_ns()) * 1e-9;
    const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
    const double fraction = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string eta = "--:--";
    if (const auto left_s = remaining_s()) {
      const auto left = std::llround(*left_s);
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
  EtaModel eta_;  // guarded by pending_mutex_
  bool estimate_ = true;
  std::FILE* log_ = nullptr;
};

struct CloseFile {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// The --progress-log, opened before the store: a path that cannot be written is bad input and fails
// with nothing written. A log is a stream read while the sweep runs, so it is written in place.
std::unique_ptr<std::FILE, CloseFile> open_progress_log(const std::filesystem::path& log) {
  if (log.empty()) return nullptr;
  std::unique_ptr<std::FILE, CloseFile> file(std::fopen(log.string().c_str(), "w"));
  if (!file) throw UsageError(fmt::format("--progress-log: cannot write '{}'", log.string()));
  return file;
}

// The threads of this process that simulate: --threads, or every core.
int local_threads(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

// 2: braking alone (through the scene's actuators) cannot stop in time, so every search runs;
// 1: feasible; 0: infeasible, nothing is simulated.
int expected_cost(const Campaign& campaign, const WorkItem& item) {
  const sim::CellInput& cell = campaign.grids[item.grid].cells[item.index];
  if (!sim::Scene(campaign.scene, cell).feasible()) return 0;
  return sim::stop_margin_m(cell.speed_kph, cell.ttc_s, cell.mu, campaign.scene.actuation) < 0.0 ? 2 : 1;
}

// The order cells run in (results do not depend on it): within each cost class shuffled with a
// fixed seed, so the cells done early are a fair sample of their class for the ETA; first a probe
// of 5 % of every class, so every class's cost is known early; then the dearest first, so
// the run ends with cheap cells and no worker idles long behind a dear one at the end.
std::array<std::size_t, EtaModel::kClasses> order_work(std::vector<WorkItem>& work) {
  std::mt19937_64 random(0x5eed5eedULL);
  std::shuffle(work.begin(), work.end(), random);
  std::stable_sort(work.begin(), work.end(), [](const WorkItem& a, const WorkItem& b) { return a.cost > b.cost; });
  std::array<std::size_t, EtaModel::kClasses> counts{}, taken{};
  for (const WorkItem& item : work) ++counts[static_cast<std::size_t>(item.cost)];
  for (WorkItem& item : work) {
    const auto c = static_cast<std::size_t>(item.cost);
    item.probe = taken[c]++ < std::max<std::size_t>(4, counts[c] / 20);  // 5 % of the class, at least 4
  }
  std::stable_partition(work.begin(), work.end(), [](const WorkItem& item) { return item.probe; });
  return counts;  // cells per class
}

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

// Thrown by a simulation after an interrupt: the search stops, what is simulated is kept.
struct SearchInterrupted {};

// An adaptive search's simulations when other processes help (a Distributor): each call of
// simulate() becomes a cell in this queue, taken by this process's simulating threads or by the
// Distributor for another process, and the calling thread waits for its region. A cell's record
// is the same wherever it is simulated (simulate_task), so the search decides as it would alone.
class AskedCells final : public TaskQueue {
 public:
  AskedCells(const Campaign& campaign, std::uint32_t grid, Committer& committer)
      : campaign_(campaign), grid_(grid), committer_(committer) {}

  /// The region of the cell's simulation, once some process delivered it. Throws
  /// SearchInterrupted after an interrupt. Thread-safe.
  sim::Region simulate(std::uint32_t cell) {
    std::unique_lock lock(mutex_);
    WorkItem item{grid_, cell};
    asked_.push_back({grid_, cell, expected_cost(campaign_, item)});
    answers_.emplace(cell, sim::Region::kInfeasible);
    changed_.notify_all();
    for (;;) {
      if (const auto it = answers_.find(cell); it->second != sim::Region::kInfeasible) {
        const sim::Region region = it->second;
        answers_.erase(it);
        return region;
      }
      if (core::interrupt_signal() != 0 || abandoned_) throw SearchInterrupted{};
      changed_.wait_for(lock, std::chrono::milliseconds(50));
    }
  }

  std::optional<CellTask> next() override {
    std::lock_guard lock(mutex_);
    return take_locked();
  }
  [[nodiscard]] std::size_t remaining() const override {
    std::lock_guard lock(mutex_);
    return asked_.size();
  }
  void deliver(CellRecord record, int cost, double seconds) override {
    const auto cell = static_cast<std::uint32_t>(record.index);
    const sim::Region region = adaptive::region_named(record.region);
    committer_.add(std::move(record), cost, seconds);
    std::lock_guard lock(mutex_);
    if (const auto it = answers_.find(cell); it != answers_.end()) it->second = region;
    changed_.notify_all();
  }
  [[nodiscard]] bool open() const override {
    std::lock_guard lock(mutex_);
    return !closed_;
  }
  /// The search has ended: no more cells will be asked for.
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    changed_.notify_all();
  }
  /// The distributor failed: the search stops as at an interrupt, the simulating threads end.
  void abandon() {
    std::lock_guard lock(mutex_);
    closed_ = abandoned_ = true;
    asked_.clear();
    changed_.notify_all();
  }

  /// This process's `threads` simulate asked cells until the queue closes; returns the
  /// thread-seconds they spent.
  double simulate_here(int threads) {
    double seconds = 0.0;
    tbb::task_arena arena(threads);  // their own: the search's threads only wait
    arena.execute([&] {
      seconds = simulate_in_loops(
          campaign_, threads, [&] { return wait_for_task(); },
          [&](CellRecord record, int cost, double spent) { deliver(std::move(record), cost, spent); });
    });
    return seconds;
  }

 private:
  std::optional<CellTask> take_locked() {
    if (asked_.empty() || core::interrupt_signal() != 0) return std::nullopt;
    const CellTask task = asked_.front();
    asked_.pop_front();
    return task;
  }

  std::optional<CellTask> wait_for_task() {
    std::unique_lock lock(mutex_);
    for (;;) {
      if (auto task = take_locked()) return task;
      if (closed_ || core::interrupt_signal() != 0) return std::nullopt;
      changed_.wait_for(lock, std::chrono::milliseconds(50));
    }
  }

  const Campaign& campaign_;
  std::uint32_t grid_;
  Committer& committer_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<CellTask> asked_;                         ///< asked for, not taken yet
  std::unordered_map<std::uint32_t, sim::Region> answers_;  ///< per cell asked: kInfeasible until delivered
  bool closed_ = false;
  bool abandoned_ = false;
};

// The adaptive search's view of one grid: feasibility and the stop boundary from the scene;
// simulations run as a full sweep runs them (the cell's own seed), stored through the committer,
// or read from the store when an earlier run simulated them.
class GridOracle final : public adaptive::Oracle {
 public:
  GridOracle(const Campaign& campaign, std::size_t g, Committer& committer,
             const std::vector<std::pair<std::int64_t, std::string>>& stored)
      : campaign_(campaign),
        g_(static_cast<std::uint32_t>(g)),
        grid_(campaign.grids[g]),
        committer_(committer),
        stored_(grid_.cells.size(), sim::Region::kInfeasible),
        present_(grid_.cells.size(), 0) {
    for (const auto& [index, region] : stored)
      if (index >= 0 && static_cast<std::size_t>(index) < stored_.size()) {
        stored_[static_cast<std::size_t>(index)] = adaptive::region_named(region);
        present_[static_cast<std::size_t>(index)] = 1;
      }
    // The analytic stop boundary is the shipped emergency stop's; with another baseline only a
    // simulation tells, and without one no cell is G.
    const sim::StrategyTable strategies = sim::registered_strategies();
    const sim::StrategyInfo* baseline = strategies.first_of(sim::StrategyRole::kBaseline);
    const bool listed = baseline != nullptr && std::find(campaign.strategies.begin(), campaign.strategies.end(),
                                                         baseline->name) != campaign.strategies.end();
    stop_rule_ = !listed ? Rule::kNoBaseline : baseline->name == "emergency_stop" ? Rule::kAnalytic : Rule::kSimulate;
  }

  [[nodiscard]] bool feasible(std::size_t cell) const override {
    return sim::Scene(campaign_.scene, grid_.cells[cell]).feasible();
  }

  [[nodiscard]] adaptive::StopCall stop(std::size_t cell) const override {
    switch (stop_rule_) {
      case Rule::kNoBaseline: return adaptive::StopCall::kCannotStop;
      case Rule::kSimulate: return adaptive::StopCall::kUnknown;
      case Rule::kAnalytic: break;
    }
    return sim::stop_call(campaign_.scene, grid_.cells[cell]);
  }

  [[nodiscard]] bool passes_early(std::size_t cell) const override {
    return sim::may_pass_early(campaign_.scene, grid_.cells[cell]);
  }
  [[nodiscard]] bool nothing_to_mitigate(std::size_t cell) const override {
    return sim::nothing_to_mitigate(campaign_.scene, grid_.cells[cell]);
  }
  [[nodiscard]] sim::Region simulate(std::size_t cell) override {
    if (stored_[cell] != sim::Region::kInfeasible) return stored_[cell];
    if (core::interrupt_signal() != 0) throw SearchInterrupted{};
    if (asked_ != nullptr) return asked_->simulate(static_cast<std::uint32_t>(cell));
    const auto start = Clock::now();
    CellRecord record = simulate_task(campaign_, CellTask{g_, static_cast<std::uint32_t>(cell), 1});
    const sim::Region region = adaptive::region_named(record.region);
    committer_.add(std::move(record), 1, std::chrono::duration<double>(Clock::now() - start).count());
    return region;
  }

  [[nodiscard]] std::uint64_t seed(std::size_t cell) const { return cell_seed(campaign_, grid_, cell); }
  /// The store held the cell before this run (simulated, or infeasible).
  [[nodiscard]] bool stored(std::size_t cell) const { return present_[cell] != 0; }
  /// Simulations go to `asked` (borrowed) instead of this thread.
  void ask(AskedCells* asked) noexcept { asked_ = asked; }

 private:
  enum class Rule { kAnalytic, kSimulate, kNoBaseline };
  const Campaign& campaign_;
  std::uint32_t g_;  ///< the grid's position in the campaign
  const GridSpec& grid_;
  Committer& committer_;
  AskedCells* asked_ = nullptr;
  std::vector<sim::Region> stored_;  ///< kInfeasible: not simulated yet
  std::vector<char> present_;        ///< in the store before this run
  Rule stop_rule_ = Rule::kAnalytic;
};

// An inferred cell as the store keeps it: its region and grounds, no outcomes.
CellRecord inferred_record(const GridSpec& grid, std::size_t index, std::uint64_t seed, const adaptive::Cell& cell) {
  CellRecord r;
  const sim::CellInput& in = grid.cells[index];
  r.grid = grid.name;
  r.index = static_cast<std::int64_t>(index);
  r.speed_kph = in.speed_kph;
  r.ttc_s = in.ttc_s;
  r.mu = in.mu;
  r.passage_m = in.passage_m;
  r.truck_speed_kph = in.truck_speed_kph;
  r.seed = seed;
  r.feasible = true;
  r.region = std::string(sim::region_name(cell.region));
  r.evidence = "inferred";
  r.method = "inferred";
  r.inferred_from.assign(cell.from.begin(), cell.from.end());
  return r;
}

AdaptiveSummary summarize(const GridSpec& grid, const adaptive::Result& result, double confidence) {
  AdaptiveSummary s;
  s.grid = grid.name;
  s.feasible = result.feasible;
  s.simulated = result.simulated;
  for (const adaptive::Cell& c : result.cells) {
    s.inferred += c.method == adaptive::Method::kStop || c.method == adaptive::Method::kLine ||
                  c.method == adaptive::Method::kBox;
    s.inferred_stop += c.method == adaptive::Method::kStop;
  }
  s.rounds = result.rounds;
  s.lines = result.lines;
  s.lines_resolved = result.lines_resolved;
  s.lines_inferred = result.lines_inferred;
  s.lines_fully_resolved = result.lines_fully_resolved;
  s.violations = result.violations.size();
  s.verify_population = result.verify_population;
  s.verify_sampled = result.verify_sampled;
  s.verify_disagreements = result.verify_disagreements.size();
  s.disagreement_low = result.disagreement.low;
  s.disagreement_high = result.disagreement.high;
  nlohmann::ordered_json violations = nlohmann::ordered_json::array();
  for (const auto& v : result.violations)
    violations.push_back({{"kind", v.what}, {"lower_cell", v.low_cell}, {"higher_cell", v.high_cell}});
  nlohmann::ordered_json simulated_for = nlohmann::ordered_json::object();
  for (std::size_t p = 0; p < adaptive::kPurposes; ++p)
    simulated_for[std::string(adaptive::purpose_name(static_cast<adaptive::Purpose>(p)))] = result.simulated_for[p];
  const nlohmann::ordered_json j{
      {"grid", s.grid},
      {"feasible_cells", s.feasible},
      {"simulated_cells", s.simulated},
      {"simulated_fraction", s.feasible > 0 ? static_cast<double>(s.simulated) / static_cast<double>(s.feasible) : 0.0},
      {"simulated_for", simulated_for},
      {"inferred_cells", s.inferred},
      {"inferred_by_stop_boundary", s.inferred_stop},
      {"rounds", s.rounds},
      {"lines", {{"total", s.lines}, {"resolved", s.lines_resolved}, {"inferred", s.lines_inferred},
                 {"fully_resolved", s.lines_fully_resolved}}},
      {"violations", violations},
      {"verification", {{"population", s.verify_population},
                        {"sampled", s.verify_sampled},
                        {"disagreements", s.verify_disagreements},
                        {"disagreeing_cells", result.verify_disagreements},
                        {"confidence", confidence},
                        {"rate_low", s.disagreement_low},
                        {"rate_high", s.disagreement_high}}}};
  s.json = j.dump();
  return s;
}

// One grid by the adaptive search: the cells it asks for are simulated (or read back), the
// others stored as inferred in batches, then the summary.
AdaptiveSummary sweep_adaptive(const Campaign& campaign, std::size_t g, ResultStore& store, Committer& committer,
                               const SweepOptions& options, double& simulation_seconds) {
  const GridSpec& grid = campaign.grids[g];
  store.delete_inferred(grid.name);
  GridOracle oracle(campaign, g, committer, store.simulated_regions(grid.name));
  adaptive::Lattice lattice{grid.levels};
  adaptive::Options search_options;
  search_options.initial_levels = options.initial_levels;
  search_options.stride = options.stride;
  search_options.brackets = options.brackets;
  search_options.spread = options.spread;
  search_options.verify_sample = options.verify_sample;
  search_options.seed = core::derive_seed(campaign.seed, "adaptive verification " + grid.name);
  adaptive::Result result;
  bool interrupted = false;
  if (options.distributor == nullptr) {
    try {
      result = adaptive::search(lattice, oracle, search_options);
    } catch (const SearchInterrupted&) {
      interrupted = true;
    }
  } else {
    // The search runs with a thread per simulation it may keep in flight (each waits for its
    // cell), this process's simulating threads and the distributor beside it.
    AskedCells asked(campaign, static_cast<std::uint32_t>(g), committer);
    oracle.ask(&asked);
    const int here = local_threads(options.threads);
    beside_distributor(
        *options.distributor, campaign, asked,
        [&] {
          std::jthread simulating([&] { simulation_seconds += asked.simulate_here(here); });
          try {
            tbb::task_arena arena(here + options.distributor->threads());
            arena.execute([&] { result = adaptive::search(lattice, oracle, search_options); });
          } catch (const SearchInterrupted&) {
            interrupted = true;
          } catch (...) {
            asked.abandon();  // the simulating thread ends before the error goes on
            throw;
          }
          asked.close();
        },
        [&] { asked.abandon(); });  // the search and the simulating threads stop
  }
  if (interrupted) return {};  // the caller flushes the committer and reports the interrupt
  std::vector<CellRecord> batch;
  const auto flush = [&] {
    store.insert(batch);
    batch.clear();
  };
  for (std::size_t i = 0; i < result.cells.size(); ++i) {
    const adaptive::Cell& cell = result.cells[i];
    if (cell.method == adaptive::Method::kSimulated || oracle.stored(i)) continue;
    if (cell.method == adaptive::Method::kNone) {  // infeasible: a full sweep's row, no simulation
      sim::CellResult infeasible;
      infeasible.input = grid.cells[i];
      batch.push_back(to_record(grid.name, static_cast<std::int64_t>(i), oracle.seed(i), infeasible));
    } else {
      batch.push_back(inferred_record(grid, i, oracle.seed(i), cell));
    }
    if (batch.size() >= 4096) flush();
  }
  flush();
  AdaptiveSummary summary = summarize(grid, result, search_options.confidence);
  store.set_adaptive_summary(grid.name, summary.json);
  return summary;
}

}  // namespace

CellRecord simulate_task(const Campaign& campaign, const CellTask& task) {
  const GridSpec& grid = campaign.grids[task.grid];
  const sim::CellInput& cell = grid.cells[task.index];
  sim::CellOptions options;
  options.strategies = campaign.strategies;
  options.seed = cell_seed(campaign, grid, task.index);
  options.keep_trees = grid.keep_trees;
  const sim::CellResult result = sim::simulate_cell(campaign.scene, cell, options);
  return to_record(grid.name, static_cast<std::int64_t>(task.index), options.seed, result, grid.keep_trees);
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
    adaptive[g] = (options.adaptive || campaign.grids[g].adaptive) && !campaign.grids[g].levels[0].empty();
  const bool any_adaptive = std::find(adaptive.begin(), adaptive.end(), 1) != adaptive.end();
  if (any_adaptive && options.shard_count > 1)
    throw UsageError("--shard cannot split an adaptive sweep: the search picks each cell from the ones simulated "
                     "before; run it on one machine (every core: --threads 0)");
  const auto start = Clock::now();
  CampaignMeta meta = make_meta(campaign);
  meta.shard_index = options.shard_index;
  meta.shard_count = options.shard_count;
  const auto store_path = options.output_dir / "results.sqlite";

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
    std::size_t position = 0;  // global position over all grids, for sharding
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
    Committer committer(store, work.size() + adaptive_cells, options.progress && ::isatty(2) == 1, options.unit, EtaModel(counts),
                        log.get());
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
      AdaptiveSummary grid_summary =
          sweep_adaptive(campaign, g, store, committer, options, summary.simulation_seconds);
      committer.finish();
      if (core::interrupt_signal() == 0) summary.adaptive.push_back(std::move(grid_summary));
    }
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
