// EMRM as a strategy: the loss-evaluation FSM reads what physics says of the cell (severity of
// the unmitigated impact, exposure, controllability, maneuverability) and ends in the state of the
// strategy to execute; EMRM's outcome is that strategy's (docs/simulate.md, "emrm").

#include <algorithm>
#include <string>
#include <vector>

#include "emrm/fsm/operations.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::sim {
namespace {

// The events of the loss-evaluation FSM (examples/tjunction/loss_evaluation_fsm.yaml).
std::string severity_event(int unmitigated_level) {
  if (unmitigated_level >= 7) return "Se3";
  if (unmitigated_level >= 6) return "Se2";
  return "Se1";
}

std::string maneuverability_event(double mu) {
  if (mu >= 0.7) return "Mi3";
  if (mu >= 0.35) return "Mi2";
  return "Mi1";
}

// C0…C2: the least demanding controllability class among the strategies that avoided; C3 when none did.
std::string controllability_event(const StrategyTable& strategies,
                                  const std::map<std::string, StrategyOutcome>& outcomes) {
  int least = 3;
  for (const auto& [name, o] : outcomes) {
    const StrategyInfo* info = strategies.info(name);
    if (o.avoided && info != nullptr && info->controllability) least = std::min(least, *info->controllability);
  }
  return "C" + std::to_string(least);
}

class EmrmChooser final : public Strategy {
 public:
  StrategyOutcome run(const StrategyInfo& self, const StrategyContext& c) const override {
    if (!c.at_risk) {
      // Nothing to evade: the EMRM FSM returns to normal driving and the car carries on.
      StrategyOutcome o = outcome_of(self.name, c.no_action, c.unmitigated, c.scene);
      o.chosen_strategy = "none";
      return o;
    }
    const std::vector<std::string> word{severity_event(c.unmitigated.loss_level), "E0",
                                        controllability_event(c.strategies, c.earlier),
                                        maneuverability_event(c.scene.friction())};
    const auto trace = fsm::trace_word(c.loss_evaluation_fsm, word);
    const StrategyInfo* baseline = c.strategies.first_of(StrategyRole::kBaseline);
    const std::string fallback = baseline != nullptr ? baseline->name : std::string();
    // A complete run ends in the state of the strategy to execute.
    const std::string chosen = trace.size() == 2 * word.size() + 1 ? trace.back() : fallback;
    const StrategyInfo* info = c.strategies.info(chosen);
    auto it = info != nullptr && info->emrm_may_choose ? c.earlier.find(chosen) : c.earlier.end();
    if (it == c.earlier.end()) it = c.earlier.find(fallback);
    // Never worse than an option it had: the FSM decides from classes (severity, controllability,
    // maneuverability), which can rank a strategy first whose simulated outcome is worse than
    // another's; the least-loss rule then takes the better one, and the record shows both
    // (chosen_strategy: the FSM's choice; adopted_from: what was executed).
    std::string executed = it != c.earlier.end() ? it->first : std::string();
    for (const auto& entry : c.strategies.entries()) {
      if (!entry.info.emrm_may_choose) continue;
      const auto other = c.earlier.find(entry.info.name);
      if (other == c.earlier.end()) continue;
      if (it == c.earlier.end() || better_outcome(other->second, it->second)) {
        it = other;
        executed = other->first;
      }
    }
    StrategyOutcome o = it != c.earlier.end() ? it->second : StrategyOutcome{};
    o.strategy = self.name;
    o.chosen_strategy = chosen;
    o.adopted_from = executed;
    o.loss_evaluation_trace = trace;
    return o;
  }
};

}  // namespace

std::shared_ptr<const Strategy> emrm_chooser_strategy() {
  static const auto s = std::make_shared<const EmrmChooser>();
  return s;
}

}  // namespace emrm::sim
