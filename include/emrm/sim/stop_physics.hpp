#pragma once

// What physics says of a cell without simulating it — the facts the sweep, the adaptive search,
// aggregation, boundaries, calibration and `emrm verify` share, each written once: the analytic stop
// boundary through the scene's actuators, and what the no-action rollout tells (whether the truck is
// in the car's way for certain, whether passing in front of it can help, whether there is anything
// to mitigate). Pure functions of the scene and the cell.

#include "emrm/sim/actuation.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {

/// Whether the analytic stop boundary below holds for the scene's family
/// (ScenarioFamilyInfo::stop_boundary: its hazard stands v·TTC ahead and never comes closer). Where it
/// does not, stop_call knows nothing and the boundary's checks, lines and tables are left out.
[[nodiscard]] bool stop_boundary_applies(const SceneConfig& scene);

/// How far the simulated emergency stop may end from the analytic one: it matches within 0.03 m
/// (docs/adaptive.md), so a cell whose stop margin is larger than this is settled without simulating.
inline constexpr double kStopAgreement_m = 0.1;

/// The TTC at which full braking through `actuation` stops exactly at the truck's near side:
/// actuation.stopping_distance_m(v, μ, with perception) / v. Without dead time, ramp or cap it is
/// L + v/(2μg).
[[nodiscard]] double stop_boundary_ttc_s(double speed_kph, double mu, const ActuationConfig& actuation) noexcept;

/// What braking straight through `actuation` leaves before the truck's near side: v·TTC minus the
/// stopping distance (perception included); negative when the car does not stop in time.
[[nodiscard]] double stop_margin_m(double speed_kph, double ttc_s, double mu,
                                   const ActuationConfig& actuation) noexcept;

/// The analytic stop boundary as a claim about a grid's cell: v·TTC at least the stopping distance
/// through `actuation` (perception latency, brake dead time, ramp, cap). A TTC within 1e-9 s of the
/// boundary counts as on it (grid values such as 0.25 + 7·0.06 are not exact in binary).
[[nodiscard]] bool analytically_stoppable(double speed_kph, double ttc_s, double mu,
                                          const ActuationConfig& actuation) noexcept;
/// The same for a cell: its ego speed, TTC and friction (CellInput's method factors).
[[nodiscard]] bool analytically_stoppable(const CellInput& cell, const ActuationConfig& actuation) noexcept;

/// Whether the hazard stands in the car's straight path from t = TTC (the earliest the car, braking
/// straight, can reach it) until it comes to rest: then braking short of the stop boundary cannot
/// avoid it. False for a hazard that keeps going, drifts sideways, or leaves the car's lane free (the
/// highway's truck on the shoulder alone): a G cell below the boundary is then no contradiction.
[[nodiscard]] bool hazard_in_the_way(const SceneConfig& scene, const CellInput& cell);

/// What physics says of a cell's emergency stop without simulating it: braking alone stops before
/// the truck with a margin (so the cell is G); it cannot avoid (it does not stop in time and the
/// truck stands in its way throughout); or only a simulation can tell (near the boundary, or a truck
/// that may not have reached the car's lane yet when the car gets there).
enum class StopCall { kStops, kCannotStop, kUnknown };

/// The physics of the shipped emergency stop (straight braking through the scene's actuators), for
/// a family where the stop boundary applies (kUnknown elsewhere):
/// kStops when v·TTC exceeds the stopping distance by more than kStopAgreement_m; kCannotStop when
/// it falls short by more than that and the truck stands in the car's lane from t = TTC (the
/// earliest the braking car can reach it) until it comes to rest, so that braking can neither stop
/// short of it nor pass in front of it before it arrives; kUnknown otherwise.
[[nodiscard]] StopCall stop_call(const SceneConfig& scene, const CellInput& cell);

/// Whether arriving sooner can help at this cell: the truck moves, so the gap it leaves narrows over
/// time and the car may pass in front of it first; unless the car reaches the truck before any of
/// its actuators can act (TTC within the perception latency and the quicker dead time) while the
/// truck stands in its way, or, doing nothing, touches it a step before the first actuator acts
/// (every strategy drives it the same until then): then nothing avoids it.
[[nodiscard]] bool may_pass_early(const SceneConfig& scene, const CellInput& cell);

/// Whether the car doing nothing hits the truck at the lowest loss level a contact can have
/// (P(MAIS3+) and P(fatal) below their levels: L4): then a strategy that does not avoid the truck
/// cannot be graded lower either. Not a proof that an unavoidable cell is R: a strategy that fails
/// to avoid without a crash graded L4 (a contact without closing speed, or no safe state reached
/// within the horizon) grades 0 and makes such a cell O.
[[nodiscard]] bool nothing_to_mitigate(const SceneConfig& scene, const CellInput& cell);

}  // namespace emrm::sim
