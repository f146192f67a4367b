// The family "highway_obstacle" (docs/families.md): its layout from the factors, its categorical
// factors, the roadside's harm, and the trade-off every driving instructor teaches — for a deer,
// brake and accept a light hit rather than swerve into the guardrail or down the embankment; for a
// truck, evade where a path exists.

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/sim/highway.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/planner.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/validity.hpp"
#include "outcomes.hpp"
#include "test_scale.hpp"

namespace emrm::sim {
namespace {

using test::outcome;

using ::testing::HasSubstr;

SceneConfig highway_scene() {
  SceneConfig config;
  config.family = "highway_obstacle";
  config.max_initial_distance_m = 70.0;
  validate(config);
  return config;
}

// A cell by its factors' names: obstacle and roadside by their levels.
CellInput cell(const SceneConfig& config, double speed_kph, double ttc_s, double mu, std::string_view obstacle,
               double blocked_m, std::string_view roadside) {
  const FactorTable factors = scenario_factors(config);
  CellInput c = factors.defaults();
  c[0] = speed_kph;
  c[1] = ttc_s;
  c[2] = mu;
  c[*factors.find("obstacle")] = factors[*factors.find("obstacle")].parse(obstacle);
  c[*factors.find("blocked_m")] = blocked_m;
  c[*factors.find("roadside")] = factors[*factors.find("roadside")].parse(roadside);
  factors.validate(c);
  return c;
}

TEST(HighwayObstacle, IsShippedWithItsFactors) {
  const SceneConfig config = highway_scene();
  const FactorTable factors = scenario_factors(config);
  EXPECT_EQ(factors.key_list(), "speed_kph, ttc_s, mu, obstacle, blocked_m, roadside");
  EXPECT_FALSE(find_family("highway_obstacle")->tjunction_analytics);
  const Factor& obstacle = factors[*factors.find("obstacle")];
  EXPECT_TRUE(obstacle.categorical());
  EXPECT_EQ(obstacle.parse("deer"), 1.0);
  EXPECT_EQ(obstacle.value_text(0.0), "truck");
  EXPECT_FALSE(obstacle.accepts(0.5));
  EXPECT_FALSE(obstacle.accepts(2.0));
  try {
    (void)obstacle.parse("moose");
    ADD_FAILURE() << "an unknown level was read";
  } catch (const UsageError& e) {
    EXPECT_THAT(e.what(), HasSubstr("obstacle is one of truck, deer, got 'moose'"));
  }
  EXPECT_THAT(obstacle.refusal(2.0), HasSubstr("one of the levels truck (0), deer (1)"));
  // The road is 10 m wide: the obstacle reaches no further into it.
  const Factor& blocked = factors[*factors.find("blocked_m")];
  EXPECT_TRUE(blocked.accepts(10.0));
  EXPECT_FALSE(blocked.accepts(10.01));
  EXPECT_EQ(cell_text(factors, cell(config, 100, 1.2, 0.8, "deer", 5.0, "embankment")),
            "100 km/h, TTC 1.2 s, mu 0.8, deer, blocked 5 m, embankment");
}

TEST(HighwayObstacle, TheObstacleStopsBlockedMetresIntoTheRoad) {
  const SceneConfig config = highway_scene();
  for (const std::string_view kind : {"truck", "deer"}) {
    const Scene scene(config, cell(config, 90, 1.4, 0.8, kind, 4.0, "guardrail"));
    const ObstacleConfig& o = kind == "deer" ? config.highway.deer : config.highway.truck;
    const Actor& hazard = scene.hazard();
    EXPECT_EQ(core::enum_name(hazard.body().kind), kind == "deer" ? "animal" : "truck");
    // Its near side v·TTC ahead of the ego's front bumper, its far side where the ego has passed it.
    EXPECT_NEAR(hazard.at(0.0).box.center.x - o.width_m / 2.0, 90 / 3.6 * 1.4, 1e-12);
    EXPECT_NEAR(scene.passed_x_m() - scene.initial_distance_m(), o.width_m, 1e-12);
    // At rest its front (its highest y) stands blocked_m above the right edge; it moved along +y only.
    const double v = o.speed_kph / 3.6;
    const double rest_s = v / o.decel_mps2;
    EXPECT_NEAR(hazard.y_extent_at(rest_s + 1.0).second, scene.road().min_y_m + 4.0, 1e-12);
    EXPECT_NEAR(hazard.y_extent_at(0.0).second, scene.road().min_y_m + 4.0 - v * v / (2.0 * o.decel_mps2), 1e-12);
    EXPECT_EQ(hazard.at(0.0).box.center.x, hazard.at(rest_s).box.center.x);
    EXPECT_NEAR(hazard.y_extent_at(1.0).second - hazard.y_extent_at(1.0).first, o.length_m, 1e-12);
  }
}

TEST(HighwayObstacle, FreeBandsLieBesideTheObstacle) {
  const SceneConfig config = highway_scene();
  const double t = config.simulation.horizon_s;
  // A 12 m truck reaching 6.25 m into the road leaves the left lane alone.
  const Scene truck(config, cell(config, 100, 1.2, 0.8, "truck", 6.25, "guardrail"));
  const FreeBands t_bands = truck.free_bands(t);
  ASSERT_EQ(t_bands.count, 1u);
  EXPECT_FALSE(t_bands.band[0].right);
  EXPECT_NEAR(t_bands.band[0].low_m, 3.75, 1e-12);
  EXPECT_EQ(t_bands.band[0].high_m, truck.road().max_y_m);
  // A deer 1.6 m long standing 5 m into the road leaves room on both sides.
  const Scene deer(config, cell(config, 100, 1.2, 0.8, "deer", 5.0, "guardrail"));
  const FreeBands d_bands = deer.free_bands(t);
  ASSERT_EQ(d_bands.count, 2u);
  EXPECT_TRUE(d_bands.band[0].right);
  EXPECT_EQ(d_bands.band[0].low_m, deer.road().min_y_m);
  EXPECT_NEAR(d_bands.band[0].high_m, -2.5 + 5.0 - 1.6, 1e-12);
  EXPECT_NEAR(d_bands.band[1].low_m, -2.5 + 5.0, 1e-12);
}

// Whether the obstacle stands in the car's straight path, from its extent across the road: the car
// in the right lane spans y in [1.875 - w/2, 1.875 + w/2]; an obstacle whose front stops short of it
// (the shoulder alone) leaves the lane free, so braking need not stop short of it.
TEST(HighwayObstacle, TheObstacleIsInTheWayOnlyWhereItReachesTheCarsPath) {
  const SceneConfig config = highway_scene();
  const double right_side = config.highway.shoulder_m + 1.875 - config.ego.width_m / 2.0;  // as blocked_m
  EXPECT_FALSE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "truck", 2.5, "guardrail")));
  EXPECT_FALSE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "truck", right_side - 0.05, "guardrail")));
  EXPECT_TRUE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "truck", right_side + 0.05, "guardrail")));
  EXPECT_TRUE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "truck", 6.25, "guardrail")));
  // A deer 1.6 m long standing 9.5 m into the road has passed beyond the car's lane.
  EXPECT_FALSE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "deer", 9.5, "guardrail")));
  EXPECT_TRUE(hazard_in_the_way(config, cell(config, 100, 1.2, 0.8, "deer", 5.0, "guardrail")));
}

