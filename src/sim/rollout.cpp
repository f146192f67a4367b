#include "emrm/sim/rollout.hpp"

#include <algorithm>
#include <cmath>

#include "check_support.hpp"
#include "emrm/core/trig.hpp"

namespace emrm::sim {

Roller::Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits)
    : Roller(scene, model, limits, ValidityChecker(scene, model, limits), TerminationTest(scene)) {}

Roller::Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, ValidityChecker validity,
               TerminationTest termination)
    : scene_(scene),
      model_(model),
      limits_(limits),
      validity_(std::move(validity)),
      termination_(std::move(termination)),
      actuators_(scene.config().actuation, model.params(), scene.friction(), scene.config().simulation.dt_s),
      instant_actuation_(scene.config().actuation.instant()) {}

[[gnu::flatten]] RolloutResult Roller::roll(const VehicleState& start, double t0_s,
                                            const std::vector<ControlSegment>& plan, const std::optional<Tail>& tail,
                                            int record_every, const ActuatorState* actuators) const {
  const double dt = scene_.config().simulation.dt_s;
  const double mu = scene_.friction();
  ControlSchedule schedule(plan, tail, model_.params(), limits_, mu, dt);

  RolloutResult r;
  r.maneuver.plan = plan;
  r.maneuver.tail = tail;
  Step step;
  step.state = start;
  step.t_s = t0_s;
  step.dt_s = dt;
  ActuatorState act = actuators != nullptr ? *actuators : Actuators::at_rest(start);
  auto finish = [&](Termination why) {
    r.termination = why;
    r.end_actuators = std::move(act);
    r.passed_truck = step.recovering || why == Termination::kPassed;
    r.end_time_s = step.t_s;
    r.end_state = step.state;
    if (r.path.back().t_s != step.t_s) r.path.push_back({step.t_s, step.state, step.control});
    return std::move(r);
  };

  for (int n = 0;; ++n) {
    // Controllers steer the commanded angle: they see it, not the lagging wheels.
    std::optional<Control> u;
    if (instant_actuation_) {
      u = schedule.control_at(step.state);
    } else {
      VehicleState seen = step.state;
      seen.steer_rad = act.steer_command_rad;
      u = schedule.control_at(seen);
    }
    if (!u) {
      step.control = Control{};
      if (r.path.empty()) r.path.push_back({step.t_s, step.state, step.control});
      return finish(Termination::kOpen);
    }
    step.control = *u;
    if (n == 0) r.path.push_back({step.t_s, step.state, step.control});  // the start, with its control

    step.before = step.state;
    if (instant_actuation_) {
      step.applied = step.control;
      step.full_brake_held = step.control.brake >= 0.999;
    } else {
      step.applied = actuators_.apply(act, step.state, step.control, step.t_s);
      step.full_brake_held = actuators_.full_brake_held(act, step.control);
    }
    step.state = model_.step(step.state, step.applied, mu, dt);
    if (instant_actuation_) act.steer_command_rad = step.state.steer_rad;  // the wheels are the command
    step.steer_command_rad = act.steer_command_rad;
    step.t_s += dt;
    schedule.advance();
    step.ego = scene_.ego_box(step.state);
    step.truck = scene_.hazard_at(step.t_s);

    Termination why{};
    if (validity_.ends(step, r, why)) return finish(why);
    step.ego_extent = extent_of(step.ego);
    step.truck_extent = extent_of(step.truck.box);
    if ((n + 1) % record_every == 0) r.path.push_back({step.t_s, step.state, step.control});
    if (termination_.ends(step, r, why)) {
      if (why != Termination::kPassed || !recovery_) return finish(why);
      // Passed: not yet an avoidance. The recovery controller takes over until a safe state.
      const Road& road = scene_.road();
      const double margin = 0.5 * scene_.config().ego.width_m + 0.3;
      const double low = road.min_y_m + margin;
      const double high = std::max(low, road.max_y_m - margin);
      step.recovering = true;
      step.recovery_until_s = step.t_s + scene_.config().safe_state.horizon_s;
      schedule.recover(std::clamp(step.state.y_m, low, high));
    }
  }
}

RolloutResult replay(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                     const Maneuver& maneuver) {
  return Roller(scene, model, limits).roll(scene.ego_initial(), 0.0, maneuver.plan, maneuver.tail, 1);
}

RolloutResult no_action_rollout(const Scene& scene, const VehicleModel& model) {
  Roller coast(scene, model, ControlLimits{});
  coast.set_recovery(false);
  return coast.roll(scene.ego_initial(), 0.0, {}, Tail{}, 10);
}

double min_ttc_along(const Scene& scene, const std::vector<PathPoint>& path) {
  double best = detail::kInfinity;
  const double horizon = scene.config().simulation.horizon_s;
  for (const auto& p : path) {
    const ActorState truck = scene.hazard_at(p.t_s);
    if (const auto ttc = core::time_to_overlap(scene.ego_box(p.state), detail::world_velocity(p.state), truck.box,
                                               truck.velocity_mps, horizon))
      best = std::min(best, *ttc);
  }
  return best;
}

}  // namespace emrm::sim
