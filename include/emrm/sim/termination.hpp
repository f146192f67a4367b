#pragma once

// Termination (rollout.hpp): when a valid rollout is over — passed the truck, stopped, certain to
// stop short, the horizon, and after the truck the safe state (stable with room to stop).

#include <memory>
#include <optional>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/step.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// Below this speed a car is at rest: a rollout ends as stopped (Termination::kStopped). The
/// unavoidability certificate and the export and judging of trajectories use the same speed.
inline constexpr double kStoppedSpeed_mps = 0.05;

namespace detail {
struct TerminationTests;  ///< the built-in tests (termination.cpp)
}  // namespace detail

/// When a valid rollout is over. Built in, in this order: passed the truck, stopped, braking
/// straight at the limit with room to stop (finished in closed form), the horizon; in the
/// recovery phase: stopped, stabilised with room to stop, the recovery horizon; then the checks
/// added with add() (CheckChain, step.hpp).
class TerminationTest : public CheckChain<TerminationTest, detail::TerminationTests> {
 public:
  explicit TerminationTest(const Scene& scene);
};
extern template class CheckChain<TerminationTest, detail::TerminationTests>;

/// The safe state after passing the truck (docs/physics.md, "Safe state"): yaw rate, body slip,
/// heading and wheel angle within the scene's safe_state bounds, and a straight stop from here
/// (through the brakes' dead time and ramp) ends on the drivable area.
[[nodiscard]] bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s) noexcept;
/// The same with the ego's box at `s` already computed (the rollout's hot path has it).
[[nodiscard]] bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s,
                                            const core::OrientedBox& ego_box) noexcept;

/// The path with its closed-form final stop filled in: a rollout braking straight short of the
/// hazard ends in one step to where it comes to rest (the "stops short" test above); the braking in
/// between is added at steps of `dt_s` at the constant deceleration that step implies, the motion
/// the closed form stands for, so that every trajectory shown or exported holds every integration
/// step. Other paths (and paths already filled in) are returned unchanged.
[[nodiscard]] std::vector<PathPoint> with_closed_form_stop(const std::vector<PathPoint>& path, double dt_s);

}  // namespace emrm::sim
