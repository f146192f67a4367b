#pragma once

// Validity (rollout.hpp): the checks run after every step of a rollout, the first that objects
// ending it — the strategy's constraint, contact with the truck, leaving the drivable area — and
// the impact assessments of a contact and of a departure, which recorded trajectories share
// (exchange::assess).

#include <memory>
#include <optional>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/controls.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/step.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

namespace detail {
struct ValidityChecks;  ///< the built-in checks (validity.cpp)
}  // namespace detail

/// When a step is no longer valid. The built-in checks come first, in this order: the strategy's
/// constraint (when `limits` has one: no locked or sliding rear axle), contact with the hazard, then
/// with each other actor of the scene in its order, leaving the drivable area; then the checks added
/// with add() (CheckChain, step.hpp). Contact and departure are found between samples too
/// (conservative advancement inside the step, docs/physics.md "Continuous collision checking"),
/// timed by bisection, and assessed: an actor by the impact model, the roadside by the scene's
/// roadside model. Borrows the scene and the model.
class ValidityChecker : public CheckChain<ValidityChecker, detail::ValidityChecks> {
 public:
  ValidityChecker(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);
};
extern template class CheckChain<ValidityChecker, detail::ValidityChecks>;

/// The impact of the ego at state `s` on an actor of `body` at `actor`, as a rollout's contact check
/// assesses it when the two first touch: the contact test (nudging the ego on by up to 1 cm along the
/// closing motion when the boxes only touch), then assess_impact with the actor's mass and inertia.
/// The contact found goes to `contact_out` when given. Used by recorded trajectories too
/// (exchange::assess).
[[nodiscard]] ImpactAssessment actor_impact(const Scene& scene, const ActorBody& body, const VehicleState& s,
                                            const ActorState& actor, core::Contact* contact_out = nullptr) noexcept;
/// A touch still to come on the ego standing at `s` from `t_s` on: an actor that moves on (a car still
/// drifting across, a pedestrian walking on) and meets the car at rest (docs/physics.md, "Safe
/// state"). Found by conservative advancement of each actor's closed-form motion until it rests or
/// has moved past the car along its direction for good, timed by bisection; the earliest touch, or
/// nothing. A rollout that comes to rest ends in that contact rather than stopped; recorded
/// trajectories share it (exchange::assess).
struct TouchAtRest {
  std::size_t actor = 0;  ///< its index in Scene::actors()
  double t_s = 0.0;
};
[[nodiscard]] std::optional<TouchAtRest> touch_at_rest(const Scene& scene, const VehicleState& s, double t_s) noexcept;

/// The ego leaving the drivable area at state `s`, assessed against the scene's roadside: a barrier
/// is an immovable body met by the corner nearest the edge (written to `point_out` when given);
/// open ground scores L4 with no impact.
[[nodiscard]] ImpactAssessment roadside_impact(const Scene& scene, const VehicleState& s,
                                               core::Vec2* point_out = nullptr) noexcept;

}  // namespace emrm::sim
