#include "emrm/sim/swerve.hpp"

#include <algorithm>

namespace emrm::sim {

std::vector<ControlSegment> swerve_plan(const Scene& scene, const Swerve& swerve) {
  const auto& cfg = scene.config();
  const auto& p = cfg.ego;
  std::vector<ControlSegment> plan;
  const double latency = cfg.actuation.perception_latency_s;
  if (latency > 0.0) plan.push_back(hold(Control{}, latency));
  const double side = swerve.side;
  const double in_time = std::min(swerve.peak_rad, p.max_steer_rad) / p.max_steer_rate_radps;
  Control in;
  in.brake = swerve.brake;
  in.steer_rate_radps = -side * p.max_steer_rate_radps;
  in.rear_lock = swerve.lock_in;
  plan.push_back(hold(in, in_time));
  Control held = in;
  held.steer_rate_radps = 0.0;
  held.brake = swerve.brake_hold;
  held.rear_lock = swerve.rear_lock;
  plan.push_back(hold(held, swerve.hold_s));
  Control counter = in;
  counter.rear_lock = false;
  counter.brake = swerve.brake_out;
  counter.steer_rate_radps = side * p.max_steer_rate_radps;
  plan.push_back(hold(counter, in_time * (1.0 + swerve.counter)));
  Control counter_held = counter;
  counter_held.steer_rate_radps = 0.0;
  plan.push_back(hold(counter_held, swerve.counter_hold_s));
  Control straighten = counter_held;
  straighten.steer_rate_radps = -side * p.max_steer_rate_radps * swerve.counter;
  plan.push_back(hold(straighten, in_time * swerve.counter));
  return plan;
}

std::vector<double> free_sides(const Scene& scene) {
  const FreeBands free = scene.free_bands(scene.config().simulation.horizon_s);
  std::vector<double> sides;
  for (std::size_t i = 0; i < free.count; ++i) sides.push_back(free.band[i].right ? 1.0 : -1.0);
  return sides;
}

std::vector<Swerve> reference_swerves(const Scene& scene, bool allow_rear_lock) {
  const std::vector<double> peaks{0.1, 0.2, 0.3, 0.45, 0.6};
  const std::vector<double> holds{0.0, 0.2, 0.4, 0.7, 1.0};
  const std::vector<double> counters{0.0, 0.5, 1.0};
  const std::vector<double> counter_holds{0.3, 0.6};
  const std::vector<double> brakes{0.0, 0.3, 0.6};
  const std::vector<bool> locks = allow_rear_lock ? std::vector<bool>{false, true} : std::vector<bool>{false};
  std::vector<Swerve> family;
  for (const double side : free_sides(scene))
    for (const double peak : peaks)
      for (const double hold_s : holds)
        for (const double counter : counters)
          for (const double counter_hold : counter_holds)
            for (const double brake : brakes)
              for (const bool lock : locks)
                family.push_back({side, peak, hold_s, counter, counter_hold, brake, brake, brake, lock});
  return family;
}

std::vector<Swerve> falsifier_swerves(const Scene& scene, bool allow_rear_lock) {
  std::vector<Swerve> family = reference_swerves(scene, allow_rear_lock);
  if (!allow_rear_lock) return family;
  for (const double side : free_sides(scene))
    for (const double peak : {0.1, 0.2, 0.3, 0.45, 0.6})
      for (const double hold_s : {0.0, 0.2, 0.4})
        for (const double counter : {0.0, 0.5, 1.0})
          for (const bool lock : {false, true})
            family.push_back({side, peak, hold_s, counter, 0.3, 1.0, 1.0, 1.0, lock, true});
  return family;
}

}  // namespace emrm::sim