// A departure down the embankment: AASHTO's critical slope (steeper than 1V:3H) rolls the car over,
// and a rollover kills 2.7 % of occupants (NHTSA, Strashny 2007); a flatter slope is traversable.
TEST(HighwayObstacle, AnEmbankmentSteeperThanCriticalRollsTheCarOver) {
  SceneConfig config = highway_scene();
  const SeverityConfig& severity = config.severity;
  EXPECT_EQ(severity.critical_slope_h, 3.0);
  EXPECT_EQ(severity.rollover_p_fatal, 0.027);
  EXPECT_TRUE(rolls_over(2.0, severity));
  EXPECT_FALSE(rolls_over(3.0, severity));  // 1V:3H itself is non-recoverable but traversable
  EXPECT_FALSE(rolls_over(4.0, severity));
  // A car leaving the road to the right at 20 m/s.
  VehicleState s;
  s.x_m = 30.0;
  s.y_m = -2.6;
  s.yaw_rad = -0.1;
  s.vx_mps = 20.0;
  for (const double slope : {2.0, 4.0}) {
    config.highway.embankment_slope_h = slope;
    const Scene scene(config, cell(config, 100, 1.2, 0.8, "deer", 5.0, "embankment"));
    const ImpactAssessment a = roadside_impact(scene, s);
    EXPECT_EQ(a.delta_v_mps, 0.0);
    EXPECT_EQ(a.p_fatal, slope < 3.0 ? 0.027 : 0.0);
    EXPECT_EQ(a.p_mais3, a.p_fatal);
    EXPECT_EQ(a.loss_level, 4);
  }
  // The same departure against the guardrail is an impact.
  const Scene guarded(config, cell(config, 100, 1.2, 0.8, "deer", 5.0, "guardrail"));
  EXPECT_GT(roadside_impact(guarded, s).delta_v_mps, 0.0);
}

