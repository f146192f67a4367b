// The private actions as esmini steps them (OSCPrivateAction.cpp): started when their event starts,
// stepped at the step's start time before the entities move (runtime.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "runtime.hpp"

namespace emrm::openscenario::detail {
namespace {

double sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }
double wrap(double angle) { return std::remainder(angle, 2.0 * std::numbers::pi); }

double limit(double value, double bound) { return std::clamp(value, -std::fabs(bound), std::fabs(bound)); }

EntityState& on_lane_entity(World& world, const Action& spec, const std::string& actor) {
  EntityState& e = world.entity(actor);
  if (world.roads == nullptr || !e.on_lane)
    throw InputError(spec.where, fmt::format("{}: entity '{}' is on no lane when the action starts", spec.name, actor));
  return e;
}

double range_of(const TransitionDynamics& d, double start, double target) {
  switch (d.dimension) {
    case DynamicsDimension::kTime:
    case DynamicsDimension::kDistance:
      return d.value;
    case DynamicsDimension::kRate:
      return range_for_peak_rate(d.shape, start, target, d.value);
  }
  return d.value;
}

}  // namespace

unsigned ActionRuntime::domains() const {
  return std::visit(
      [](const auto& a) -> unsigned {
        using A = std::decay_t<decltype(a)>;
        if constexpr (std::is_same_v<A, SpeedAction>) return kLongitudinal;
        if constexpr (std::is_same_v<A, LaneChangeAction> || std::is_same_v<A, LaneOffsetAction>) return kLateral;
        if constexpr (std::is_same_v<A, FollowTrajectoryAction>) return a.timing ? kLateral | kLongitudinal : kLateral;
        if constexpr (std::is_same_v<A, EnvironmentAction> || std::is_same_v<A, ControllerAction> ||
                      std::is_same_v<A, AppearanceOnlyAction> || std::is_same_v<A, ParameterAction>)
          return 0U;
        return kLateral | kLongitudinal;
      },
      spec_.kind);
}

bool ActionRuntime::start(World& world, double time_s) {
  (void)time_s;
  param_ = 0.0;
  if (const auto* speed = std::get_if<SpeedAction>(&spec_.kind)) {
    start_speed(world, *speed);
  } else if (const auto* change = std::get_if<LaneChangeAction>(&spec_.kind)) {
    start_lane_change(world, *change);
  } else if (const auto* offset = std::get_if<LaneOffsetAction>(&spec_.kind)) {
    start_lane_offset(world, *offset);
  } else if (const auto* follow = std::get_if<FollowTrajectoryAction>(&spec_.kind)) {
    start_trajectory(world, *follow);
  } else if (const auto* parameter = std::get_if<ParameterAction>(&spec_.kind)) {
    std::string& value = world.parameters[parameter->parameter];
    if (parameter->set) {
      value = *parameter->set;
    } else {
      char* end = nullptr;
      const double number = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || *end != '\0')
        throw InputError(spec_.where,
                         fmt::format("parameter '{}' is '{}', not a number to modify", parameter->parameter, value));
      value = fmt::format("{:.17g}", number * parameter->multiply + parameter->add);
    }
  } else if (const auto* teleport = std::get_if<TeleportAction>(&spec_.kind)) {
    EntityState& e = world.entity(actor_);
    const ResolvedPosition p = resolve(world, teleport->position, &e);
    if (p.lane) {
      e.on_lane = true;
      e.lane = *p.lane;
      e.direction = p.direction;
      e.heading_offset_rad = 0.0;
      world.update_pose(e);
      e.heading_offset_rad = wrap(p.pose.heading_rad - e.pose.heading_rad);
      world.update_pose(e);
    } else {
      e.on_lane = false;
      e.pose = p.pose;
    }
    return true;
  }
  // A controller action is done at once; an environment, visibility or appearance action ends in
  // its first step (esmini's Step ends them), so its completion is seen by the next evaluation.
  return std::holds_alternative<ControllerAction>(spec_.kind);
}

bool ActionRuntime::step(World& world, double time_s, double dt_s) {
  if (const auto* speed = std::get_if<SpeedAction>(&spec_.kind)) return step_speed(world, *speed, dt_s);
  if (std::holds_alternative<LaneChangeAction>(spec_.kind)) return step_lane_change(world, dt_s);
  if (const auto* offset = std::get_if<LaneOffsetAction>(&spec_.kind)) return step_lane_offset(world, *offset, dt_s);
  if (const auto* follow = std::get_if<FollowTrajectoryAction>(&spec_.kind))
    return step_trajectory(world, *follow, time_s, dt_s);
  return true;
}

// ---- SpeedAction (esmini's LongSpeedAction) ----

