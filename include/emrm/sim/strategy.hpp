#pragma once

// Strategies: constraint sets on the controls plus an objective, registered by name with
// everything the rest of the program needs to know of them (label, colour, evaluation order,
// limits, planner, what EMRM may choose). Every list of strategies — the simulator's evaluation
// loop, the region rule, the tables, the figures, the CLI's choices — is derived from the
// registry, so a new strategy is one registration and no edit elsewhere.
//
// A strategy whose constraint set contains another's may adopt that one's avoidance (a full ABS
// stop is a legal dodge; any dodge is a legal drift); simulate_cell() therefore always evaluates
// every registered strategy in evaluation order, so a strategy's result never depends on which
// others were asked for.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/fsm/generator.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::sim {

/// What a strategy is for the region rule and for EMRM.
enum class StrategyRole {
  kBaseline,  ///< the reference maneuver: its avoidance makes a cell G (the emergency stop)
  kEvasive,   ///< an alternative: its avoidance (when the baseline's fails) makes a cell Y
  kChooser,   ///< picks among the others (EMRM, the oracle); does not count for the region
};

/// Everything the program knows of a strategy besides how it drives.
struct StrategyInfo {
  std::string name;    ///< identifier in files and on the command line
  std::string label;   ///< in figure keys and prose ("emergency stop")
  std::string title;   ///< as a table heading ("Emerg. Stop")
  std::string colour;  ///< "#rrggbb", the same in every figure
  int order = 0;       ///< evaluation order (ascending); also the order of every listing
  StrategyRole role = StrategyRole::kEvasive;
  ControlLimits limits;  ///< what its planner may command
  std::string planner;   ///< the planner that searches its maneuver (planner.hpp); empty: none
  /// Earlier strategies whose avoidance it may adopt (and, with limits.accept_contact, whose
  /// least-loss collision), in order of preference.
  std::vector<std::string> may_adopt;
  bool emrm_may_choose = false;  ///< the loss-evaluation FSM may choose it
  /// The controllability class its avoidance shows (0 for C0 … 2 for C2; see docs/simulate.md);
  /// unset when its avoidance says nothing about controllability.
  std::optional<int> controllability;
  /// A chooser that picks in hindsight from the simulated outcomes (the oracle, `best_strategy`):
  /// never worse than a strategy EMRM may choose (`emrm verify`, check 4). A chooser without it
  /// (`emrm`) is a controller: it decides before it knows any outcome and may be worse.
  bool hindsight = false;
};

class StrategyTable;

/// What a strategy sees: the cell, the vehicle model, its seed, the outcomes of the strategies
/// evaluated before it, and (for a chooser) the FSMs and the no-action rollout. The EMRM controller
/// reads none of the outcomes: it runs the strategies itself, on the scene it perceives, with a
/// context of its own whose `earlier` holds its own predictions.
struct StrategyContext {
  const Scene& scene;
  const VehicleModel& model;
  const StrategyTable& strategies;
  std::uint64_t seed = 0;
  bool keep_tree = false;
  const ImpactAssessment& unmitigated;
  const RolloutResult& no_action;  ///< the car doing nothing (coasting) from t = 0
  bool at_risk = false;            ///< the no-action rollout hits the truck
  const std::map<std::string, StrategyOutcome>& earlier;
  const fsm::Generator& emrm_fsm;
  const fsm::Generator& loss_evaluation_fsm;
  /// A certificate proves that nothing avoids the truck here (certificate.hpp): searches for an
  /// avoidance are skipped, and a least-loss search runs only where the reference is above L4.
  bool unavoidable = false;
};

/// How a strategy drives. Implementations are stateless and thread-safe.
class Strategy {
 public:
  virtual ~Strategy() = default;
  /// The outcome of the strategy `self` in the context's cell (loss fields filled; the EMRM FSM
  /// trace is filled by simulate_cell).
  [[nodiscard]] virtual StrategyOutcome run(const StrategyInfo& self, const StrategyContext& context) const = 0;
};

/// A registered strategy: its record and its implementation.
struct RegisteredStrategy {
  StrategyInfo info;
  std::shared_ptr<const Strategy> strategy;
};

