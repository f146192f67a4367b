// When a valid rollout is over (termination.hpp): the built-in termination tests — passed the truck,
// stopped, certain to stop short, the horizon, and the safe state after the truck.

#include "emrm/sim/termination.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "check_chain.hpp"
#include "check_support.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/sim/validity.hpp"

namespace emrm::sim {
namespace detail {

class PassedTruckTest {
 public:
  explicit PassedTruckTest(const Scene& scene) : scene_(scene) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.ego_extent.min_x > scene_.passed_x_m(step.t_s)) return end(why, Termination::kPassed);
    return false;
  }

 private:
  const Scene& scene_;
};

// At rest: a safe state, unless an actor that moves on meets the standing car (touch_at_rest); then
// the rollout ends in that contact, when it happens, the car where it stands.
bool end_at_rest(const Scene& scene, Step& step, RolloutResult& result, Termination& why) {
  if (const auto touch = touch_at_rest(scene, step.state, step.t_s)) {
    const Actor& actor = scene.actors()[touch->actor];
    if (result.path.empty() || result.path.back().t_s != step.t_s) result.path.push_back({step.t_s, step.state, {}});
    step.t_s = touch->t_s;
    step.ego = scene.ego_box(step.state);
    result.impact = actor_impact(scene, actor.body(), step.state, actor.at(step.t_s));
    return end(why, Termination::kContact);
  }
  return end(why, Termination::kStopped);
}

class StoppedTest {
 public:
  explicit StoppedTest(const Scene& scene) : scene_(scene) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    if (step.state.speed_mps() < kStoppedSpeed_mps) return end_at_rest(scene_, step, result, why);
    return false;
  }

 private:
  const Scene& scene_;
};

// The least gap, from time t_s until both are at rest, between a hazard's near side that drives
// along the road (its direction's x component) and the ego's front at front_x_m, braking straight at
// decel_mps2 from speed_mps; −∞ when the hazard comes on towards the car and never rests. Both
// motions are piecewise quadratic in closed form: the least gap lies at a breakpoint (the car's stop,
// the hazard's braking onset or rest) or where the two speeds are equal.
double least_gap_while_braking(const Scene& scene, double t_s, double front_x_m, double speed_mps, double decel_mps2) {
  const ActorMotion& m = scene.hazard().motion();
  const double along = m.direction.x;
  if (along < 0.0 && std::isinf(m.rest_time_s())) return -std::numeric_limits<double>::infinity();
  const double stop_s = speed_mps / decel_mps2;
  const auto gap = [&](double tau) {
    const double ego_m =
        tau < stop_s ? speed_mps * tau - 0.5 * decel_mps2 * tau * tau : speed_mps * speed_mps / (2.0 * decel_mps2);
    return scene.initial_distance_m() + along * m.travelled_m(t_s + tau) - (front_x_m + ego_m);
  };
  const auto closing = [&](double tau) {  // the car's speed less the hazard's along the road
    return std::max(speed_mps - decel_mps2 * tau, 0.0) - along * m.speed_at_mps(t_s + tau);
  };
  std::array<double, 4> breaks{0.0, stop_s, m.brake_from_s - t_s, m.rest_time_s() - t_s};
  std::sort(breaks.begin(), breaks.end());
  double least = std::numeric_limits<double>::infinity();
  double previous = 0.0;
  for (const double b : breaks) {
    if (!(b >= 0.0) || std::isinf(b)) continue;
    least = std::min(least, gap(b));
    // Both speeds are linear in between: the gap is least where the closing speed falls through 0.
    const double c0 = closing(previous), c1 = closing(b);
    if (c0 > 0.0 && c1 < 0.0) least = std::min(least, gap(previous + (b - previous) * c0 / (c0 - c1)));
    previous = b;
  }
  return least;
}

// Braking straight at full demand (the friction limit, or the brakes' cap), the rest is closed form:
// the car stops short of the truck, and the rollout jumps to where and when it comes to rest. Short
// of a hazard that drives along the road (a car cutting in) means behind it until both rest.
class StopsShortTest {
 public:
  explicit StopsShortTest(const Scene& scene)
      : scene_(scene),
        truck_near_x_m_(scene.initial_distance_m()),
        decel_mps2_(scene.config().actuation.full_decel_mps2(scene.friction())),
        hazard_drives_(scene.hazard().motion().direction.x != 0.0),
        closed_form_(!scene.hazard().motion().track) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const Control& u = step.control;
    VehicleState& s = step.state;
    // A hazard given as samples (an imported scenario's) has no closed form to stop short of: the
    // stop is simulated to rest.
    if (!closed_form_) return false;
    if (!(step.full_brake_held && !step.applied.rear_lock && std::abs(s.yaw_rad) < 0.02 &&
          std::abs(s.steer_rad) < 0.005 && std::abs(step.steer_command_rad) < 0.005 &&
          std::abs(s.yaw_rate_radps) < 0.01 && std::abs(s.vy_mps) < 0.05))
      return false;
    const double speed = s.speed_mps();
    const double stop_distance = speed * speed / (2.0 * decel_mps2_);
    constexpr double kMargin_m = 0.05;
    const bool short_of_it = hazard_drives_ ? least_gap_while_braking(scene_, step.t_s, step.ego_extent.max_x, speed,
                                                                      decel_mps2_) > kMargin_m
                                            : step.ego_extent.max_x + stop_distance + kMargin_m < truck_near_x_m_;
    if (!(short_of_it && step.truck_extent.max_y > step.ego_extent.min_y)) return false;
    if (result.path.empty() || result.path.back().t_s != step.t_s) result.path.push_back({step.t_s, s, u});
    s.x_m += stop_distance * std::cos(s.yaw_rad);
    s.y_m += stop_distance * std::sin(s.yaw_rad);
    step.t_s += speed / decel_mps2_;
    s.vx_mps = s.vy_mps = s.yaw_rate_radps = 0.0;
    return end_at_rest(scene_, step, result, why);
  }

 private:
  const Scene& scene_;
  double truck_near_x_m_;
  double decel_mps2_;
  bool hazard_drives_;
  bool closed_form_;
};

