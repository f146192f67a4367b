#pragma once

// The controls of a rollout, propagation's input (rollout.hpp): what a strategy allows the planner
// to command, a plan of held or pursuit segments and the tail after it, and the schedule that says
// which control applies at each step.

#include <cstddef>
#include <optional>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// What a strategy allows the planner to command.
struct ControlLimits {
  bool allow_rear_lock = false;      ///< the rear wheels may be locked (a handbrake drift)
  bool forbid_rear_sliding = false;  ///< the rear axle must never slide sideways (dodge)
  bool accept_contact = false;       ///< a collision is an admissible end (drift to accident)
};

/// A piece of a plan: a control held for a duration. With `pursue`, the steering rate is not
/// held but recomputed every step by pure pursuit towards that point (closed-loop extension, as
/// in CL-RRT); brake and rear lock are held.
struct ControlSegment {
  Control control;
  double duration_s = 0.0;
  std::optional<core::Vec2> pursue;
  /// With `pursue`: `control.brake` scales the braking that the friction circle leaves after the
  /// current lateral acceleration (a driver braking as hard as the turn allows).
  bool friction_circle_brake = false;
  /// With `pursue`: the steering limit, as the lateral acceleration (in mu·g) of the steady-state
  /// angle; above 1 it allows the transient over-steering of a quick lane change.
  double pursuit_grip = 0.9;
};

/// A segment that holds `control` for `duration_s`.
[[nodiscard]] inline ControlSegment hold(const Control& control, double duration_s) {
  return {control, duration_s, std::nullopt, false, 0.9};
}

/// Pure pursuit: the steering rate (within limits) that turns the wheels towards the angle whose
/// arc passes through `target`, never sharper than the steady-state angle for `grip`·mu·g of
/// lateral acceleration.
[[nodiscard]] double pursuit_steer_rate(const VehicleState& s, const core::Vec2& target, const VehicleParams& p,
                                        double mu, double grip, double dt_s) noexcept;

/// The share of the friction limit left for braking after the current lateral acceleration.
[[nodiscard]] double friction_circle_share(const VehicleState& s, double mu) noexcept;

/// What happens after a plan runs out: `control` is held until the rollout ends; with
/// `straighten`, its steering rate is replaced by one that brings the wheels back to straight.
struct Tail {
  Control control;
  bool straighten = false;
  /// `control.brake` scales the braking the friction circle leaves after the lateral acceleration.
  bool friction_circle_brake = false;
  /// Steer by pure pursuit towards this point instead (a braking swerve into the passage).
  std::optional<core::Vec2> pursue;

  /// The full-stop fail-safe: steering back to straight while braking as hard as the friction
  /// circle allows, which is full ABS braking once the car runs straight.
  [[nodiscard]] static Tail full_stop() { return {Control{0.0, 1.0, false}, true, true, std::nullopt}; }
};

/// The controls of a rollout from t = 0: its plan, then its tail. Replaying them from the cell's
/// initial state with the same scene, model and limits reproduces the rollout step for step: the
/// witness of an outcome (docs/simulate.md, "Evidence").
struct Maneuver {
  std::vector<ControlSegment> plan;
  std::optional<Tail> tail;
};

/// Propagation's input: which control applies at each step. Borrows the plan and tail, which
/// must outlive it.
class ControlSchedule {
 public:
  ControlSchedule(const std::vector<ControlSegment>& plan, const std::optional<Tail>& tail, const VehicleParams& params,
                  const ControlLimits& limits, double mu, double dt_s);
  /// The control to apply from state `s` for the next step, or nothing when the plan has run out
  /// and there is no tail.
  [[nodiscard]] std::optional<Control> control_at(const VehicleState& s);
  /// Moves the schedule on by one step.
  void advance() noexcept { segment_left_s_ -= dt_s_; }
  /// Drops what is left of the plan and the tail for the recovery controller: pure pursuit of a
  /// point ahead on the line y = `keep_y_m`, no braking, rear wheels released (docs/physics.md,
  /// "Safe state").
  void recover(double keep_y_m) noexcept { recovery_y_m_ = keep_y_m; }

 private:
  const std::vector<ControlSegment>& plan_;
  const std::optional<Tail>& tail_;
  const VehicleParams& params_;
  ControlLimits limits_;
  double mu_;
  double dt_s_;
  std::size_t segment_ = 0;
  double segment_left_s_ = 0.0;
  std::optional<double> recovery_y_m_;
};

}  // namespace emrm::sim
