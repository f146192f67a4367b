#include <algorithm>
#include <chrono>
#include <vector>

#include "emrm/sim/planner.hpp"
#include "emrm/sim/swerve.hpp"

// The reference planner ("reference"): see planner.hpp.

namespace emrm::sim {

PlanResult plan_reference(const Scene& scene, const VehicleModel& model, const ControlLimits& limits) {
  const Roller roller(scene, model, limits);
  PlanResult result;
  const auto started = std::chrono::steady_clock::now();
  const VehicleState start = scene.ego_initial();
  const Tail stop = Tail::full_stop();

  auto consider = [&](RolloutResult r) {
    ++result.stats.rollouts;
    result.closest_miss_m = std::min(result.closest_miss_m, lateral_miss_m(scene, r));
    if (r.avoided()) {
      if (!result.avoidance) result.avoidance = std::move(r);
      return;
    }
    if (r.termination == Termination::kConstraint) return;
    if (!result.collision || less_loss(r.impact, result.collision->impact)) result.collision = std::move(r);
  };

  const double latency = scene.config().actuation.perception_latency_s;
  const std::vector<ControlSegment> wait =
      latency > 0.0 ? std::vector<ControlSegment>{hold(Control{}, latency)} : std::vector<ControlSegment>{};
  consider(roller.roll(start, 0.0, wait, stop, 5));

  // Swerve towards each side left free of the hazard (the T-junction's passage: right): steer in to a
  // peak, hold, counter-steer, then brake out.
  for (const Swerve& swerve : reference_swerves(scene, limits.allow_rear_lock))
    consider(roller.roll(start, 0.0, swerve_plan(scene, swerve), stop, 5));
  result.stats.nodes = result.stats.rollouts;
  result.stats.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

PlanResult ReferencePlanner::plan(const PlanningProblem& p) const { return plan_reference(p.scene, p.model, p.limits); }

}  // namespace emrm::sim
