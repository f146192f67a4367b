#include "emrm/sim/strategy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "builtin_strategies.hpp"
#include "emrm/core/random.hpp"
#include "emrm/core/registry.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/termination.hpp"

namespace emrm::sim {

std::uint64_t cell_key(const CellInput& cell, std::uint64_t salt) {
  return core::derive_seed(salt, fmt::format("{:.17g}", fmt::join(cell, "|")));
}
namespace {

core::Registry<RegisteredStrategy>& strategy_registry() {
  static core::Registry<RegisteredStrategy> strategies(
      "strategy", builtin_strategies(), [](const RegisteredStrategy& s) -> std::string_view { return s.info.name; },
      [](const RegisteredStrategy& a, const RegisteredStrategy& b) { return a.info.order < b.info.order; });
  return strategies;
}

const std::vector<ControlSegment> kNoPlan;

class EmergencyStop final : public Strategy {
 public:
  StrategyOutcome run(const StrategyInfo& self, const StrategyContext& c) const override {
    const Roller roller(c.scene, c.model, self.limits);
    const double latency = c.scene.config().actuation.perception_latency_s;
    const std::vector<ControlSegment> wait =
        latency > 0.0 ? std::vector<ControlSegment>{hold(Control{}, latency)} : kNoPlan;
    const RolloutResult r = roller.roll(c.scene.ego_initial(), 0.0, wait, Tail::full_stop(), 1);
    StrategyOutcome o = outcome_of(self.name, r, c.unmitigated, c.scene);
    o.planner.rollouts = 1;
    return o;
  }
};

// A planned strategy: adopts an earlier avoidance it may take, else searches with its planner.
class PlannedStrategy final : public Strategy {
  // The baseline's outcome under this strategy's name: what the car does when the strategy has
  // nothing to execute.
  static StrategyOutcome fallback_to_baseline(const StrategyInfo& self, const StrategyContext& c) {
    StrategyOutcome o;
    if (const StrategyInfo* baseline = c.strategies.first_of(StrategyRole::kBaseline)) {
      if (auto it = c.earlier.find(baseline->name); it != c.earlier.end()) o = it->second;
      o.adopted_from = baseline->name;
    }
    o.strategy = self.name;
    return o;
  }

