#pragma once

// Rollouts: the vehicle driven under a control schedule until something ends the run. A rollout
// is three parts, in the manner of OMPL's StatePropagator / StateValidityChecker / Goal:
// - propagation: the ControlSchedule says which control applies at each step (a plan of held or
//   pursuit segments, then a tail), and the vehicle model integrates it;
// - validity: a ValidityChecker runs its StepChecks after every step (by default the strategy's
//   constraint, contact with the truck, leaving the drivable area); the first that objects ends the
//   rollout;
// - termination: a TerminationTest runs its StepChecks on every valid step (by default: passed the
//   truck, stopped, certain to stop short, horizon).
// New constraints or goals are new StepChecks handed to the Roller, not edits to its loop.

#include <memory>
#include <optional>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// What a strategy allows the planner to command.
struct ControlLimits {
  bool allow_rear_lock = false;      ///< the rear wheels may be locked (a handbrake drift)
  bool forbid_rear_sliding = false;  ///< the rear axle must never slide sideways (dodge)
  bool accept_contact = false;       ///< a collision is an admissible end (drift to accident)
};

/// How a rollout ended.
enum class Termination {
  kContact,        ///< touched the truck
  kRoadDeparture,  ///< left the drivable area (assessed against the roadside)
  kConstraint,     ///< violated the strategy's constraint (dodge: rear axle sliding)
  kStopped,        ///< came to rest on the drivable area (or is certain to, braking straight short of the truck)
  /// Its rear is beyond the truck's far side. Ends a rollout only without recovery
  /// (Roller::set_recovery(false)); with it, passing hands over to the recovery phase.
  kPassed,
  kStabilised,     ///< passed the truck and reached a stable state with room to stop (a safe state)
  kHorizon,        ///< reached the horizon without a safe state: not an avoidance
  kOpen,           ///< the plan ran out with no tail: an unfinished tree edge
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

/// One sampled point of a path: time, state and the control being commanded (what the actuators
/// make of it is in the state: the wheel angle).
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
  /// On contact, the impact with the truck; on a road departure, the impact with the roadside
  /// (its impact_speed_mps is the speed at which the car left the road).
  ImpactAssessment impact;
  /// The controls that drove it: those handed to Roller::roll, and with planners that compose
  /// rollouts, the whole chain from t = 0.
  Maneuver maneuver;
  bool passed_truck = false;  ///< it got past the truck (an avoidance, or a recovery that failed)
  /// The actuators at the end: where a rollout that continues this one starts from.
  ActuatorState end_actuators;
  /// avoided: no contact, no departure, no violated constraint, and a safe state reached (stopped,
  /// or stable with room to stop; without recovery, passing the truck is enough).
  [[nodiscard]] bool avoided() const {
    return termination == Termination::kStopped || termination == Termination::kStabilised ||
           termination == Termination::kPassed;
  }
};

/// Propagation's input: which control applies at each step. Borrows the plan and tail, which
/// must outlive it.
class ControlSchedule {
 public:
  ControlSchedule(const std::vector<ControlSegment>& plan, const std::optional<Tail>& tail,
                  const VehicleParams& params, const ControlLimits& limits, double mu, double dt_s);
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

/// An axis-aligned extent in the road frame.
struct Extent {
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
};
[[nodiscard]] Extent extent_of(const core::OrientedBox& box) noexcept;

/// One integration step as the checks see it. A check that ends the rollout may move `state` and
/// `t_s` (back to the moment of contact, or on to a closed-form stop) and add to the result.
struct Step {
  VehicleState before;  ///< the state at the start of the step
  VehicleState state;   ///< the state at its end
  double t_s = 0.0;     ///< the time of `state`
  double dt_s = 0.0;    ///< the step's length
  Control control;      ///< commanded during the step
  /// What the actuators made of it: the control the vehicle model integrated over the step (the
  /// command itself with instant actuation). Checks that re-integrate part of the step use this.
  Control applied;
  double steer_command_rad = 0.0;  ///< the commanded wheel angle at the step's end
  /// The brake stays at its full demand from here (pressure built, every command in flight asks for it).
  bool full_brake_held = false;
  core::OrientedBox ego;  ///< the ego's footprint at `state`
  TruckState truck;       ///< the truck at `t_s`
  /// Extents of `ego` and of the truck's box, filled once the step is valid (for the termination
  /// test; validity checks must not read them).
  Extent ego_extent, truck_extent;
  /// In the recovery phase (after passing the truck) until `recovery_until_s`.
  bool recovering = false;
  double recovery_until_s = 0.0;
};

/// One test applied after every step (a state validity check or a termination test).
class StepCheck {
 public:
  virtual ~StepCheck() = default;
  /// How this step ends the rollout, or nothing. May refine `step` and fill `result` (its path
  /// and impact); must be pure otherwise (checks are shared between threads).
  [[nodiscard]] virtual std::optional<Termination> check(Step& step, RolloutResult& result) const = 0;
};

/// An ordered list of checks; the first that answers ends the rollout. Owns its checks.
class CheckList {
 public:
  CheckList() = default;
  CheckList& add(std::unique_ptr<StepCheck> check);
  [[nodiscard]] std::optional<Termination> check(Step& step, RolloutResult& result) const;
  /// As check(), answering through `why`: whether the step ends the rollout.
  [[nodiscard]] bool ends(Step& step, RolloutResult& result, Termination& why) const;
  [[nodiscard]] bool empty() const noexcept { return checks_.empty(); }

