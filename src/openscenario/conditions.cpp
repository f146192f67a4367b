// Conditions and triggers as esmini evaluates them (OSCCondition.cpp): edges against the previous
// evaluation, delays through the history of values, groups as AND (a false stops the evaluation of
// the conditions without delay), triggers as OR of their groups.

#include <cmath>
#include <cstdlib>
#include <limits>

#include "runtime.hpp"

namespace emrm::openscenario::detail {
namespace {

// esmini's EvaluateRule: strict comparisons need a margin of SMALL_NUMBER, the others allow it.
bool holds(double value, Rule rule, double threshold) {
  switch (rule) {
    case Rule::kGreaterThan:
      return value > threshold + kSmall;
    case Rule::kLessThan:
      return value < threshold - kSmall;
    case Rule::kEqualTo:
      return std::fabs(value - threshold) < kSmall;
    case Rule::kGreaterOrEqual:
      return value >= threshold - kSmall;
    case Rule::kLessOrEqual:
      return value <= threshold + kSmall;
    case Rule::kNotEqualTo:
      return std::fabs(value - threshold) >= kSmall;
  }
  return false;
}

double velocity_along(const EntityState& e, double ux, double uy) {
  return e.speed_mps * (std::cos(e.pose.heading_rad) * ux + std::sin(e.pose.heading_rad) * uy);
}

// esmini's Object::TimeToCollision: the distance over the speed at which it closes (along the
// target's velocity), undefined (negative) when it does not close.
double ttc_to_entity(const World& world, const EntityState& from, const EntityState& to, const DistanceSpec& spec) {
  const double distance = measured_distance(world, from, to, spec);
  double closing = from.speed_mps;
  if (std::fabs(to.speed_mps) > kSmall) {
    const double ux = std::cos(to.pose.heading_rad) * (to.speed_mps > 0.0 ? 1.0 : -1.0);
    const double uy = std::sin(to.pose.heading_rad) * (to.speed_mps > 0.0 ? 1.0 : -1.0);
    const double projected = velocity_along(from, ux, uy);
    const double sign_own = from.speed_mps >= 0.0 ? 1.0 : -1.0;
    const double sign_projected = projected >= 0.0 ? 1.0 : -1.0;
    closing = sign_own * sign_projected * (projected - std::fabs(to.speed_mps));
  }
  if (std::fabs(distance) < kSmall || std::fabs(closing) < kSmall) return -1.0;
  const double ttc = distance / closing;
  return ttc < 0.0 ? -1.0 : ttc;
}

// esmini's ParameterCondition: numbers compared by the rule, text only for equality.
bool parameter_holds(const World& world, const ParameterCondition& p) {
  const auto found = world.parameters.find(p.parameter);
  const std::string value = found != world.parameters.end() ? found->second : std::string();
  char* end_value = nullptr;
  char* end_threshold = nullptr;
  const double number = std::strtod(value.c_str(), &end_value);
  const double threshold = std::strtod(p.value.c_str(), &end_threshold);
  if (!value.empty() && !p.value.empty() && *end_value == '\0' && *end_threshold == '\0')
    return holds(number, p.rule, threshold);
  if (p.rule == Rule::kEqualTo) return value == p.value;
  if (p.rule == Rule::kNotEqualTo) return value != p.value;
  return false;
}

}  // namespace

bool ConditionRuntime::check_state() {
  const auto& spec = std::get<StoryboardElementStateCondition>(spec_.kind);
  const auto matches = [&](const StateChange& c) {
    switch (spec.state) {
      case ElementState::kStandbyState:
        return c.state == State::kStandby;
      case ElementState::kRunningState:
        return c.state == State::kRunning;
      case ElementState::kCompleteState:
        return c.state == State::kComplete;
      case ElementState::kStartTransition:
        return c.transition == StateTransition::kStart;
      case ElementState::kEndTransition:
        return c.transition == StateTransition::kEnd;
      case ElementState::kStopTransition:
        return c.transition == StateTransition::kStop;
      case ElementState::kSkipTransition:
        return c.transition == StateTransition::kSkip;
    }
    return false;
  };
  // A transition is seen at the one evaluation after it; a state until it changes.
  latest_.transition = StateTransition::kNone;
  if (pending_.empty()) return matches(latest_);
  bool result = false;
  for (const StateChange& change : pending_) result = result || matches(change);
  latest_ = pending_.back();
  pending_.clear();
  return result;
}

bool ConditionRuntime::check(const World& world, double time_s) {
  if (const auto* c = std::get_if<SimulationTimeCondition>(&spec_.kind)) return holds(time_s, c->rule, c->value_s);
  if (std::holds_alternative<StoryboardElementStateCondition>(spec_.kind)) return check_state();
  if (const auto* p = std::get_if<ParameterCondition>(&spec_.kind)) return parameter_holds(world, *p);
  // An entity condition: any (or all) of the triggering entities.
  bool result = false;
  for (const std::string& name : spec_.triggering_entities) {
    const EntityState& e = world.entity(name);
    bool one = false;
    if (const auto* sc = std::get_if<SpeedCondition>(&spec_.kind)) {
      one = holds(e.speed_mps, sc->rule, sc->value_mps);
    } else if (const auto* cc = std::get_if<CollisionCondition>(&spec_.kind)) {
      if (!cc->entity.empty()) {
        one = boxes_overlap(e, world.entity(cc->entity));
      } else {
        for (const EntityState& other : world.entities)
          one = one || (&other != &e && other.spec->kind == cc->kind && boxes_overlap(e, other));
      }
    } else if (const auto* off = std::get_if<OffroadCondition>(&spec_.kind)) {
      one = e.off_road_since_s && time_s - *e.off_road_since_s > off->duration_s;  // esmini: no slack
    } else if (const auto* eor = std::get_if<EndOfRoadCondition>(&spec_.kind)) {
      one = e.end_of_road_since_s && time_s - *e.end_of_road_since_s > eor->duration_s - kSmall;
    } else if (const auto* rs = std::get_if<RelativeSpeedCondition>(&spec_.kind)) {
      one = holds(e.speed_mps - world.entity(rs->entity).speed_mps, rs->rule, rs->value_mps);
    } else if (const auto* hw = std::get_if<TimeHeadwayCondition>(&spec_.kind)) {
      const double d = measured_distance(world, e, world.entity(hw->entity), hw->distance);
      one = d >= 0.0 && e.speed_mps > kSmall && holds(std::fabs(d / e.speed_mps), hw->rule, hw->value_s);
    } else if (const auto* tc = std::get_if<TimeToCollisionCondition>(&spec_.kind)) {
      double ttc = -1.0;
      if (const auto* target = std::get_if<std::string>(&tc->target)) {
        ttc = ttc_to_entity(world, e, world.entity(*target), tc->distance);
      } else {
        const WorldPose p = resolve(world, std::get<Position>(tc->target), &e).pose;
        const double d = measured_distance(world, e, p, tc->distance);
        if (std::fabs(d) > kSmall && std::fabs(e.speed_mps) > kSmall && d / e.speed_mps >= 0.0) ttc = d / e.speed_mps;
      }
      one = ttc >= 0.0 && holds(ttc, tc->rule, tc->value_s);
    } else if (const auto* rd = std::get_if<RelativeDistanceCondition>(&spec_.kind)) {
      one =
          holds(std::fabs(measured_distance(world, e, world.entity(rd->entity), rd->distance)), rd->rule, rd->value_m);
    } else if (const auto* dc = std::get_if<DistanceCondition>(&spec_.kind)) {
      const WorldPose p = resolve(world, dc->position, &e).pose;
      one = holds(std::fabs(measured_distance(world, e, p, dc->distance)), dc->rule, dc->value_m);
    } else if (const auto* rp = std::get_if<ReachPositionCondition>(&spec_.kind)) {
      const WorldPose p = resolve(world, rp->position, &e).pose;
      one = std::hypot(e.pose.x_m - p.x_m, e.pose.y_m - p.y_m) < rp->tolerance_m;
    }
    result = one;
    if (!one && spec_.all_entities) break;
    if (one && !spec_.all_entities) break;
  }
  return result;
}

void ConditionRuntime::register_value(double time_s, bool value) {
  if (!history_.empty() && time_s < history_.back().first + kSmall) {
    history_.back().second = value;  // the same time evaluated again (esmini's first two frames)
    if (history_.size() > 1 && history_[history_.size() - 2].second == value) history_.pop_back();
    history_index_ = std::min(history_index_, history_.size());
  } else if (history_.empty() || value != history_.back().second) {
    history_.emplace_back(time_s, value);  // the first value, or a change
  }
}

// esmini's ConditionDelay::GetValueAtTime: true when the value was true at any registered change
// in the window since the previous look, else the value holding at `time_s`.
bool ConditionRuntime::delayed_value(double time_s) {
  if (history_.empty()) return false;
  if (history_index_ >= history_.size()) return history_.back().second;
  if (time_s > history_[history_index_].first - kSmall) {
    bool value = false;
    for (; history_index_ < history_.size() && time_s > history_[history_index_].first - kSmall; ++history_index_)
      value = value || history_[history_index_].second;
    return value;
  }
  return history_index_ > 0 && history_[history_index_ - 1].second;
}

bool ConditionRuntime::evaluate(const World& world, double time_s) {
  const bool result = check(world, time_s);
  bool current = result;
  if (spec_.edge != ConditionEdge::kNone) {
    current = false;
    if (evaluated_) {
      if (spec_.edge == ConditionEdge::kRising) current = result && !last_result_;
      if (spec_.edge == ConditionEdge::kFalling) current = !result && last_result_;
      if (spec_.edge == ConditionEdge::kRisingOrFalling) current = result != last_result_;
    }
  }
  last_result_ = result;
  evaluated_ = true;
  register_value(time_s, current);
  value_ = delayed_value(time_s - spec_.delay_s);
  return value_;
}

void ConditionRuntime::reset() {
  history_.clear();
  history_index_ = 0;
  value_ = false;
  pending_.clear();
}

TriggerRuntime::TriggerRuntime(const Trigger& spec) {
  for (const auto& group : spec.groups) {
    groups_.emplace_back();
    for (const Condition& c : group) groups_.back().push_back(std::make_unique<ConditionRuntime>(c));
  }
}

bool TriggerRuntime::evaluate(const World& world, double time_s) {
  bool result = false;
  for (auto& group : groups_) {
    if (group.empty()) continue;
    bool all = true;
    for (auto& condition : group)
      if (all || condition->spec().delay_s > 0.0) all = condition->evaluate(world, time_s) && all;
    result = result || all;
  }
  // A trigger that fired starts its conditions' edges afresh (esmini: state IDLE).
  if (result)
    for (auto& group : groups_)
      for (auto& condition : group) condition->set_idle();
  return result;
}

void TriggerRuntime::reset() {
  for (auto& group : groups_)
    for (auto& condition : group) condition->reset();
}

}  // namespace emrm::openscenario::detail