// For two impacts the least-loss order is Δv's, as before the risks joined it.
TEST(HighwayObstacle, LeastLossOrdersImpactsByDeltaV) {
  const SeverityConfig c;
  const auto impact = [&](double dv) {
    ImpactAssessment a;
    a.delta_v_mps = dv;
    a.p_mais3 = p_mais3(dv, c);
    a.p_fatal = p_fatal(dv, c);
    a.loss_level = loss_level(true, false, a.p_mais3, a.p_fatal, c);
    return a;
  };
  for (double a = 0.0; a < 40.0; a += 0.37)
    for (double b = 0.0; b < 40.0; b += 0.53) {
      const ImpactAssessment x = impact(a), y = impact(b);
      const bool by_dv = x.loss_level != y.loss_level ? x.loss_level < y.loss_level : a < b;
      EXPECT_EQ(less_loss(x, y), by_dv) << a << " " << b;
    }
}

// The shipped example: the production car's actuation (its delays matter at 100 km/h).
SceneConfig example_scene() { return load_scene_config(EMRM_SOURCE_DIR "/examples/highway_obstacle/scene.yaml"); }

// The deer/truck contrast of the paper's introduction at 100 km/h on μ 0.8, TTC 1.0–1.5 s (issue 37).
// A deer standing in the ego's lane: where EMRM cannot get past it, it brakes into it rather than
// leave the road. A 70 kg deer costs the car's occupants a Δv of at most its share of the closing
// speed, m_deer / (m_car + m_deer) (plus the tangential share of a glancing contact); a departure
// costs a guardrail impact or, down the 1V:2H embankment, a rollover (P(fatal) 2.7 %).
TEST(HighwayObstacle, ADeerIsBrakedForRatherThanTheRoadLeft) {
  const SceneConfig config = example_scene();
  const double share = config.highway.deer.mass_kg / (config.highway.deer.mass_kg + config.ego.mass_kg);
  int braked_into = 0;
  const std::vector<double> ttcs = test::sample(std::vector<double>{1.0, 1.25, 1.5}, std::vector<double>{1.0, 1.5});
  for (const double ttc : ttcs)
    for (const double blocked : test::sample(std::vector<double>{4.5, 5.0, 6.25}, std::vector<double>{5.0}))
      for (const std::string_view roadside : {"guardrail", "embankment"}) {
        const CellResult r = simulate_cell(config, cell(config, 100, ttc, 0.8, "deer", blocked, roadside), {});
        const std::string where = fmt::format("TTC {} s, blocked {} m, {}", ttc, blocked, roadside);
        const StrategyOutcome& stop = outcome(r, "emergency_stop");
        const StrategyOutcome& emrm = outcome(r, "emrm");
        if (stop.avoided) continue;
        // The braked hit: light, L4, its Δv within the deer's share of the impact speed.
        EXPECT_EQ(stop.impact.loss_level, 4) << where;
        EXPECT_LE(stop.impact.delta_v_mps, 1.05 * share * stop.impact.impact_speed_mps) << where;
        if (emrm.avoided) continue;
        // EMRM never trades it for a worse departure or guardrail hit: no higher level, no higher risk.
        EXPECT_FALSE(less_loss(stop.impact, emrm.impact)) << where;
        if (emrm.road_departure) {
          EXPECT_LE(emrm.impact.loss_level, stop.impact.loss_level) << where;
          EXPECT_LE(emrm.impact.p_fatal, stop.impact.p_fatal) << where;
        } else {
          ++braked_into;
        }
      }
  EXPECT_GT(braked_into, 0) << "no cell where EMRM had to hit the deer: the contrast is not tested";
}

