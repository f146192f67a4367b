#pragma once

// Actuation (docs/actuation.md): what lies between a command and the tires. Perception and
// decision take `perception_latency_s` before the first command; the brakes answer a command after
// a dead time and build pressure along a linear ramp, up to an optional deceleration cap; the
// steering actuator answers after its own dead time and follows the commanded road-wheel angle
// with a first-order lag. Every strategy and every planner rollout drives through it: their
// controls are commands (a steering rate of the commanded angle, a brake demand, the rear lock),
// and the vehicle model receives what the actuators make of them.

#include <string>
#include <vector>

#include "emrm/core/config.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// The scene's `actuation:` block. All zeros is instant actuation ("ideal").
struct ActuationConfig {
  double perception_latency_s = 0.0;   ///< from the hazard to the first command
  double brake_dead_time_s = 0.0;      ///< from a brake command to the first pressure
  double brake_ramp_s = 0.0;           ///< linear rise from no braking to the full demand
  double max_decel_mps2 = 0.0;         ///< brake cap; 0: friction-limited only
  double steer_dead_time_s = 0.0;      ///< from a steering command to the first wheel motion
  double steer_time_constant_s = 0.0;  ///< first-order lag of the road-wheel angle behind its command

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, perception_latency_s, core::non_negative);
    EMRM_FIELD(a, brake_dead_time_s, core::non_negative);
    EMRM_FIELD(a, brake_ramp_s, core::non_negative);
    EMRM_FIELD(a, max_decel_mps2, core::non_negative);
    EMRM_FIELD(a, steer_dead_time_s, core::non_negative);
    EMRM_FIELD(a, steer_time_constant_s, core::non_negative);
  }

  bool operator==(const ActuationConfig&) const = default;

  /// The actuators pass commands through unchanged (the perception latency aside).
  [[nodiscard]] bool instant() const noexcept {
    return brake_dead_time_s == 0.0 && brake_ramp_s == 0.0 && max_decel_mps2 == 0.0 && steer_dead_time_s == 0.0 &&
           steer_time_constant_s == 0.0;
  }
  /// Deceleration of full braking on friction `mu`: mu·g, or the cap if lower.
  [[nodiscard]] double full_decel_mps2(double mu) const noexcept;
  /// Distance a car at `speed_mps` travels, braking straight at full demand from now, before it
  /// stops: v·t_d + v·t_r/2 + v²/(2a) − a·t_r²/24 (for v > a·t_r/2; stopping within the ramp
  /// otherwise), t_d the brake dead time, plus the perception latency with `with_perception`.
  [[nodiscard]] double stopping_distance_m(double speed_mps, double mu, bool with_perception) const noexcept;
  /// Time the same stop takes.
  [[nodiscard]] double stopping_time_s(double speed_mps, double mu, bool with_perception) const noexcept;
  /// For people: "instant", or every parameter with its unit ("perception latency 0.25 s, brake dead
  /// time 0.1 s, …, no brake cap, …").
  [[nodiscard]] std::string summary() const;
};

/// One command as the actuators remember it: issued at `t_s`, held for one step. The commanded
/// road-wheel angle is the one at `t_s` (it moves linearly to the next sample's).
struct CommandSample {
  double t_s = 0.0;
  double steer_command_rad = 0.0;
  double brake = 0.0;
  bool rear_lock = false;
};

/// The actuators' memory: the commanded steering angle now, the brake level the pressure has
/// reached, and the commands still in flight within the longest dead time (oldest first). A
/// rollout that starts where another ended (a planner's tree) carries it on.
struct ActuatorState {
  double steer_command_rad = 0.0;
  double brake_level = 0.0;  ///< fraction of the full demand the pressure has reached, 0…1
  std::vector<CommandSample> history;
};

/// The actuators of one rollout. Pure given their state; cheap.
class Actuators {
 public:
  Actuators(const ActuationConfig& config, const VehicleParams& params, double mu, double dt_s);

  /// The actuators at rest before the hazard, with the wheels at the vehicle's current angle.
  [[nodiscard]] static ActuatorState at_rest(const VehicleState& s);

  /// Takes `command` for the step from `t_s` (state `s`, actuators `a`) and returns the control the
  /// vehicle model integrates over it: the steering rate that moves the wheels to where the lagged,
  /// delayed command puts them at the step's end, the step's mean brake level (times the cap), and
  /// the rear lock after the brake dead time. Advances `a` to the step's end.
  [[nodiscard]] Control apply(ActuatorState& a, const VehicleState& s, const Control& command, double t_s) const;

  /// The brake stays at full demand from here: the pressure is there and every command in flight
  /// (and the current one) asks for it.
  [[nodiscard]] bool full_brake_held(const ActuatorState& a, const Control& command) const noexcept;

 private:
  [[nodiscard]] double steer_command_at(const ActuatorState& a, double t_s) const noexcept;
  [[nodiscard]] const CommandSample* sample_at(const ActuatorState& a, double t_s) const noexcept;

  ActuationConfig config_;
  double max_steer_rad_;
  double max_steer_rate_radps_;
  double brake_scale_;  ///< the cap's share of mu·g
  double dt_s_;
  double memory_s_;  ///< how far back commands are kept
};

}  // namespace emrm::sim
