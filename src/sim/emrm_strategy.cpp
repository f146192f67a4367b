// The two choosers (docs/simulate.md, "emrm").
//
// `emrm` is a controller. It decides from what the car has before it acts: the scene it perceives,
// its own vehicle model and the on-board planning budget (scene.controller), never from the cell's
// simulated outcomes. The loss-evaluation FSM reads the severity of the predicted unmitigated
// impact, the controllability its own predictions show (the emergency stop rolled out, then the
// evasive strategies planned on board, lazily) and the maneuverability of the perceived friction,
// and ends in the strategy to execute; the controller commits to that strategy's on-board maneuver
// and is judged on the true outcome of replaying it.
//
// `best_strategy` is the oracle: the best simulated outcome of the strategies EMRM may choose and
// of the controller, in hindsight (an avoidance first, then the least loss).

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
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

// The seed of an on-board search: the perceived cell's factors and the strategy, not the
// campaign's seed, so that the controller's decision does not depend on it.
std::uint64_t onboard_seed(const Scene& seen, std::string_view strategy) {
  return derive_seed(cell_key(seen.cell(), 0x0b0a5d0b0a5d0b0aULL), strategy);
}

// Nothing to evade: the EMRM FSM returns to normal driving and the car carries on.
StrategyOutcome carry_on(const StrategyInfo& self, const RolloutResult& no_action, const StrategyContext& c) {
  StrategyOutcome o = outcome_of(self.name, no_action, c.unmitigated, c.scene);
  o.chosen_strategy = "none";
  return o;
}

// No strategy to execute (a table without one EMRM may choose): an empty outcome.
StrategyOutcome nothing_to_execute(const StrategyInfo& self) {
  StrategyOutcome o;
  o.strategy = self.name;
  return o;
}

// The controller's own predictions: each strategy it may choose, run on the perceived scene with
// the on-board budget, once, when it is first asked for. The outcomes a strategy may adopt are these
// predictions (a dodge may take the predicted stop's avoidance), never the cell's simulations.
class OnboardPlans {
 public:
  OnboardPlans(const StrategyContext& truth, const Scene& seen, const RolloutResult& no_action,
               const ImpactAssessment& unmitigated)
      : truth_(truth), seen_(seen), no_action_(no_action), unmitigated_(unmitigated) {}

  const StrategyOutcome& of(const RegisteredStrategy& entry) {
    const std::string& name = entry.info.name;
    if (const auto it = plans_.find(name); it != plans_.end()) return it->second;
    // A fixed maneuver (the stop) needs no search; a planned one searches with the on-board budget.
    const Scene& scene = entry.info.planner.empty() ? seen_ : planning_scene();
    const StrategyContext context{
        scene, truth_.model, truth_.strategies, onboard_seed(seen_, name),  false, unmitigated_, no_action_,
        true,  plans_,       truth_.emrm_fsm,   truth_.loss_evaluation_fsm, false};
    StrategyOutcome o = entry.strategy->run(entry.info, context);
    stats_.add(o.planner);
    return plans_.insert_or_assign(name, std::move(o)).first->second;
  }

  [[nodiscard]] const PlannerStats& stats() const noexcept { return stats_; }

 private:
  // The perceived scene under the on-board budget (built when the first search needs it).
  const Scene& planning_scene() {
    if (!planning_) {
      budget_ = seen_.config();
      budget_.planner.max_nodes = budget_.controller.max_nodes;
      planning_.emplace(budget_, seen_.cell());
    }
    return *planning_;
  }

  const StrategyContext& truth_;
  const Scene& seen_;
  const RolloutResult& no_action_;
  const ImpactAssessment& unmitigated_;
  std::map<std::string, StrategyOutcome> plans_;
  PlannerStats stats_;
  SceneConfig budget_;
  std::optional<Scene> planning_;
};

