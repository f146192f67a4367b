#pragma once

// One step of a rollout as its checks see it (rollout.hpp): how a rollout ends, what it records,
// the step handed to each check, the interface and ordered list of checks, and the chain of
// built-in and added checks that the validity checker (validity.hpp) and the termination test
// (termination.hpp) are.

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/controls.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// How a rollout ended.
enum class Termination {
  kContact,        ///< touched the truck
  kRoadDeparture,  ///< left the drivable area (assessed against the roadside)
  kConstraint,     ///< violated the strategy's constraint (dodge: rear axle sliding)
  kStopped,        ///< came to rest on the drivable area (or is certain to, braking straight short of the truck)
  /// Its rear is beyond the truck's far side. Ends a rollout only without recovery
  /// (Roller::set_recovery(false)); with it, passing hands over to the recovery phase.
  kPassed,
  kStabilised,  ///< passed the truck and reached a stable state with room to stop (a safe state)
  kHorizon,     ///< reached the horizon without a safe state: not an avoidance
  kOpen,        ///< the plan ran out with no tail: an unfinished tree edge
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

/// An axis-aligned extent in the road frame.
struct Extent {
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
};
/// Inline: the rollout loop takes two a step.
[[nodiscard]] inline Extent extent_of(const core::OrientedBox& box) noexcept {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Extent e{kInf, -kInf, kInf, -kInf};
  for (const auto& c : box.corners()) {
    e.min_x = std::min(e.min_x, c.x);
    e.max_x = std::max(e.max_x, c.x);
    e.min_y = std::min(e.min_y, c.y);
    e.max_y = std::max(e.max_y, c.y);
  }
  return e;
}

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
  ActorState truck;       ///< the truck at `t_s`
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

/// What the validity checker and the termination test have in common: their built-in checks, in
/// the order `Checker`'s constructor fixes, then the checks added with add(), in the order added;
/// the first that answers ends the rollout. `BuiltIn` holds the built-in checks and answers for
/// them all with `bool ends(Step&, RolloutResult&, Termination&) const`; it is complete only in
/// `Checker`'s own .cpp, which instantiates this template (src/sim/check_chain.hpp), so the
/// built-in checks are called directly there, with no virtual call per step (the rollout loop is
/// the simulator's hot path); only the added ones are virtual.
template <class Checker, class BuiltIn>
class CheckChain {
 public:
  /// Adds a check run after the built-in ones (and those added before it).
  Checker& add(std::unique_ptr<StepCheck> check) {
    added_.add(std::move(check));
    return static_cast<Checker&>(*this);
  }
  [[nodiscard]] std::optional<Termination> check(Step& step, RolloutResult& result) const;
  /// As check(), answering through `why` (what Roller calls each step).
  [[nodiscard]] bool ends(Step& step, RolloutResult& result, Termination& why) const;

 protected:
  explicit CheckChain(std::unique_ptr<const BuiltIn> built_in);
  ~CheckChain();
  CheckChain(CheckChain&&) noexcept;
  CheckChain& operator=(CheckChain&&) noexcept;

 private:
  std::unique_ptr<const BuiltIn> built_in_;
  CheckList added_;
};

}  // namespace emrm::sim