class HorizonTest {
 public:
  explicit HorizonTest(const Scene& scene) : horizon_s_(scene.config().simulation.horizon_s) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.t_s >= (step.recovering ? step.recovery_until_s : horizon_s_) - 1e-9)
      return end(why, Termination::kHorizon);
    return false;
  }

 private:
  double horizon_s_;
};

// After passing the truck: stable (yaw rate, body slip, heading and steering within the scene's
// safe_state bounds) with room to stop, i.e. a straight full stop from here stays on the road.
class StabilisedTest {
 public:
  explicit StabilisedTest(const Scene& scene) : scene_(scene) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (!stable_with_room_to_stop(scene_, step.state, step.ego)) return false;
    return end(why, Termination::kStabilised);
  }

 private:
  const Scene& scene_;
};

}  // namespace detail

bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s) noexcept {
  return stable_with_room_to_stop(scene, s, scene.ego_box(s));
}

bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s, const core::OrientedBox& ego_box) noexcept {
  const SafeStateConfig& bounds = scene.config().safe_state;
  if (!(std::abs(s.yaw_rate_radps) <= bounds.max_yaw_rate_radps &&
        std::abs(s.slip_angle_rad()) <= bounds.max_slip_angle_rad &&
        std::abs(core::wrap_angle(s.yaw_rad)) <= bounds.max_heading_error_rad &&
        std::abs(s.steer_rad) <= bounds.max_steer_rad))
    return false;
  // A stop from here, through the brakes' dead time and ramp.
  const double stop_distance = scene.config().actuation.stopping_distance_m(s.speed_mps(), scene.friction(), false);
  core::OrientedBox at_rest = ego_box;
  at_rest.center = at_rest.center + core::Vec2::unit(s.yaw_rad) * stop_distance;
  return scene.on_drivable_area(at_rest);
}

namespace detail {

// The built-in termination tests, in their order (CheckChain calls ends() each step): those of the
// approach, or after the truck those of the recovery phase.
struct TerminationTests {
  PassedTruckTest passed;
  StoppedTest stopped;
  StopsShortTest stops_short;
  HorizonTest horizon;
  StabilisedTest stabilised;

  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    if (step.recovering)
      return stopped.ends(step, result, why) || stabilised.ends(step, result, why) || horizon.ends(step, result, why);
    return passed.ends(step, result, why) || stopped.ends(step, result, why) || stops_short.ends(step, result, why) ||
           horizon.ends(step, result, why);
  }
};

}  // namespace detail

template class CheckChain<TerminationTest, detail::TerminationTests>;

TerminationTest::TerminationTest(const Scene& scene)
    : CheckChain(std::make_unique<const detail::TerminationTests>(detail::TerminationTests{
          detail::PassedTruckTest(scene), detail::StoppedTest(scene), detail::StopsShortTest(scene),
          detail::HorizonTest(scene), detail::StabilisedTest(scene)})) {}

std::vector<PathPoint> with_closed_form_stop(const std::vector<PathPoint>& path, double dt_s) {
  if (path.size() < 2) return path;
  const PathPoint& from = path[path.size() - 2];
  const PathPoint& rest = path.back();
  const double span_s = rest.t_s - from.t_s;
  const double speed = from.state.speed_mps();
  if (!(rest.state.speed_mps() == 0.0 && speed > 0.0 && span_s > 1.5 * dt_s)) return path;
  std::vector<PathPoint> out(path.begin(), path.end() - 1);
  const double decel = speed / span_s;
  const auto [c, s] = core::cos_sin(from.state.yaw_rad);
  for (double tau = dt_s; tau < span_s - 0.5 * dt_s; tau += dt_s) {
    PathPoint p = from;
    const double travelled = speed * tau - 0.5 * decel * tau * tau;
    p.t_s = from.t_s + tau;
    p.state.x_m += travelled * c;
    p.state.y_m += travelled * s;
    const double k = (speed - decel * tau) / speed;
    p.state.vx_mps *= k;
    p.state.vy_mps *= k;
    p.state.yaw_rate_radps = 0.0;
    out.push_back(p);
  }
  out.push_back(rest);
  return out;
}

}  // namespace emrm::sim
