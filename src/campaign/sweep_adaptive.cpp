// A grid swept by the adaptive boundary search (docs/adaptive.md): the search's oracle over the
// grid's cells (feasibility and the stop boundary from the scene, simulations through the sweep's
// committer or read back from the store), its simulations handed to other processes when a
// Distributor helps, and the inferred cells and the summary stored once it ends.

#include <fmt/format.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "emrm/campaign/adaptive.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/strategy.hpp"
#include "sweep_parts.hpp"

namespace emrm::campaign {
namespace {

using Clock = std::chrono::steady_clock;
using detail::Committer;
using detail::expected_cost;
using detail::simulate_in_loops;
using detail::WorkItem;

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
    const sim::Region region = record.region;
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
  std::deque<CellTask> asked_;                              ///< asked for, not taken yet
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
             const std::vector<std::pair<std::int64_t, sim::Region>>& stored)
      : campaign_(campaign),
        g_(static_cast<std::uint32_t>(g)),
        grid_(campaign.grids[g]),
        committer_(committer),
        stored_(grid_.cells.size(), sim::Region::kInfeasible),
        present_(grid_.cells.size(), 0) {
    for (const auto& [index, region] : stored)
      if (index >= 0 && static_cast<std::size_t>(index) < stored_.size()) {
        stored_[static_cast<std::size_t>(index)] = region;
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
      case Rule::kNoBaseline:
        return adaptive::StopCall::kCannotStop;
      case Rule::kSimulate:
        return adaptive::StopCall::kUnknown;
      case Rule::kAnalytic:
        break;
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
    const sim::Region region = record.region;
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
  r.factors = in;
  r.seed = seed;
  r.feasible = true;
  r.region = cell.region;
  r.evidence = CellEvidence::kInferred;
  r.method = CellMethod::kInferred;
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
      {"lines",
       {{"total", s.lines},
        {"resolved", s.lines_resolved},
        {"inferred", s.lines_inferred},
        {"fully_resolved", s.lines_fully_resolved}}},
      {"violations", violations},
      {"verification",
       {{"population", s.verify_population},
        {"sampled", s.verify_sampled},
        {"disagreements", s.verify_disagreements},
        {"disagreeing_cells", result.verify_disagreements},
        {"confidence", confidence},
        {"rate_low", s.disagreement_low},
        {"rate_high", s.disagreement_high}}}};
  s.json = j.dump();
  return s;
}

// The grid as the search's lattice: every factor when the search takes that many; else the factors
// the grid varies, and the TTC and the friction always (the search's monotone axes). A factor held at
// one level adds nothing to a cell's index in the grid's expansion order, so the lattice's indices
// are the grid's either way. Throws UsageError for a grid that varies more factors than the search
// takes.
adaptive::Lattice lattice_of(const GridSpec& grid, std::size_t ttc, std::size_t friction,
                             const sim::FactorTable& factors) {
  if (grid.levels.size() <= adaptive::Lattice::kMaxAxes) return {grid.levels, ttc, friction};
  adaptive::Lattice lattice;
  std::vector<std::string> varied;
  for (std::size_t i = 0; i < grid.levels.size(); ++i) {
    if (i == ttc) lattice.ttc_axis = lattice.levels.size();
    if (i == friction) lattice.friction_axis = lattice.levels.size();
    if (grid.levels[i].size() > 1 || i == ttc || i == friction) {
      lattice.levels.push_back(grid.levels[i]);
      varied.push_back(factors[i].key);
    }
  }
  if (lattice.levels.size() > adaptive::Lattice::kMaxAxes)
    throw UsageError(fmt::format(
        "grid '{}': the adaptive search takes at most {} factors with more than one level, the TTC and the "
        "friction among them; this grid varies {} ({}): hold some at one level, or sweep it without --adaptive",
        grid.name, adaptive::Lattice::kMaxAxes, lattice.levels.size(), core::join(varied, ", ")));
  return lattice;
}

}  // namespace

namespace detail {

AdaptiveSummary sweep_adaptive(const Campaign& campaign, std::size_t g, ResultStore& store, Committer& committer,
                               const SweepOptions& options, double& simulation_seconds) {
  const GridSpec& grid = campaign.grids[g];
  store.delete_inferred(grid.name);
  GridOracle oracle(campaign, g, committer, store.simulated_regions(grid.name));
  const sim::FactorTable factors = sim::scenario_factors(campaign.scene);
  const auto axis = [&](sim::FactorRole role) {
    const auto i = factors.find(role);
    if (!i)
      throw UsageError(
          fmt::format("grid '{}': the adaptive search needs the scenario's TTC and friction factors", grid.name));
    return *i;
  };
  const adaptive::Lattice lattice =
      lattice_of(grid, axis(sim::FactorRole::kTtc), axis(sim::FactorRole::kFriction), factors);
  adaptive::Options search_options = options.search;
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
      batch.push_back(to_record(campaign.scene, grid.name, static_cast<std::int64_t>(i), oracle.seed(i), infeasible));
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

}  // namespace detail

}  // namespace emrm::campaign
