// When a valid rollout is over (termination.hpp): the built-in termination tests — passed the truck,
// stopped, certain to stop short, the horizon, and the safe state after the truck.

#include "emrm/sim/termination.hpp"

#include <cmath>

#include "check_chain.hpp"
#include "check_support.hpp"
#include "emrm/core/trig.hpp"

namespace emrm::sim {
namespace detail {

class PassedTruckTest {
 public:
  explicit PassedTruckTest(const Scene& scene) : passed_x_m_(scene.passed_x_m()) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.ego_extent.min_x > passed_x_m_) return end(why, Termination::kPassed);
    return false;
  }

 private:
  double passed_x_m_;
};

class StoppedTest {
 public:
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.state.speed_mps() < kStoppedSpeed_mps) return end(why, Termination::kStopped);
    return false;
  }
};

// Braking straight at full demand (the friction limit, or the brakes' cap), the rest is closed form:
// the car stops short of the truck, and the rollout jumps to where and when it comes to rest.
class StopsShortTest {
 public:
  explicit StopsShortTest(const Scene& scene)
      : truck_near_x_m_(scene.initial_distance_m()),
        decel_mps2_(scene.config().actuation.full_decel_mps2(scene.friction())) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const Control& u = step.control;
    VehicleState& s = step.state;
    if (!(step.full_brake_held && !step.applied.rear_lock && std::abs(s.yaw_rad) < 0.02 &&
          std::abs(s.steer_rad) < 0.005 && std::abs(step.steer_command_rad) < 0.005 &&
          std::abs(s.yaw_rate_radps) < 0.01 && std::abs(s.vy_mps) < 0.05))
      return false;
    const double speed = s.speed_mps();
    const double stop_distance = speed * speed / (2.0 * decel_mps2_);
    if (!(step.ego_extent.max_x + stop_distance + 0.05 < truck_near_x_m_ &&
          step.truck_extent.max_y > step.ego_extent.min_y))
      return false;
    if (result.path.empty() || result.path.back().t_s != step.t_s) result.path.push_back({step.t_s, s, u});
    s.x_m += stop_distance * std::cos(s.yaw_rad);
    s.y_m += stop_distance * std::sin(s.yaw_rad);
    step.t_s += speed / decel_mps2_;
    s.vx_mps = s.vy_mps = s.yaw_rate_radps = 0.0;
    return end(why, Termination::kStopped);
  }

 private:
  double truck_near_x_m_;
  double decel_mps2_;
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
    : CheckChain(std::make_unique<const detail::TerminationTests>(
          detail::TerminationTests{detail::PassedTruckTest(scene), detail::StoppedTest(), detail::StopsShortTest(scene),
                                   detail::HorizonTest(scene), detail::StabilisedTest(scene)})) {}

}  // namespace emrm::sim