 public:
  StrategyOutcome run(const StrategyInfo& self, const StrategyContext& c) const override {
    for (const auto& other : self.may_adopt) {
      auto it = c.earlier.find(other);
      if (it != c.earlier.end() && it->second.avoided) return adopted(self.name, other, it->second);
    }
    // Proven unavoidable: nothing to search for unless contact is accepted and the reference is
    // above the lowest contact level (a least-loss search may still lower it). Else the car falls
    // back to what the baseline gives.
    if (c.unavoidable && (!self.limits.accept_contact || c.unmitigated.loss_level <= 4))
      return fallback_to_baseline(self, c);
    const Planner* planner = find_planner(self.planner);
    const PlanResult plan = planner->plan({c.scene, c.model, self.limits, c.seed, c.keep_tree});
    StrategyOutcome o;
    if (const auto& found = plan.avoidance ? plan.avoidance : plan.collision) {
      // The planner's path is thinned and stitched from tree edges: replaying its controls gives
      // the same run at every step, which is what the outcome shows and a verifier re-checks.
      o = outcome_of(self.name, replay(c.scene, c.model, self.limits, found->maneuver), c.unmitigated, c.scene);
    } else {
      // Every branch broke the strategy's constraint: it cannot be executed here.
      o = fallback_to_baseline(self, c);
    }
    // With contact accepted, a collision found by an earlier strategy is also admissible.
    if (self.limits.accept_contact && !o.avoided) {
      for (const auto& other : self.may_adopt) {
        auto it = c.earlier.find(other);
        if (it != c.earlier.end() && less_loss(it->second.impact, o.impact)) {
          const auto stats = o.planner;
          o = adopted(self.name, other, it->second);
          o.planner = stats;
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
};

}  // namespace

StrategyOutcome outcome_of(std::string_view strategy, const RolloutResult& rollout, const ImpactAssessment& unmitigated,
                           const Scene& scene) {
  StrategyOutcome o;
  o.strategy = strategy;
  o.avoided = rollout.avoided();
  o.contact = rollout.termination == Termination::kContact;
  o.road_departure = rollout.termination == Termination::kRoadDeparture;
  if (!o.avoided) o.impact = rollout.impact;
  o.delta_loss = unmitigated.loss_level - o.impact.loss_level;
  // Every integration step, the closed-form final stop's too: the least TTC lies inside a stop.
  o.path = with_closed_form_stop(rollout.path, scene.config().simulation.dt_s);
  o.min_ttc_s = o.contact ? 0.0 : min_ttc_along(scene, o.path);
  o.maneuver = rollout.maneuver;
  return o;
}

bool better_outcome(const StrategyOutcome& a, const StrategyOutcome& b) noexcept {
  if (a.avoided != b.avoided) return a.avoided;
  if (a.avoided) return false;
  return less_loss(a.impact, b.impact);
}

bool avoidance_admissible(const ControlLimits& found_with, const ControlLimits& limits) noexcept {
  return (!found_with.allow_rear_lock || limits.allow_rear_lock) &&
         (!limits.forbid_rear_sliding || found_with.forbid_rear_sliding);
}

StrategyOutcome adopted(const std::string& name, const std::string& source_name, const StrategyOutcome& source) {
  StrategyOutcome o = source;
  o.strategy = name;
  o.adopted_from = source.adopted_from.empty() ? source_name : source.adopted_from;
  o.planner = {};
  o.tree.clear();
  return o;
}

std::shared_ptr<const Strategy> emergency_stop_strategy() {
  static const auto s = std::make_shared<const EmergencyStop>();
  return s;
}

std::shared_ptr<const Strategy> planned_strategy() {
  static const auto s = std::make_shared<const PlannedStrategy>();
  return s;
}

StrategyTable::StrategyTable(std::shared_ptr<const std::vector<RegisteredStrategy>> entries)
    : entries_(std::move(entries)) {}

const RegisteredStrategy* StrategyTable::find(std::string_view name) const noexcept {
  for (const auto& e : *entries_)
    if (e.info.name == name) return &e;
  return nullptr;
}

const StrategyInfo* StrategyTable::info(std::string_view name) const noexcept {
  const RegisteredStrategy* e = find(name);
  return e ? &e->info : nullptr;
}

std::vector<std::string> StrategyTable::names() const {
  std::vector<std::string> out;
  out.reserve(entries_->size());
  for (const auto& e : *entries_) out.push_back(e.info.name);
  return out;
}

const StrategyInfo* StrategyTable::first_of(StrategyRole role) const noexcept {
  for (const auto& e : *entries_)
    if (e.info.role == role) return &e.info;
  return nullptr;
}

StrategyTable registered_strategies() { return StrategyTable(strategy_registry().table()); }

StrategyRegistration::StrategyRegistration(StrategyInfo info, std::shared_ptr<const Strategy> strategy)
    : name_(info.name) {
  if (!strategy) throw UsageError(fmt::format("strategy '{}' has no implementation", info.name));
  if (!info.planner.empty() && find_planner(info.planner) == nullptr)
    throw UsageError(fmt::format("strategy '{}': unknown planner '{}'; expected one of: {}", info.name, info.planner,
                                 core::join(planner_names(), ", ")));
  const StrategyTable table = registered_strategies();
  for (const auto& other : info.may_adopt)
    if (const StrategyInfo* o = table.info(other); o == nullptr || o->order >= info.order)
      throw UsageError(
          fmt::format("strategy '{}' may adopt '{}', which is not a strategy evaluated before it", info.name, other));
  strategy_registry().add({std::move(info), std::move(strategy)});
}

StrategyRegistration::~StrategyRegistration() { strategy_registry().remove(name_); }

}  // namespace emrm::sim
