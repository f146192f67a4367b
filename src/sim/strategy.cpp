#include "emrm/sim/strategy.hpp"

#include <algorithm>
#include <memory>
#include <vector>

namespace emrm::sim {

StrategyOutcome outcome_of(std::string_view strategy, const RolloutResult& rollout,
                           const ImpactAssessment& unmitigated, const Scene& scene) {
  StrategyOutcome o;
  o.strategy = strategy;
  o.avoided = rollout.avoided();
  o.contact = rollout.termination == Termination::kContact;
  o.road_departure = rollout.termination == Termination::kRoadDeparture;
  if (!o.avoided) o.impact = rollout.impact;
  o.delta_loss = unmitigated.loss_level - o.impact.loss_level;
  o.min_ttc_s = o.contact ? 0.0 : min_ttc_along(scene, rollout.path);
  o.path = rollout.path;
  return o;
}

namespace {

const std::vector<ControlSegment> kNoPlan;

class EmergencyStop final : public Strategy {
 public:
  std::string_view name() const override { return "emergency_stop"; }
  StrategyOutcome run(const StrategyContext& c) const override {
    const Roller roller(c.scene, c.model, ControlLimits{});
    const double latency = c.scene.config().simulation.latency_s;
    const std::vector<ControlSegment> wait =
        latency > 0.0 ? std::vector<ControlSegment>{hold(Control{}, latency)} : kNoPlan;
    const RolloutResult r = roller.roll(c.scene.ego_initial(), 0.0, wait, Tail::full_stop(), 1);
    StrategyOutcome o = outcome_of(name(), r, c.unmitigated, c.scene);
    o.planner.rollouts = 1;
    return o;
  }
};

// An RRT strategy: its control limits, and the earlier strategies whose avoidance it may adopt.
class RrtStrategy final : public Strategy {
 public:
  RrtStrategy(std::string name, ControlLimits limits, std::vector<std::string> may_adopt)
      : name_(std::move(name)), limits_(limits), may_adopt_(std::move(may_adopt)) {}

  std::string_view name() const override { return name_; }

  StrategyOutcome run(const StrategyContext& c) const override {
    for (const auto& other : may_adopt_) {
      auto it = c.earlier.find(other);
      if (it != c.earlier.end() && it->second.avoided) {
        StrategyOutcome o = it->second;
        o.strategy = name_;
        o.adopted_from = it->second.adopted_from.empty() ? other : it->second.adopted_from;
        o.planner = {};
        o.tree.clear();
        return o;
      }
    }
    const PlanResult plan = plan_rrt(c.scene, c.model, limits_, c.seed, c.keep_tree);
    StrategyOutcome o;
    if (plan.avoidance) {
      o = outcome_of(name_, *plan.avoidance, c.unmitigated, c.scene);
    } else if (plan.collision) {
      o = outcome_of(name_, *plan.collision, c.unmitigated, c.scene);
    } else {
      // Every branch broke the strategy's constraint: it cannot be executed here; the car falls
      // back to what an emergency stop would give.
      auto it = c.earlier.find("emergency_stop");
      if (it != c.earlier.end()) o = it->second;
      o.strategy = name_;
      o.adopted_from = "emergency_stop";
    }
    // With contact accepted, a collision found by an earlier strategy is also admissible.
    if (limits_.accept_contact && !o.avoided) {
      for (const auto& other : may_adopt_) {
        auto it = c.earlier.find(other);
        if (it != c.earlier.end() && less_loss(it->second.impact, o.impact)) {
          const auto planner = o.planner;
          o = it->second;
          o.strategy = name_;
          o.adopted_from = it->second.adopted_from.empty() ? other : it->second.adopted_from;
          o.planner = planner;
        }
      }
    }
    o.planner.nodes = plan.stats.nodes;
    o.planner.rollouts = plan.stats.rollouts;
    o.planner.time_ms = plan.stats.time_ms;
    o.planner.time_limited = plan.stats.time_limited;
    if (c.keep_tree) o.tree = plan.tree;
    return o;
  }

 private:
  std::string name_;
  ControlLimits limits_;
  std::vector<std::string> may_adopt_;
};

const std::vector<std::unique_ptr<Strategy>>& registry() {
  static const auto strategies = [] {
    std::vector<std::unique_ptr<Strategy>> all;
    all.push_back(std::make_unique<EmergencyStop>());
    all.push_back(std::make_unique<RrtStrategy>("dodge", ControlLimits{false, true, false},
                                                std::vector<std::string>{"emergency_stop"}));
    all.push_back(std::make_unique<RrtStrategy>("drift_to_avoid", ControlLimits{true, false, false},
                                                std::vector<std::string>{"emergency_stop", "dodge"}));
    all.push_back(std::make_unique<RrtStrategy>(
        "drift_to_accident", ControlLimits{true, false, true},
        std::vector<std::string>{"emergency_stop", "dodge", "drift_to_avoid"}));
    return all;
  }();
  return strategies;
}

}  // namespace

const Strategy* find_strategy(std::string_view name) {
  for (const auto& s : registry())
    if (s->name() == name) return s.get();
  return nullptr;
}

}  // namespace emrm::sim