// The same car swerving off the road where the deer stands: down the embankment it rolls over, into
// the guardrail it hits at the swerve's angle; both are worse than the braked hit on the deer.
TEST(HighwayObstacle, LeavingTheRoadForADeerIsWorseThanHittingIt) {
  const SceneConfig config = example_scene();
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  for (const std::string_view roadside : {"guardrail", "embankment"}) {
    const Scene scene(config, cell(config, 100, 1.5, 0.8, "deer", 5.0, roadside));
    const Roller roller(scene, *model, ControlLimits{});
    const RolloutResult braked = roller.roll(scene.ego_initial(), 0.0, {hold(Control{}, 0.25)}, Tail::full_stop());
    ASSERT_EQ(braked.termination, Termination::kContact) << roadside;
    // Hard right: off the road before the deer.
    Control right;
    right.steer_rate_radps = -config.ego.max_steer_rate_radps;
    const RolloutResult swerve = roller.roll(scene.ego_initial(), 0.0, {hold(Control{}, 0.25), hold(right, 3.0)}, {});
    ASSERT_EQ(swerve.termination, Termination::kRoadDeparture) << roadside;
    EXPECT_TRUE(less_loss(braked.impact, swerve.impact)) << roadside;
  }
}

// A truck across the ego's lane: wherever a textbook lane change to the left gets past it (an
// open-loop steer-hold-countersteer, found here by a small grid of its own), EMRM avoids too.
TEST(HighwayObstacle, ATruckIsAvoidedWhereAPathExists) {
  const SceneConfig config = example_scene();
  const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const double rate = config.ego.max_steer_rate_radps;
  int witnessed = 0;
  const std::vector<double> ttcs = test::sample(std::vector<double>{1.25, 1.5}, std::vector<double>{1.5});
  for (const double ttc : ttcs)
    for (const double blocked : {5.0, 6.25}) {
      const CellInput c = cell(config, 100, ttc, 0.8, "truck", blocked, "guardrail");
      const Scene scene(config, c);
      const Roller roller(scene, *model, ControlLimits{});
      bool path = false;
      for (const double peak : {0.03, 0.05, 0.08, 0.12})
        for (const double hold_s : {0.1, 0.3, 0.5, 0.8}) {
          if (path) break;
          Control in, out;
          in.steer_rate_radps = rate;
          out.steer_rate_radps = -rate;
          const std::vector<ControlSegment> plan{hold(Control{}, 0.25),   hold(in, peak / rate),
                                                 hold(Control{}, hold_s), hold(out, 2.0 * peak / rate),
                                                 hold(Control{}, hold_s), hold(in, peak / rate)};
          path = roller.roll(scene.ego_initial(), 0.0, plan, Tail::full_stop()).avoided();
        }
      if (!path) continue;
      ++witnessed;
      const CellResult r = simulate_cell(config, c, {});
      EXPECT_TRUE(outcome(r, "emrm").avoided) << "TTC " << ttc << " s, blocked " << blocked << " m";
    }
  EXPECT_GT(witnessed, 0) << "no cell with a lane change past the truck: the contrast is not tested";
}

}  // namespace
}  // namespace emrm::sim
