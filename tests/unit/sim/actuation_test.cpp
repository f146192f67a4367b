// Actuators (docs/actuation.md): the emergency stop against the closed form of a delayed, ramped,
// capped stop; the wheel angle against the lag's analytic response; the lateral offset of a step
// steer against an independent linear single-track model; planners' maneuvers replaying under
// actuators; the bounds of the certificates under actuators.

#include "emrm/sim/actuation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "emrm/sim/certificate.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "tjunction.hpp"

namespace emrm::sim {
namespace actuation_test {

// The emergency stop as the strategy runs it: nothing during the perception latency, then full
// braking with the wheels held straight.
RolloutResult emergency_stop(const SceneConfig& config, const TJunctionCell& cell) {
  const Scene scene(config, cell);
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const double latency = config.actuation.perception_latency_s;
  std::vector<ControlSegment> wait;
  if (latency > 0.0) wait.push_back(hold(Control{}, latency));
  return Roller(scene, *model, ControlLimits{}).roll(scene.ego_initial(), 0.0, wait, Tail::full_stop(), 1);
}

TEST(Actuation, StoppingDistanceIsTheClosedFormOfADelayedRampedStop) {
  ActuationConfig a;
  a.perception_latency_s = 0.2;
  a.brake_dead_time_s = 0.1;
  a.brake_ramp_s = 0.4;
  const double g = kGravity_mps2;
  // v > a t_r / 2: dead time at full speed, the ramp's v t_r − a t_r²/6, the rest at full decel.
  const double v = 20.0;
  const double ramp_end_speed = v - g * 0.4 / 2.0;
  const double expected = v * 0.3 + (v * 0.4 - g * 0.16 / 6.0) + ramp_end_speed * ramp_end_speed / (2.0 * g);
  EXPECT_NEAR(a.stopping_distance_m(v, 1.0, true), expected, 1e-9);
  EXPECT_NEAR(a.stopping_distance_m(v, 1.0, false), expected - v * 0.2, 1e-9);
  // Slow enough to stop within the ramp: v = a t²/(2 t_r).
  const double slow = 1.0;
  const double t = std::sqrt(2.0 * slow * 0.4 / g);
  EXPECT_NEAR(a.stopping_distance_m(slow, 1.0, false), slow * 0.1 + slow * t - g * t * t * t / (6.0 * 0.4), 1e-12);
  EXPECT_NEAR(a.stopping_time_s(slow, 1.0, false), 0.1 + t, 1e-12);
  // The cap replaces mu g when it is lower, and only then.
  a.max_decel_mps2 = 6.0;
  EXPECT_DOUBLE_EQ(a.full_decel_mps2(1.0), 6.0);
  EXPECT_DOUBLE_EQ(a.full_decel_mps2(0.5), 0.5 * g);
}

TEST(Actuation, EmergencyStopAvoidsExactlyWhenTheClosedFormSaysSoToOneStep) {
  // v·TTC ≥ v·τ + v·t_r/2 + v²/(2a) − a·t_r²/24, τ = perception latency + brake dead time, over
  // random speeds, frictions, latencies, ramps and caps; one cell a little (1.5 steps) on each side.
  std::mt19937_64 rng(20261124);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SceneConfig config;
  config.truck.speed_kph = 0.0;  // the truck stands across the lane
  config.max_initial_distance_m = 200.0;
  config.simulation.horizon_s = 12.0;
  const double dt = config.simulation.dt_s;
  int checked = 0;
  for (int i = 0; i < 40; ++i) {
    ActuationConfig& a = config.actuation;
    a.perception_latency_s = std::round(unit(rng) * 40.0) * dt;  // the plan's hold ends on a step
    a.brake_dead_time_s = unit(rng) * 0.3;
    a.brake_ramp_s = unit(rng) * 0.6;
    a.max_decel_mps2 = unit(rng) < 0.5 ? 4.0 + 5.0 * unit(rng) : 0.0;
    const double v = 5.0 + 25.0 * unit(rng);
    const double mu = 0.3 + 0.8 * unit(rng);
    const double boundary_s = a.stopping_distance_m(v, mu, true) / v;
    for (const double side : {-1.0, 1.0}) {
      const TJunctionCell cell{v * 3.6, boundary_s + side * 1.5 * dt, mu, 3.0, 0.0};
      const RolloutResult r = emergency_stop(config, cell);
      EXPECT_EQ(r.avoided(), side > 0.0) << "v " << v << " mu " << mu << " latency " << a.perception_latency_s
                                         << " dead " << a.brake_dead_time_s << " ramp " << a.brake_ramp_s << " cap "
                                         << a.max_decel_mps2 << " TTC " << cell.ttc_s;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 80);
}

TEST(Actuation, DecelerationRisesAlongTheRampAfterTheDeadTimes) {
  SceneConfig config;
  config.truck.speed_kph = 0.0;
  config.max_initial_distance_m = 200.0;
  config.actuation.perception_latency_s = 0.2;
  config.actuation.brake_dead_time_s = 0.15;
  config.actuation.brake_ramp_s = 0.5;
  config.actuation.max_decel_mps2 = 8.0;
  const double v = 25.0;
  const RolloutResult r = emergency_stop(config, {v * 3.6, 6.0, 1.0, 3.0, 0.0});
  const auto speed_at = [&](double t) {
    for (const auto& p : r.path)
      if (p.t_s >= t - 1e-9) return p.state.speed_mps();
    return 0.0;
  };
  EXPECT_NEAR(speed_at(0.35), v, 1e-6);                          // nothing before both dead times
  EXPECT_NEAR(speed_at(0.35 + 0.5), v - 8.0 * 0.5 / 2.0, 0.02);  // the ramp's mean: half the cap
  // Then the cap, not mu g, to the stop: when and where the closed form says.
  const double dt = config.simulation.dt_s;
  EXPECT_EQ(r.termination, Termination::kStopped);
  EXPECT_NEAR(r.end_time_s, config.actuation.stopping_time_s(v, 1.0, true), dt);
  EXPECT_NEAR(r.end_state.x_m - r.path.front().state.x_m, config.actuation.stopping_distance_m(v, 1.0, true), v * dt);
}

// The lag's response to the commanded angle ramping at `rate` to `peak` from time zero.
double lagged_ramp(double t, double rate, double peak, double tc) {
  if (t <= 0.0) return 0.0;
  const double t1 = peak / rate;
  const auto ramp = [&](double s) { return tc > 0.0 ? rate * (s - tc * (1.0 - std::exp(-s / tc))) : rate * s; };
  if (t <= t1) return ramp(t);
  return peak + (ramp(t1) - peak) * (tc > 0.0 ? std::exp(-(t - t1) / tc) : 0.0);
}

struct SteerRun {
  RolloutResult run;
  SceneConfig config;
};

// A step steer to `peak` at the full steering rate from the end of the perception latency.
SteerRun step_steer(ActuationConfig actuation, double peak, double speed_mps) {
  SteerRun out;
  out.config.actuation = actuation;
  out.config.max_initial_distance_m = 400.0;
  out.config.simulation.horizon_s = 3.0;
  out.config.road.shoulder_m = 50.0;  // room to the side: this is about the response, not the road
  out.config.road.lanes = 20;
  const Scene scene(out.config, {speed_mps * 3.6, 10.0, 1.0, 3.0, 0.0});
  const auto model = make_vehicle_model("single_track_fiala", out.config.ego);
  const double rate = out.config.ego.max_steer_rate_radps;
  std::vector<ControlSegment> plan;
  if (actuation.perception_latency_s > 0.0) plan.push_back(hold(Control{}, actuation.perception_latency_s));
  plan.push_back(hold(Control{rate, 0.0, false}, peak / rate));
  plan.push_back(hold(Control{}, 3.0));
  out.run = Roller(scene, *model, ControlLimits{}).roll(scene.ego_initial(), 0.0, plan, std::nullopt, 1);
  return out;
}

TEST(Actuation, WheelAngleFollowsTheDeadTimeThenTheFirstOrderLag) {
  for (const double tc : {0.0, 0.08, 0.2}) {
    ActuationConfig a;
    a.perception_latency_s = 0.1;
    a.steer_dead_time_s = 0.07;  // not a whole number of steps: the delay falls inside a step
    a.steer_time_constant_s = tc;
    a.brake_ramp_s = 0.2;       // not instant even at tc = 0
    const double peak = 0.048;  // six steps at the full rate: the command holds a whole number of steps
    const SteerRun s = step_steer(a, peak, 20.0);
    const double rate = s.config.ego.max_steer_rate_radps;
    int compared = 0;
    for (const auto& p : s.run.path) {
      if (p.t_s > 1.5) break;
      EXPECT_NEAR(p.state.steer_rad, lagged_ramp(p.t_s - 0.1 - 0.07, rate, peak, tc), 1e-9)
          << "t = " << p.t_s << ", time constant " << tc;
      ++compared;
    }
    EXPECT_GT(compared, 100);
  }
}

// The linear single-track model (constant speed, linear tires, small angles), integrated
// independently with a fine RK4: the lateral offset of the CG for a wheel angle delta(t).
template <class Wheel>
double linear_offset(const VehicleParams& p, double v, double t_end, Wheel&& delta) {
  double vy = 0.0, r = 0.0, psi = 0.0, y = 0.0;
  const double h = 1e-4;
  const auto rates = [&](double t, double vy_, double r_, double psi_) {
    const double d = delta(t);
    const double f = -p.front_cornering_stiffness_n_per_rad * ((vy_ + p.cg_to_front_axle_m * r_) / v - d);
    const double rr = -p.rear_cornering_stiffness_n_per_rad * (vy_ - p.cg_to_rear_axle_m * r_) / v;
    return std::array<double, 4>{(f + rr) / p.mass_kg - v * r_,
                                 (p.cg_to_front_axle_m * f - p.cg_to_rear_axle_m * rr) / p.yaw_inertia_kgm2, r_,
                                 v * psi_ + vy_};
  };
  for (double t = 0.0; t < t_end - 1e-12; t += h) {
    const auto k1 = rates(t, vy, r, psi);
    const auto k2 = rates(t + h / 2, vy + h / 2 * k1[0], r + h / 2 * k1[1], psi + h / 2 * k1[2]);
    const auto k3 = rates(t + h / 2, vy + h / 2 * k2[0], r + h / 2 * k2[1], psi + h / 2 * k2[2]);
    const auto k4 = rates(t + h, vy + h * k3[0], r + h * k3[1], psi + h * k3[2]);
    vy += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
    r += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
    psi += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
    y += h / 6 * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3]);
  }
  return y;
}

TEST(Actuation, LateralOffsetOfAStepSteerFollowsTheLaggedActuator) {
  // Small angles on a dry road: the Fiala model is nearly linear there, so its offset matches the
  // linear single-track model driven by the analytic wheel angle, and differs clearly from the
  // offset with instant steering.
  ActuationConfig a;
  a.steer_dead_time_s = 0.1;
  a.steer_time_constant_s = 0.15;
  const double peak = 0.008;  // one step at the full rate
  const double v = 20.0;
  const SteerRun lagged = step_steer(a, peak, v);
  const SteerRun instant = step_steer(ActuationConfig{}, peak, v);
  const VehicleParams& p = lagged.config.ego;
  const double rate = p.max_steer_rate_radps;
  const double y0 = lagged.config.road.ego_lane_center_m;
  for (const double t : {0.6, 1.0, 1.4}) {
    const auto offset_at = [&](const RolloutResult& r) {
      for (const auto& point : r.path)
        if (point.t_s >= t - 1e-9) return point.state.y_m - y0;
      return 0.0;
    };
    const double model = linear_offset(p, v, t, [&](double s) { return lagged_ramp(s - 0.1, rate, peak, 0.15); });
    const double simulated = offset_at(lagged.run);
    EXPECT_NEAR(simulated, model, 0.02 * std::abs(model) + 1e-3) << "t = " << t;
    EXPECT_GT(offset_at(instant.run) - simulated, 0.1 * std::abs(model)) << "the lag must cost offset at t = " << t;
  }
}

TEST(Actuation, PlannerManeuversReplayThroughTheActuators) {
  // Tree nodes carry the actuators' memory (commands in flight, the commanded angle, the brake
  // level): the stitched maneuver replayed from t = 0 is the planner's run, step for step.
  SceneConfig config;
  config.actuation = {0.1, 0.12, 0.2, 8.5, 0.06, 0.1};
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  const ControlLimits drift{.allow_rear_lock = true};
  int compared = 0;
  for (const TJunctionCell& cell : {TJunctionCell{50, 1.0, 1.0, 3.0, 10.0}, TJunctionCell{40, 0.9, 1.0, 2.0, 10.0},
                                    TJunctionCell{60, 1.1, 0.5, 3.0, 10.0}}) {
    const Scene scene(config, cell);
    const PlanResult plan = plan_rrt(scene, *model, drift, 3, false);
    for (const auto* found : {&plan.avoidance, &plan.collision}) {
      if (!found->has_value()) continue;
      const RolloutResult& planned = **found;
      const RolloutResult again = replay(scene, *model, drift, maneuver_from_json(to_json(planned.maneuver), "test"));
      ++compared;
      EXPECT_EQ(again.termination, planned.termination);
      EXPECT_EQ(again.end_time_s, planned.end_time_s);
      EXPECT_EQ(again.end_state.x_m, planned.end_state.x_m);
      EXPECT_EQ(again.end_state.y_m, planned.end_state.y_m);
      EXPECT_EQ(again.end_state.steer_rad, planned.end_state.steer_rad);
    }
  }
  EXPECT_GE(compared, 3);
}

TEST(Actuation, CertificatesUnderActuatorsAreMadeForThemAndCheckOnlyForThem) {
  // A slow steering actuator makes more cells provably unavoidable; a certificate names the
  // actuation it was made for, and a scene with other actuators does not accept it.
  SceneConfig instant;
  instant.actuation.perception_latency_s = 0.25;
  SceneConfig slow = instant;
  slow.actuation.steer_dead_time_s = 0.1;
  slow.actuation.steer_time_constant_s = 0.15;
  int certified_instant = 0, certified_slow = 0;
  std::optional<Certificate> example;
  for (double speed = 40.0; speed <= 72.0; speed += 4.0)
    for (double ttc = 0.4; ttc <= 1.3; ttc += 0.1) {
      const TJunctionCell cell{speed, ttc, 1.0, 3.0, 10.0};
      if (certify_unavoidable(Scene(instant, cell))) ++certified_instant;
      if (auto c = certify_unavoidable(Scene(slow, cell))) {
        ++certified_slow;
        EXPECT_TRUE(check_certificate(Scene(slow, cell), *c));
        EXPECT_FALSE(check_certificate(Scene(instant, cell), *c));
        if (!example) example = c;
      }
    }
  EXPECT_GT(certified_slow, certified_instant);
  ASSERT_TRUE(example.has_value());
  const Certificate back =
      certificate_from_json(to_json(*example, test::tjunction_factors()), test::tjunction_factors(), "test");
  EXPECT_EQ(back.actuation.steer_time_constant_s, 0.15);
  EXPECT_TRUE(check_certificate(Scene(slow, back.cell), back));
}

}  // namespace actuation_test
}  // namespace emrm::sim
