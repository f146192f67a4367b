#pragma once

// The falsifier: a trajectory optimisation that looks for the avoidance a search missed
// (docs/planner.md, "The falsifier"). It rolls out the reference planner's grid of the swerve family
// (swerve.hpp) and a drift family (braking pursuits into a free passage with the rear locked) and
// optimises continuously from the nearest misses: over the swerve family's parameters (peak, hold,
// counter-steer, its hold, the brake levels in, held and out), and over the numbers of given
// maneuvers and of the drifts (the searches' least-loss failures, a neighbour's witness: each
// segment's duration, brake, steering rate or pursuit target and grip), with NLopt's Subplex on a
// score that falls as a rollout comes nearer an avoidance. Deterministic: no random choice.

#include <vector>

#include "emrm/sim/planner.hpp"

namespace emrm::sim {

/// How close a rollout came to an avoidance, lower is nearer: −1 for an avoidance; in (−1, 0] for a
/// rollout that got past the hazard and then failed to reach a safe state (the slower it left the
/// road, the nearer); for a contact, the lesser of how far the ego reached across the hazard's edge
/// (lateral_miss_m) and how much further it would have needed to stop (v²/(2μg) at the contact);
/// above that, a departure before the hazard and a violated constraint.
[[nodiscard]] double falsifier_score(const Scene& scene, const RolloutResult& rollout) noexcept;

/// The falsifier: its grid (the reference planner's, and handbrake kicks where the rear may lock),
/// then local optimisations, until an avoidance: from the given maneuvers (`hints`, any strategy's,
/// replayed under `limits`), the nearest three first, then from the drift family's three nearest
/// misses, then from the grid's four, each of `planner.falsifier_evaluations` rollouts. Its avoidance, if any, is an
/// ordinary rollout from t = 0 (a witness). Its `closest_miss_m` is the least falsifier_score of its failures, at least
/// 0: how far the nearest came from getting across the hazard's edge or from stopping short of it.
[[nodiscard]] PlanResult falsify(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                                 const std::vector<Maneuver>& hints = {});

/// The falsifier as a planner, without hints (ignores the seed and keep_tree).
class FalsifierPlanner final : public Planner {
 public:
  [[nodiscard]] std::string_view name() const override { return "falsifier"; }
  [[nodiscard]] PlanResult plan(const PlanningProblem& problem) const override;
};

}  // namespace emrm::sim
