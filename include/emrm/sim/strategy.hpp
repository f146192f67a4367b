#pragma once

// Strategies (DESIGN.md §7): constraint sets on the controls plus an objective, registered by
// name. A strategy whose constraint set contains another's may adopt that one's avoidance (a
// full ABS stop is a legal dodge; any dodge is a legal drift); simulate_cell() therefore always
// evaluates them in the fixed order of strategy_names(), so a strategy's result never depends on
// which others were asked for.

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "emrm/sim/planner.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::sim {

/// What a strategy sees: the cell, the vehicle model, its seed, and the outcomes of the
/// strategies evaluated before it.
struct StrategyContext {
  const Scene& scene;
  const VehicleModel& model;
  std::uint64_t seed = 0;
  bool keep_tree = false;
  const ImpactAssessment& unmitigated;
  const std::map<std::string, StrategyOutcome>& earlier;
};

/// A named way of driving out of the hazard.
class Strategy {
 public:
  virtual ~Strategy() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// The outcome of this strategy in the context's cell (loss fields filled, FSM traces not).
  [[nodiscard]] virtual StrategyOutcome run(const StrategyContext& context) const = 0;
};

/// The registered strategy of that name, or nullptr. The emrm strategy is not in this registry:
/// it is the loss-evaluation FSM choosing among these (see simulate_cell).
[[nodiscard]] const Strategy* find_strategy(std::string_view name);

/// The outcome of one rollout, with its loss fields against the unmitigated reference and its
/// least time to collision along the path (min_ttc_along; 0 on contact).
[[nodiscard]] StrategyOutcome outcome_of(std::string_view strategy, const RolloutResult& rollout,
                                         const ImpactAssessment& unmitigated, const Scene& scene);

}  // namespace emrm::sim