double ActionRuntime::speed_target(const World& world, const SpeedAction& a) const {
  const double max_speed = world.entity(actor_).spec->performance.max_speed_mps;
  if (!a.relative) return limit(a.value, max_speed);
  const double reference = world.entity(*a.relative).speed_mps;
  return limit(a.delta ? reference + a.value : reference * a.value, max_speed);
}

void ActionRuntime::start_speed(World& world, const SpeedAction& a) {
  EntityState& e = world.entity(actor_);
  const Performance& performance = e.spec->performance;
  transition_.shape = a.dynamics.shape;
  transition_.start = e.speed_mps;
  transition_.target = speed_target(world, a);
  if (a.dynamics.dimension == DynamicsDimension::kDistance) {
    transition_.range = duration_for_distance(transition_.start, transition_.target, a.dynamics.value);
  } else {
    transition_.range = range_of(a.dynamics, transition_.start, transition_.target);
  }
  // A shape steeper than the vehicle accelerates is stretched in time (esmini's SetMaxRate).
  const double max_rate =
      transition_.target > transition_.start ? performance.max_acceleration_mps2 : performance.max_deceleration_mps2;
  const double peak = std::fabs(transition_.slope(transition_.range / 2.0));
  const double linear_peak =
      transition_.jumps() ? 0.0 : std::fabs(transition_.target - transition_.start) / transition_.range;
  const double peak_rate = transition_.shape == DynamicsShape::kLinear ? linear_peak : peak;
  scale_ = (!transition_.jumps() && peak_rate > max_rate) ? peak_rate / max_rate : 1.0;
  reached_ = false;
  e.speed_mps = transition_.value(0.0);
}

bool ActionRuntime::step_speed(World& world, const SpeedAction& a, double dt_s) {
  EntityState& e = world.entity(actor_);
  const Performance& performance = e.spec->performance;
  if (a.relative) transition_.target = speed_target(world, a);
  double speed = 0.0;
  if (transition_.range > 0.0 && param_ > transition_.range - kSmall) {
    // After the transition (a continuous relative target): follow it within the vehicle's limits.
    const double acc = dt_s > kSmall ? (transition_.target - e.speed_mps) / dt_s : 0.0;
    const double limited = std::clamp(acc, -performance.max_deceleration_mps2, performance.max_acceleration_mps2);
    speed = limit(e.speed_mps + limited * dt_s, performance.max_speed_mps);
  } else {
    param_ = std::min(param_ + dt_s / scale_, std::max(transition_.range, 0.0));
    speed = transition_.value(param_);
    const double required = dt_s > kSmall ? (speed - e.speed_mps) / dt_s : 0.0;
    if (required > performance.max_acceleration_mps2 + kSmall ||
        required < -(performance.max_deceleration_mps2 + kSmall)) {
      const double acc = std::clamp(required, -performance.max_deceleration_mps2, performance.max_acceleration_mps2);
      speed = limit(e.speed_mps + acc * dt_s, performance.max_speed_mps);
      const double step_approx = (speed - e.speed_mps) / required;
      param_ = std::clamp(param_ - (dt_s - step_approx), 0.0, std::max(transition_.range, 0.0));
    }
  }
  if (param_ > transition_.range - kSmall && std::fabs(speed - transition_.target) < kSmall) {
    reached_ = true;
    speed = transition_.target;
  }
  e.speed_mps = speed;
  return reached_ && !(a.relative && a.continuous);
}

// ---- LaneChangeAction (esmini's LatLaneChangeAction) ----

void ActionRuntime::start_lane_change(World& world, const LaneChangeAction& a) {
  EntityState& e = on_lane_entity(world, spec_, actor_);
  int target = a.value;
  if (a.relative) {
    const EntityState& ref = world.entity(*a.relative);
    // value lanes to the left of the reference's driving direction, skipping lane 0.
    const int from = ref.lane.lane_id;
    target = from + a.value * ref.direction;
    if (target == 0 || (from > 0) != (target > 0))
      target = static_cast<int>(sign(target - from)) * (std::abs(target) + 1);
  }
  if (!world.roads->has_lane(e.lane.road_id, target, e.lane.s_m))
    throw InputError(spec_.where, fmt::format("{}: road '{}' has no lane {} at s = {} m where entity '{}' starts it",
                                              spec_.name, e.lane.road_id, target, e.lane.s_m, actor_));
  e.heading_offset_rad = 0.0;
  const double t = world.roads->lane_center_t(e.lane.road_id, e.lane.lane_id, e.lane.s_m) + e.lane.offset_m;
  internal_ = e.lane;
  internal_.lane_id = target;
  internal_.offset_m = t - world.roads->lane_center_t(e.lane.road_id, target, e.lane.s_m);
  transition_.shape = a.dynamics.shape;
  transition_.start = internal_.offset_m;
  // targetLaneOffset, as esmini reads it: along t, from the target lane's centre.
  transition_.target = a.target_lane_offset_m;
  transition_.range = range_of(a.dynamics, transition_.start, transition_.target);
  lane_change_dimension_ = a.dynamics.dimension;
  e.lane = internal_;
  world.update_pose(e);
}