 private:
  std::vector<std::unique_ptr<StepCheck>> checks_;
};

/// When a step is no longer valid. The built-in checks come first, in this order: the strategy's
/// constraint (when `limits` has one: no locked or sliding rear axle), contact with the truck,
/// leaving the drivable area; then the checks added with add(). Contact and departure are found
/// between samples too (conservative advancement inside the step, docs/physics.md "Continuous
/// collision checking"), timed by bisection, and assessed: the truck by the impact model, the
/// roadside by the scene's roadside model. The built-in ones are called directly (no virtual call per step: the
/// rollout loop is the simulator's hot path). Borrows the scene and the model.
class ValidityChecker {
 public:
  ValidityChecker(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);
  ~ValidityChecker();
  ValidityChecker(ValidityChecker&&) noexcept;
  ValidityChecker& operator=(ValidityChecker&&) noexcept;
  /// Adds a check run after the built-in ones.
  ValidityChecker& add(std::unique_ptr<StepCheck> check);
  [[nodiscard]] std::optional<Termination> check(Step& step, RolloutResult& result) const;
  /// As check(), answering through `why` (what Roller calls each step).
  [[nodiscard]] bool ends(Step& step, RolloutResult& result, Termination& why) const;

 private:
  struct BuiltIn;
  std::unique_ptr<const BuiltIn> built_in_;
  CheckList added_;
};

/// When a valid rollout is over. Built in, in this order: passed the truck, stopped, braking
/// straight at the limit with room to stop (finished in closed form), the horizon; in the
/// recovery phase: stopped, stabilised with room to stop, the recovery horizon; then the checks
/// added with add().
class TerminationTest {
 public:
  explicit TerminationTest(const Scene& scene);
  ~TerminationTest();
  TerminationTest(TerminationTest&&) noexcept;
  TerminationTest& operator=(TerminationTest&&) noexcept;
  /// Adds a test run after the built-in ones.
  TerminationTest& add(std::unique_ptr<StepCheck> check);
  [[nodiscard]] std::optional<Termination> check(Step& step, RolloutResult& result) const;
  /// As check(), answering through `why` (what Roller calls each step).
  [[nodiscard]] bool ends(Step& step, RolloutResult& result, Termination& why) const;

 private:
  struct BuiltIn;
  std::unique_ptr<const BuiltIn> built_in_;
  CheckList added_;
};

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

/// The impact of the ego at state `s` on the truck, as a rollout's contact check assesses it when
/// the two first touch: the contact test (nudging the ego on by up to 1 cm along the closing motion
/// when the boxes only touch), then assess_impact with the truck's mass and inertia. The contact
/// found goes to `contact_out` when given. Used by recorded trajectories too (exchange::assess).
[[nodiscard]] ImpactAssessment truck_impact(const Scene& scene, const VehicleState& s, const TruckState& truck,
                                            core::Contact* contact_out = nullptr) noexcept;
/// The ego leaving the drivable area at state `s`, assessed against the scene's roadside: a barrier
/// is an immovable body met by the corner nearest the edge (written to `point_out` when given);
/// open ground scores L4 with no impact.
[[nodiscard]] ImpactAssessment roadside_impact(const Scene& scene, const VehicleState& s,
                                               core::Vec2* point_out = nullptr) noexcept;
/// The safe state after passing the truck (docs/physics.md, "Safe state"): yaw rate, body slip,
/// heading and wheel angle within the scene's safe_state bounds, and a straight stop from here
/// (through the brakes' dead time and ramp) ends on the drivable area.
[[nodiscard]] bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s) noexcept;
/// The same with the ego's box at `s` already computed (the rollout's hot path has it).
[[nodiscard]] bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s,
                                            const core::OrientedBox& ego_box) noexcept;

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
