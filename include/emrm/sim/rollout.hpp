#pragma once

// Rollouts: the vehicle driven under a control schedule until something ends the run. A rollout
// is three parts, in the manner of OMPL's StatePropagator / StateValidityChecker / Goal:
// - propagation: the ControlSchedule (controls.hpp) says which control applies at each step (a plan
//   of held or pursuit segments, then a tail), and the vehicle model integrates it;
// - validity: a ValidityChecker (validity.hpp) runs its StepChecks after every step (by default the
//   strategy's constraint, contact with the truck, leaving the drivable area); the first that
//   objects ends the rollout;
// - termination: a TerminationTest (termination.hpp) runs its StepChecks on every valid step (by
//   default: passed the truck, stopped, certain to stop short, horizon).
// Both are a CheckChain (step.hpp): their built-in checks, then those added. New constraints or
// goals are new StepChecks (step.hpp) added to them and handed to the Roller, not edits to its
// loop. This header includes the other four, so that its users need no other.

#include <optional>
#include <vector>

#include "emrm/sim/controls.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/step.hpp"
#include "emrm/sim/termination.hpp"
#include "emrm/sim/validity.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// Simulates from `start` at time `t0` under `plan` (then, if the plan runs out, `tail` until an
/// end condition). Deterministic and pure; the scene and model are borrowed.
class Roller {
 public:
  /// A roller with the built-in validity checks and termination tests.
  Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);
  /// A roller with these checks.
  Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, ValidityChecker validity,
         TerminationTest termination);

  /// Rolls out `plan` from (t0, start). `record_every` thins the recorded path (1 = every step).
  /// With recovery (the default), passing the truck hands the car to the recovery controller
  /// (ControlSchedule::recover) until it is stopped or stable with room to stop (an avoidance),
  /// leaves the road or reaches the scene's safe_state.horizon_s (not an avoidance).
  /// `actuators` carries on the actuators of a rollout that ended in `start` (a planner's tree node);
  /// by default they are at rest, with the wheels at start's angle (the hazard's first moment).
  [[nodiscard]] RolloutResult roll(const VehicleState& start, double t0_s, const std::vector<ControlSegment>& plan,
                                   const std::optional<Tail>& tail, int record_every = 5,
                                   const ActuatorState* actuators = nullptr) const;
  /// Without recovery, passing the truck ends a rollout (Termination::kPassed): for the
  /// no-action reference, which asks only whether the car would touch the truck.
  void set_recovery(bool on) noexcept { recovery_ = on; }

  [[nodiscard]] const Scene& scene() const noexcept { return scene_; }
  [[nodiscard]] const VehicleModel& model() const noexcept { return model_; }

 private:
  const Scene& scene_;
  const VehicleModel& model_;
  ControlLimits limits_;
  ValidityChecker validity_;
  TerminationTest termination_;
  Actuators actuators_;
  bool instant_actuation_;
  bool recovery_ = true;
};

/// Replays a maneuver from the cell's initial state at t = 0, recording every step: the executed
/// trajectory at the integration step.
[[nodiscard]] RolloutResult replay(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                                   const Maneuver& maneuver);

/// The car doing nothing from t = 0 (coasting straight, no recovery): its contact with the truck,
/// assessed by the same impact model as every strategy's, is the cell's unmitigated reference.
[[nodiscard]] RolloutResult no_action_rollout(const Scene& scene, const VehicleModel& model);

/// The least time to collision along a path: at each point, when ego and truck would first touch
/// if both kept their velocities (0 in contact); infinity if they never would within the horizon.
[[nodiscard]] double min_ttc_along(const Scene& scene, const std::vector<PathPoint>& path);

}  // namespace emrm::sim