/// A snapshot of the registry, in evaluation order. Immutable: registrations made later do not
/// change it.
class StrategyTable {
 public:
  explicit StrategyTable(std::shared_ptr<const std::vector<RegisteredStrategy>> entries);
  [[nodiscard]] const std::vector<RegisteredStrategy>& entries() const noexcept { return *entries_; }
  /// The strategy of that name, or nullptr.
  [[nodiscard]] const RegisteredStrategy* find(std::string_view name) const noexcept;
  /// The record of that name, or nullptr.
  [[nodiscard]] const StrategyInfo* info(std::string_view name) const noexcept;
  /// The names, in evaluation order.
  [[nodiscard]] std::vector<std::string> names() const;
  /// The first strategy of that role, or nullptr.
  [[nodiscard]] const StrategyInfo* first_of(StrategyRole role) const noexcept;

 private:
  std::shared_ptr<const std::vector<RegisteredStrategy>> entries_;
};

/// The registered strategies now.
[[nodiscard]] StrategyTable registered_strategies();

/// Adds a strategy for as long as the returned registration lives (a test's or a plugin's own
/// strategy). Throws UsageError if the name is taken, or if its planner or an adopted strategy is
/// unknown. Register before simulating: a simulation uses the table it started with.
class StrategyRegistration {
 public:
  StrategyRegistration(StrategyInfo info, std::shared_ptr<const Strategy> strategy);
  ~StrategyRegistration();
  StrategyRegistration(const StrategyRegistration&) = delete;
  StrategyRegistration& operator=(const StrategyRegistration&) = delete;

 private:
  std::string name_;
};

/// The built-in implementations, for registering variants of them.
/// The emergency stop: after the latency, straight ABS braking to a standstill.
[[nodiscard]] std::shared_ptr<const Strategy> emergency_stop_strategy();
/// A planned maneuver: adopt an earlier avoidance if allowed, else search with self.planner.
[[nodiscard]] std::shared_ptr<const Strategy> planned_strategy();
/// EMRM, a controller: the loss-evaluation FSM chooses among the strategies EMRM may choose from the
/// controller's own predictions (the perceived scene, its vehicle model, the on-board planning
/// budget `scene.controller`), and the controller commits to that strategy's on-board maneuver,
/// judged by replaying it in the true scene (docs/simulate.md, "emrm").
[[nodiscard]] std::shared_ptr<const Strategy> emrm_chooser_strategy();
/// The oracle: the best simulated outcome of the strategies EMRM may choose (better_outcome), in
/// hindsight; what no controller that commits before it knows the outcome can beat.
[[nodiscard]] std::shared_ptr<const Strategy> oracle_chooser_strategy();

/// A key from a cell's factors alone (not the campaign's seed), salted by its user (the strengthened
/// search's restarts, the controller's on-board searches), from which they derive their seeds.
[[nodiscard]] std::uint64_t cell_key(const CellInput& cell, std::uint64_t salt);

/// What the on-board system perceives of a cell: today the true scene itself. A perception model
/// (a misjudged distance, a late detection) would return a scene of its own; the controller plans
/// on it and is judged on the true one.
[[nodiscard]] const Scene& perceived_scene(const Scene& truth) noexcept;

/// The outcome of one rollout, with its loss fields against the unmitigated reference and its
/// least time to collision along the path (min_ttc_along; 0 on contact).
[[nodiscard]] StrategyOutcome outcome_of(std::string_view strategy, const RolloutResult& rollout,
                                         const ImpactAssessment& unmitigated, const Scene& scene);

/// Whether outcome `a` is better than `b`: an avoidance beats a failure; between failures the lower
/// loss level, then the lower risks and Δv (less_loss). The oracle is never worse than EMRM's options by
/// this order.
[[nodiscard]] bool better_outcome(const StrategyOutcome& a, const StrategyOutcome& b) noexcept;

/// Whether an avoidance found under `found_with` obeys `limits` too: no rear lock unless `limits`
/// allows it, and no rear sliding where `limits` forbids it unless `found_with` forbade it as well.
/// Contact acceptance does not matter to an avoidance.
[[nodiscard]] bool avoidance_admissible(const ControlLimits& found_with, const ControlLimits& limits) noexcept;

/// The outcome of `source` taken over by strategy `name` (adopted_from set, planner stats and tree
/// cleared).
[[nodiscard]] StrategyOutcome adopted(const std::string& name, const std::string& source_name,
                                      const StrategyOutcome& source);

}  // namespace emrm::sim