bool ActionRuntime::step_lane_change(World& world, double dt_s) {
  EntityState& e = world.entity(actor_);
  e.moved_longitudinally = true;  // the action moves the entity along the road itself
  if (std::fabs(e.speed_mps) < kSmall) return false;
  const double rate = transition_.slope(param_);
  const double step_len = std::fabs(e.speed_mps) * dt_s;
  double delta_long = 0.0;
  double offset = internal_.offset_m;
  double heading = 0.0;  // of the motion relative to the driving direction, in the road's t sense
  if (lane_change_dimension_ == DynamicsDimension::kDistance) {
    delta_long = std::sqrt(step_len * step_len / (1.0 + rate * rate));
    param_ = std::min(param_ + delta_long, transition_.range);
    offset = transition_.value(param_);
    heading = std::atan(rate);
  } else {
    const double delta_lat = dt_s * std::fabs(rate);
    delta_long = std::sqrt(step_len * step_len - std::pow(std::min(delta_lat, step_len), 2.0));
    if (delta_lat < step_len + kSmall) {
      param_ = std::min(param_ + dt_s, transition_.range);
      offset = transition_.value(param_);
      heading = std::atan2(sign(e.speed_mps) * sign(rate) * delta_lat, delta_long);
    } else {
      // Lateral motion faster than the speed allows: linear, sideways (esmini's fallback).
      param_ = std::min(param_ + step_len * transition_.range / std::fabs(transition_.target - transition_.start),
                        transition_.range);
      Transition linear = transition_;
      linear.shape = DynamicsShape::kLinear;
      offset = linear.value(param_);
      heading = sign(e.speed_mps) * sign(rate) * (std::numbers::pi / 2.0 - kSmall);
    }
  }
  if (transition_.jumps()) delta_long = step_len;
  internal_.offset_m = offset;
  const LaneStep moved = world.roads->step_along(
      internal_, s_step_for(*world.roads, internal_, sign(e.speed_mps) * delta_long) * e.direction);
  if (moved.direction_flipped) e.direction = -e.direction;
  internal_ = moved.to;
  const bool done = param_ > transition_.range - kSmall || std::fabs(offset - transition_.target) < kSmall ||
                    (param_ > 0.0 && sign(offset - transition_.target) != sign(transition_.start - transition_.target));
  // The heading turns with t: towards +t is to the left when driving along s, to the right against it.
  e.heading_offset_rad = done || moved.end_of_road ? 0.0 : heading * e.direction;
  e.lane = internal_;
  world.update_pose(e);
  return done || moved.end_of_road;
}

// ---- LaneOffsetAction (esmini's LatLaneOffsetAction) ----

void ActionRuntime::start_lane_offset(World& world, const LaneOffsetAction& a) {
  EntityState& e = on_lane_entity(world, spec_, actor_);
  const auto center_t = [&](const LaneCoord& c) { return world.roads->lane_center_t(c.road_id, c.lane_id, c.s_m); };
  double target = 0.0;
  if (a.relative) {
    const EntityState& ref = on_lane_entity(world, spec_, *a.relative);
    // The reference's t, moved value to the left of its driving direction, from this lane's centre.
    target = center_t(ref.lane) + ref.lane.offset_m + a.value_m * ref.direction - center_t(e.lane);
  } else {
    target = a.value_m;  // along t, from the lane's centre (esmini)
  }
  transition_.shape = a.shape;
  transition_.start = e.lane.offset_m;
  transition_.target = target;
  transition_.range = range_for_peak_second_derivative(a.shape, transition_.start, target, a.max_lateral_acc_mps2);
}

bool ActionRuntime::step_lane_offset(World& world, const LaneOffsetAction& a, double dt_s) {
  (void)a;
  EntityState& e = world.entity(actor_);
  const double offset = transition_.value(param_);
  const bool done = param_ > transition_.range - kSmall || std::fabs(offset - transition_.target) < kSmall ||
                    (param_ > 0.0 && sign(offset - transition_.target) != sign(transition_.start - transition_.target));
  if (done) {
    e.lane.offset_m = transition_.target;
    e.heading_offset_rad = 0.0;
  } else {
    e.lane.offset_m = offset;
    const double speed = std::fabs(e.speed_mps) > kSmall ? e.speed_mps : kSmall;
    e.heading_offset_rad = std::atan(transition_.slope(param_) / speed) * e.direction;
  }
  world.update_pose(e);
  param_ += dt_s;
  return done;
}

}  // namespace emrm::openscenario::detail
