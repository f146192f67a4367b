#include <algorithm>
#include <chrono>
#include <vector>

#include "emrm/sim/planner.hpp"

// The reference planner ("reference"): see planner.hpp.

namespace emrm::sim {

PlanResult plan_reference(const Scene& scene, const VehicleModel& model, const ControlLimits& limits) {
  const auto& cfg = scene.config();
  const auto& p = cfg.ego;
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

  const double latency = cfg.actuation.perception_latency_s;
  const std::vector<ControlSegment> wait =
      latency > 0.0 ? std::vector<ControlSegment>{hold(Control{}, latency)} : std::vector<ControlSegment>{};
  consider(roller.roll(start, 0.0, wait, stop, 5));

  // Swerve towards each side left free of the hazard (the T-junction's passage: right): steer in to a
  // peak, hold, counter-steer, then brake out.
  const FreeBands free = scene.free_bands(cfg.simulation.horizon_s);
  std::vector<double> sides;
  for (std::size_t i = 0; i < free.count; ++i) sides.push_back(free.band[i].right ? 1.0 : -1.0);
  const std::vector<double> peaks{0.1, 0.2, 0.3, 0.45, 0.6};
  const std::vector<double> holds{0.0, 0.2, 0.4, 0.7, 1.0};
  const std::vector<double> counters{0.0, 0.5, 1.0};
  const std::vector<double> counter_holds{0.3, 0.6};
  const std::vector<double> brakes{0.0, 0.3, 0.6};
  const std::vector<bool> locks = limits.allow_rear_lock ? std::vector<bool>{false, true} : std::vector<bool>{false};
  for (const double side : sides)
    for (double peak : peaks) {
      const double in_time = std::min(peak, p.max_steer_rad) / p.max_steer_rate_radps;
      for (double hold_s : holds)
        for (double counter : counters)
          for (double counter_hold : counter_holds)
            for (double brake : brakes)
              for (bool lock : locks) {
                std::vector<ControlSegment> plan = wait;
                Control u;
                u.brake = brake;
                u.steer_rate_radps = -side * p.max_steer_rate_radps;
                plan.push_back(hold(u, in_time));
                Control h = u;
                h.steer_rate_radps = 0.0;
                h.rear_lock = lock;
                plan.push_back(hold(h, hold_s));
                Control c = u;
                c.steer_rate_radps = side * p.max_steer_rate_radps;
                plan.push_back(hold(c, in_time * (1.0 + counter)));
                Control ch = c;
                ch.steer_rate_radps = 0.0;
                plan.push_back(hold(ch, counter_hold));
                Control straighten = ch;
                straighten.steer_rate_radps = -side * p.max_steer_rate_radps * counter;
                plan.push_back(hold(straighten, in_time * counter));
                consider(roller.roll(start, 0.0, plan, stop, 5));
              }
    }
  result.stats.nodes = result.stats.rollouts;
  result.stats.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

PlanResult ReferencePlanner::plan(const PlanningProblem& p) const { return plan_reference(p.scene, p.model, p.limits); }

}  // namespace emrm::sim
