#pragma once

// The built-in termination tests of a rollout (rollout.hpp, TerminationTest): passed the truck,
// stopped, certain to stop short, the horizon, and the safe state after the truck. Internal to
// src/sim: rollout.cpp is the only user; they sit in its anonymous namespace's neighbour so the
// rollout loop can call them directly.

#include <cmath>
#include <numbers>

#include "emrm/sim/rollout.hpp"

namespace emrm::sim::termination {

// The built-in checks answer through `why` and return whether the step ends the rollout.
inline bool end(Termination& why, Termination reason) noexcept {
  why = reason;
  return true;
}

inline constexpr double kStoppedSpeed_mps = 0.05;


class PassedTruckTest {
 public:
  explicit PassedTruckTest(const Scene& scene) : truck_far_x_m_(scene.truck_far_x_m()) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.ego_extent.min_x > truck_far_x_m_) return end(why, Termination::kPassed);
    return false;
  }

 private:
  double truck_far_x_m_;
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
      : truck_near_x_m_(scene.initial_distance_m()), decel_mps2_(scene.config().actuation.full_decel_mps2(scene.cell().mu)) {}
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

}  // namespace emrm::sim::termination