// C0…C2: the least demanding class among the strategies whose on-board plan avoids in prediction,
// tried from the least demanding up, so that nothing is searched once the stop is predicted to
// avoid; C3 when none does.
int predicted_controllability(const StrategyTable& strategies, OnboardPlans& plans) {
  std::vector<const RegisteredStrategy*> candidates;
  for (const auto& entry : strategies.entries())
    if (entry.info.emrm_may_choose && entry.info.controllability) candidates.push_back(&entry);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto* a, const auto* b) { return *a->info.controllability < *b->info.controllability; });
  for (const RegisteredStrategy* entry : candidates)
    if (plans.of(*entry).avoided) return *entry->info.controllability;
  return 3;
}

class EmrmController final : public Strategy {
 public:
  StrategyOutcome run(const StrategyInfo& self, const StrategyContext& c) const override {
    const Scene& seen = perceived_scene(c.scene);
    // Its own prediction of doing nothing, with its own model (the true one when it sees the truth).
    std::optional<RolloutResult> predicted;
    const RolloutResult& no_action =
        &seen == &c.scene ? c.no_action : predicted.emplace(no_action_rollout(seen, c.model));
    if (no_action.termination != Termination::kContact) return carry_on(self, c.no_action, c);
    const ImpactAssessment& unmitigated = no_action.impact;

    OnboardPlans plans(c, seen, no_action, unmitigated);
    const int controllability = predicted_controllability(c.strategies, plans);
    const std::vector<std::string> word{severity_event(unmitigated.loss_level), "E0",
                                        "C" + std::to_string(controllability), maneuverability_event(seen.friction())};
    const auto trace = fsm::trace_word(c.loss_evaluation_fsm, word);
    // A complete run ends in the state of the strategy to execute; else the baseline.
    const StrategyInfo* baseline = c.strategies.first_of(StrategyRole::kBaseline);
    const RegisteredStrategy* chosen = trace.size() == 2 * word.size() + 1 ? c.strategies.find(trace.back()) : nullptr;
    if (chosen == nullptr || !chosen->info.emrm_may_choose)
      chosen = baseline != nullptr ? c.strategies.find(baseline->name) : nullptr;
    if (chosen == nullptr) return nothing_to_execute(self);

    // Commit to the chosen strategy's on-board maneuver (planned now if it was not yet), and be
    // judged on what it does in the true scene.
    const StrategyOutcome& plan = plans.of(*chosen);
    StrategyOutcome o =
        outcome_of(self.name, replay(c.scene, c.model, chosen->info.limits, plan.maneuver), c.unmitigated, c.scene);
    o.chosen_strategy = chosen->info.name;
    o.loss_evaluation_trace = trace;
    o.planner = plans.stats();
    return o;
  }
};

class Oracle final : public Strategy {
 public:
  StrategyOutcome run(const StrategyInfo& self, const StrategyContext& c) const override {
    if (!c.at_risk) return carry_on(self, c.no_action, c);
    // The first best in evaluation order: an avoidance, else the least loss. Its options are the
    // strategies EMRM may choose and the controller's executed maneuver (a maneuver of the strategy
    // it chose, found by its own search), so it is never worse than either.
    const StrategyOutcome* best = nullptr;
    std::string best_name;
    for (const auto& entry : c.strategies.entries()) {
      const bool controller = entry.info.role == StrategyRole::kChooser && !entry.info.hindsight;
      if (!entry.info.emrm_may_choose && !controller) continue;
      const auto it = c.earlier.find(entry.info.name);
      if (it == c.earlier.end()) continue;
      if (best == nullptr || better_outcome(it->second, *best)) {
        best = &it->second;
        best_name = entry.info.name;
      }
    }
    if (best == nullptr) return nothing_to_execute(self);
    StrategyOutcome o = adopted(self.name, best_name, *best);
    o.chosen_strategy = best_name;
    return o;
  }
};

}  // namespace

const Scene& perceived_scene(const Scene& truth) noexcept { return truth; }

std::shared_ptr<const Strategy> emrm_chooser_strategy() {
  static const auto s = std::make_shared<const EmrmController>();
  return s;
}

std::shared_ptr<const Strategy> oracle_chooser_strategy() {
  static const auto s = std::make_shared<const Oracle>();
  return s;
}

}  // namespace emrm::sim
