// The analytic facts of a cell (sim/stop_physics.hpp): the stop boundary through the actuators, and
// what the no-action rollout tells, each against its closed form or the simulator itself.

#include "emrm/sim/stop_physics.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

#include "emrm/sim/rollout.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/termination.hpp"
#include "test_scale.hpp"

namespace emrm::sim {
namespace stop_physics_test {

ActuationConfig with_latency(double latency_s) {
  ActuationConfig a;
  a.perception_latency_s = latency_s;
  return a;
}

TEST(StopBoundary, AnalyticHyperbola) {
  // v = 72 km/h = 20 m/s at mu 1: v / (2 mu g) = 20 / 19.62 = 1.0194 s.
  EXPECT_FALSE(analytically_stoppable(72, 1.0, 1.0, ActuationConfig{}));
  EXPECT_TRUE(analytically_stoppable(72, 1.02, 1.0, ActuationConfig{}));
  EXPECT_FALSE(analytically_stoppable(72, 1.02, 1.0, with_latency(0.1)));
  EXPECT_FALSE(analytically_stoppable(36, 1.0, 0.5, ActuationConfig{}));  // 10 / 9.81 = 1.019 s
}

TEST(AnalyticStop, WithoutLatencyOrRampItIsVOverTwoMuG) {
  const ActuationConfig ideal;
  for (const double speed : {20.0, 50.0, 72.0})
    for (const double mu : {0.3, 0.7, 1.0}) {
      const double v = speed / 3.6;
      EXPECT_NEAR(stop_boundary_ttc_s(speed, mu, ideal), v / (2.0 * mu * kGravity_mps2), 1e-12);
    }
  // 72 km/h = 20 m/s on μ 1: 20 / 19.62 s.
  EXPECT_NEAR(stop_boundary_ttc_s(72.0, 1.0, ideal), 1.019367992, 1e-9);
  ActuationConfig late;
  late.perception_latency_s = 0.3;
  EXPECT_NEAR(stop_boundary_ttc_s(72.0, 1.0, late), 0.3 + 1.019367992, 1e-9);
}

TEST(AnalyticStop, ItIsTheBoundaryOfAnalyticallyStoppableThroughTheActuators) {
  ActuationConfig production;
  production.perception_latency_s = 0.25;
  production.brake_dead_time_s = 0.1;
  production.brake_ramp_s = 0.25;
  production.max_decel_mps2 = 8.0;
  for (const double speed : {10.0, 30.0, 60.0})
    for (const double mu : {0.4, 1.0}) {
      const double ttc = stop_boundary_ttc_s(speed, mu, production);
      EXPECT_TRUE(analytically_stoppable(speed, ttc + 1e-6, mu, production)) << speed << " " << mu;
      EXPECT_FALSE(analytically_stoppable(speed, ttc - 1e-6, mu, production)) << speed << " " << mu;
    }
}

// The built-in scene with a production car's latency and brakes (the shipped profile's figures)
// and a planner budget of `max_nodes`.
SceneConfig production_car(int max_nodes) {
  SceneConfig config;
  config.actuation.perception_latency_s = 0.25;
  config.actuation.brake_dead_time_s = 0.1;
  config.actuation.brake_ramp_s = 0.25;
  config.actuation.steer_dead_time_s = 0.05;
  config.planner.max_nodes = max_nodes;
  return config;
}

// The analytic calls against the simulated emergency stop, on cells drawn across the 5-D domain
// with a production car's actuators and trucks up to 30 km/h: a cell called kStops is avoided by
// braking, one called kCannotStop is not, whether the truck stood in the car's lane from the start
// or only got there by the time the car could (t = TTC).
TEST(StopCall, AgreesWithTheSimulatedEmergencyStop) {
  const SceneConfig config = production_car(1);
  CellOptions only_stop;
  only_stop.strategies = {"emergency_stop"};
  only_stop.certify = false;
  only_stop.strengthen = false;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> speed(30, 72), ttc(0.25, 2.95), mu(0.1, 1.0), passage(1.0, 4.0);
  const std::array<double, 4> truck_speeds{0.0, 10.0, 20.0, 30.0};
  std::size_t stops = 0, cannot = 0, cannot_only_later = 0;
  const std::size_t cells = test::sample(4000, 800);
  for (std::size_t k = 0; k < cells; ++k) {
    const TJunctionCell cell{speed(random), ttc(random), mu(random), passage(random), truck_speeds[k % 4]};
    if (!Scene(config, cell).feasible()) continue;
    const StopCall call = stop_call(config, cell);
    if (call == StopCall::kUnknown) continue;
    const bool avoided = simulate_cell(config, cell, only_stop).strategies.front().avoided;
    EXPECT_EQ(avoided, call == StopCall::kStops)
        << cell.speed_kph << " km/h, TTC " << cell.ttc_s << " s, mu " << cell.mu << ", passage " << cell.passage_m
        << " m, truck " << cell.truck_speed_kph << " km/h";
    (call == StopCall::kStops ? stops : cannot) += 1;
    const Scene scene(config, cell);
    const double top = config.road.ego_lane_center_m + config.ego.width_m / 2.0;
    if (call == StopCall::kCannotStop && scene.truck_front_y_at(0.0) >= top - 0.01) ++cannot_only_later;
  }
  EXPECT_GT(stops, cells / 20);
  EXPECT_GT(cannot, cells / 10);
  EXPECT_GT(cannot_only_later, cells / 20);  // the truck came down into the lane after t = 0
}

// Reaching the truck before any actuator can act (TTC within the perception latency and the
// quicker dead time) while it stands in the car's way, or meeting it by then as it comes across
// (the no-action rollout's contact), the car hits it whatever it decides: no early run can start at
// such a cell. Every strategy's simulation agrees; without latency the call never rules one out.
TEST(MayPassEarly, IsRuledOutOnlyWhereNoStrategyAvoids) {
  const SceneConfig config = production_car(200);
  CellOptions options;
  options.certify = false;
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> speed(30, 72), ttc(0.2, 0.3), mu(0.1, 1.0), passage(1.0, 4.0);
  const std::array<double, 3> truck_speeds{10.0, 20.0, 30.0};
  std::size_t ruled_out = 0, still_entering = 0;
  const double top = config.road.ego_lane_center_m + config.ego.width_m / 2.0;
  const std::size_t cells = test::sample(120, 30);
  for (std::size_t k = 0; k < cells; ++k) {
    const TJunctionCell cell{speed(random), ttc(random), mu(random), passage(random), truck_speeds[k % 3]};
    if (!Scene(config, cell).feasible()) continue;
    SceneConfig instant = config;
    instant.actuation = ActuationConfig{};
    EXPECT_TRUE(may_pass_early(instant, cell));
    if (may_pass_early(config, cell)) continue;
    ++ruled_out;
    // Ruled out by the no-action rollout's contact, the truck not yet across the car's path at TTC.
    if (Scene(config, cell).truck_front_y_at(cell.ttc_s) >= top - 0.01) ++still_entering;
    const Region region = simulate_cell(config, cell, options).region;
    EXPECT_TRUE(region == Region::kO || region == Region::kR)
        << cell.speed_kph << " km/h, TTC " << cell.ttc_s << " s, mu " << cell.mu << ", passage " << cell.passage_m
        << " m, truck " << cell.truck_speed_kph << " km/h: " << region_name(region);
  }
  EXPECT_GT(ruled_out, cells / 4);
  if (!test::kSanitized) {
    EXPECT_GT(still_entering, 0u);  // a few in a hundred
  }
  TJunctionCell standing{50.0, 0.25, 0.8, 2.0, 0.0};
  EXPECT_FALSE(may_pass_early(config, standing));
}

// A rollout braking straight short of the truck ends in one step where it comes to rest (the
// "stops short" test); with_closed_form_stop fills in every step between at one deceleration, and
// that filled path is what an outcome carries (its JSON, Python and exported trajectories).
TEST(ClosedFormStop, IsFilledInAtEveryStepAtConstantDeceleration) {
  const SceneConfig config;
  const TJunctionCell cell{50, 1.5, 1.0, 3.0, 10};
  CellOptions options;
  options.strategies = {"emergency_stop"};
  const StrategyOutcome outcome = simulate_cell(config, cell, options).strategies.front();
  ASSERT_TRUE(outcome.avoided);
  const Scene scene(config, cell);
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const std::vector<PathPoint> path = replay(scene, *model, ControlLimits{}, outcome.maneuver).path;
  const double dt = config.simulation.dt_s;
  ASSERT_GT(path.back().t_s - path[path.size() - 2].t_s, 2 * dt) << "expected a closed-form stop";
  const auto filled = with_closed_form_stop(path, dt);
  ASSERT_GT(filled.size(), path.size());
  ASSERT_EQ(outcome.path.size(), filled.size());
  for (std::size_t k = 0; k < filled.size(); ++k) EXPECT_EQ(outcome.path[k].state.x_m, filled[k].state.x_m);
  EXPECT_EQ(filled.back().t_s, path.back().t_s);
  EXPECT_EQ(filled.back().state.x_m, path.back().state.x_m);
  const std::size_t from = path.size() - 2;
  const double v0 = path[from].state.speed_mps();
  const double decel = v0 / (path.back().t_s - path[from].t_s);
  for (std::size_t k = from + 1; k < filled.size(); ++k) {
    EXPECT_NEAR(filled[k].t_s - filled[k - 1].t_s, dt, dt * 0.51 + 1e-12);  // the last step may be shorter
    EXPECT_LT(filled[k].state.speed_mps(), filled[k - 1].state.speed_mps());
    EXPECT_GT(filled[k].state.x_m, filled[k - 1].state.x_m);
    const double tau = filled[k].t_s - path[from].t_s;
    if (k + 1 < filled.size()) {
      EXPECT_NEAR(filled[k].state.speed_mps(), v0 - decel * tau, 1e-9);
      EXPECT_NEAR(filled[k].state.x_m, path[from].state.x_m + v0 * tau - 0.5 * decel * tau * tau, 1e-9);
    }
  }
  // Unchanged: a path that does not end in such a stop, and a path already filled in.
  const auto short_path = std::vector<PathPoint>(path.begin(), path.end() - 1);
  EXPECT_EQ(with_closed_form_stop(short_path, dt).size(), short_path.size());
  EXPECT_EQ(with_closed_form_stop(filled, dt).size(), filled.size());
}

}  // namespace stop_physics_test
}  // namespace emrm::sim
