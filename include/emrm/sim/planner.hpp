#pragma once

// Rollouts and the dual-tree kinodynamic RRT (DESIGN.md §7).
//
// A rollout integrates the vehicle under piecewise-constant controls and checks, every step, the
// separating-axis test against the (moving) truck and the drivable area. It ends in one of:
// contact, road departure, standstill, having passed the truck, or the horizon.
//
// The RRT grows a goal tree (green) towards the passage beside the truck; from every new node it
// rolls out fail-safe branches (orange): a full stop, and, when contact is accepted,
// minimum-momentum collision maneuvers. It keeps the best avoidance path and the least-loss
// collision path, is deterministic for a seed, bounded by nodes (and a wall-clock guard), and
// stops early once its strategy's objective is met.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// What a strategy allows the planner to command.
struct ControlLimits {
  bool allow_rear_lock = false;
  bool forbid_rear_sliding = false;  ///< dodge: the rear axle must never slide sideways
  bool accept_contact = false;       ///< drift_to_accident: a collision is an admissible end
};

/// How a rollout ended.
enum class Termination {
  kContact,        ///< touched the truck
  kRoadDeparture,  ///< left the drivable area
  kConstraint,     ///< violated the strategy's constraint (dodge: rear axle sliding)
  kStopped,        ///< came to rest (or is certain to, braking straight short of the truck)
  kPassed,         ///< its rear is beyond the truck's far side
  kHorizon,        ///< reached the simulation horizon without any of the above
  kOpen,           ///< the plan ran out with no tail: an unfinished tree edge
};

/// One sampled point of a path: time, state and the control being applied.
struct PathPoint {
  double t_s = 0.0;
  VehicleState state;
  Control control;
};

struct RolloutResult {
  Termination termination = Termination::kHorizon;
  std::vector<PathPoint> path;  ///< every `record_every` steps, plus the final state
  double end_time_s = 0.0;
  VehicleState end_state;
  ImpactAssessment impact;  ///< when termination is contact
  /// avoided: no contact, no departure, no violated constraint.
  [[nodiscard]] bool avoided() const {
    return termination == Termination::kStopped || termination == Termination::kPassed ||
           termination == Termination::kHorizon;
  }
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

/// Simulates from `start` at time `t0` under `plan` (then, if the plan runs out, `tail` until an
/// end condition). Deterministic and pure.
class Roller {
 public:
  Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);

  /// Rolls out `plan` from (t0, start). `record_every` thins the recorded path (1 = every step).
  [[nodiscard]] RolloutResult roll(const VehicleState& start, double t0_s, const std::vector<ControlSegment>& plan,
                                   const std::optional<Tail>& tail, int record_every = 5) const;

  [[nodiscard]] const Scene& scene() const noexcept { return scene_; }
  [[nodiscard]] const VehicleModel& model() const noexcept { return model_; }

 private:
  const Scene& scene_;
  const VehicleModel& model_;
  ControlLimits limits_;
};

/// One edge of a search tree, kept for figures.
struct TreeEdge {
  std::vector<PathPoint> points;
  bool fail_safe = false;  ///< orange (fail-safe) vs green (goal tree)
};

struct PlannerStats {
  int nodes = 0;
  int rollouts = 0;
  double time_ms = 0.0;
  bool time_limited = false;  ///< the wall-clock guard stopped the search (results may then vary)
};

/// The planner's answer: the best avoidance (if any) and the least-loss collision (if any).
struct PlanResult {
  std::optional<RolloutResult> avoidance;  ///< full executed path from t = 0
  std::optional<RolloutResult> collision;  ///< least loss, then lowest Δv
  PlannerStats stats;
  std::vector<TreeEdge> tree;  ///< only when asked for
};

/// The dual-tree kinodynamic RRT. `seed` fixes every random choice.
[[nodiscard]] PlanResult plan_rrt(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                                  std::uint64_t seed, bool keep_tree);

/// The reference planner: a dense search over a parametric maneuver family (steer direction,
/// peak steer, hold and counter-steer timing, brake level, rear lock). For tests and diagnostics.
[[nodiscard]] PlanResult plan_reference(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);

/// The least time to collision along a path: at each point, when ego and truck would first touch
/// if both kept their velocities (0 in contact); infinity if they never would within the horizon.
[[nodiscard]] double min_ttc_along(const Scene& scene, const std::vector<PathPoint>& path);

/// Least-loss order: lower level first, then lower Δv.
[[nodiscard]] bool less_loss(const ImpactAssessment& a, const ImpactAssessment& b) noexcept;

}  // namespace emrm::sim
