// The family "cut_in" (docs/families.md): the layout from the factors (the gap is the relative speed
// times the TTC), cells whose factors contradict each other, what the TTC means (doing nothing, the car
// runs into the cutting car's rear at t = TTC), and the emergency stop's closed form against a car
// that cuts in without braking: the gap closes by the stopping distance from the relative speed.

#include "emrm/sim/cut_in.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <string_view>
#include <utility>

#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/vehicle.hpp"
#include "outcomes.hpp"

namespace emrm::sim {
namespace cut_in_test {

using test::outcome;
using ::testing::HasSubstr;

SceneConfig cut_in_scene() { return load_scene_config(EMRM_SOURCE_DIR "/examples/cut_in/scene.yaml"); }

struct CutIn {
  double speed_kph = 100.0;
  double ttc_s = 1.5;
  double mu = 1.0;
  double relative_kph = 20.0;
  double lateral_mps = 1.0;
  double decel_mps2 = 4.0;
  std::string_view following = "none";
};

CellInput cell(const SceneConfig& config, const CutIn& c) {
  const FactorTable factors = scenario_factors(config);
  CellInput out = factors.defaults();
  out[kEgoSpeedFactor] = c.speed_kph;
  out[kTtcFactor] = c.ttc_s;
  out[kFrictionFactor] = c.mu;
  out[*factors.find("relative_speed_kph")] = c.relative_kph;
  out[*factors.find("lateral_speed_mps")] = c.lateral_mps;
  out[*factors.find("target_decel_mps2")] = c.decel_mps2;
  out[*factors.find("following")] = factors[*factors.find("following")].parse(c.following);
  factors.validate(out);
  return out;
}

TEST(CutIn, LaysOutTheCuttingCarAndTheFollower) {
  const SceneConfig config = cut_in_scene();
  const CutInConfig& cut = config.cut_in;
  EXPECT_EQ(scenario_factors(config).key_list(),
            "speed_kph, ttc_s, mu, relative_speed_kph, lateral_speed_mps, target_decel_mps2, following");
  const Scene alone(config, cell(config, {}));
  ASSERT_EQ(alone.actors().size(), 1u);
  const Scene followed(config, cell(config, {.following = "car"}));
  ASSERT_EQ(followed.actors().size(), 2u);
  const Actor& cutting = followed.hazard();
  EXPECT_EQ(cutting.body().kind, ActorKind::kCar);
  // Its rear the gap ahead, v_rel·TTC; its right side on the lane line; slower by the relative speed.
  const double gap = 20.0 / 3.6 * 1.5;
  EXPECT_NEAR(followed.initial_distance_m(), gap, 1e-12);
  EXPECT_NEAR(cutting.at(0.0).box.center.x - cut.cutting.length_m / 2.0, gap, 1e-12);
  EXPECT_NEAR(cutting.y_extent_at(0.0).first, cut.lane_width_m, 1e-12);
  EXPECT_NEAR(cutting.at(0.0).velocity_mps.x, 80.0 / 3.6, 1e-12);
  // It drifts right at 1 m/s until centred in the ego's lane, and stays there.
  EXPECT_NEAR(cutting.y_extent_at(1.0).first, cut.lane_width_m - 1.0, 1e-12);
  const double centred_s = (cut.lane_width_m + cut.cutting.width_m / 2.0 - cut.ego_y_m()) / 1.0;
  EXPECT_NEAR(cutting.at(centred_s).box.center.y, cut.ego_y_m(), 1e-12);
  EXPECT_NEAR(cutting.at(centred_s + 2.0).box.center.y, cut.ego_y_m(), 1e-12);
  // It brakes at 4 m/s² from the start and comes to rest.
  EXPECT_NEAR(cutting.motion().rest_time_s(), 80.0 / 3.6 / 4.0, 1e-12);
  // The far side moves with it: the ego has passed it only beyond where it is now.
  EXPECT_NEAR(followed.passed_x_m(2.0) - followed.passed_x_m(0.0), cutting.motion().travelled_m(2.0), 1e-12);
  // The follower: centred in the left lane, behind the ego, overtaking it.
  const Actor& follower = followed.actors()[1];
  EXPECT_NEAR(follower.at(0.0).box.center.y, 1.5 * cut.lane_width_m, 1e-12);
  EXPECT_LT(follower.motion().front_at(0.0).x, -config.ego.length_m);
  EXPECT_NEAR(follower.at(0.0).velocity_mps.x, (100.0 + cut.follower_faster_kph) / 3.6, 1e-12);
  // A car driving on ahead is never in the way for certain, and the v·TTC boundary does not hold.
  EXPECT_FALSE(hazard_in_the_way(config, cell(config, {})));
  EXPECT_FALSE(stop_boundary_applies(config));
  EXPECT_EQ(stop_call(config, cell(config, {.ttc_s = 3.0})), StopCall::kUnknown);
  SceneConfig tjunction;
  EXPECT_TRUE(stop_boundary_applies(tjunction));
}

TEST(CutIn, ACarSlowerThanStandingIsInfeasible) {
  const SceneConfig config = cut_in_scene();
  const Scene scene(config, cell(config, {.speed_kph = 30.0, .relative_kph = 40.0}));
  EXPECT_FALSE(scene.feasible());
  EXPECT_THAT(scene.infeasible_reason(), HasSubstr("40 km/h slower than the ego, which drives 30 km/h"));
  const CellResult r = simulate_cell(config, cell(config, {.speed_kph = 30.0, .relative_kph = 40.0}), {});
  EXPECT_FALSE(r.feasible);
  // A gap beyond the scene's limit is infeasible too, and says so by the gap.
  const Scene far(config, cell(config, {.ttc_s = 20.0}));
  EXPECT_FALSE(far.feasible());
  EXPECT_THAT(far.infeasible_reason(), HasSubstr("its gap"));
}

// Doing nothing, the ego reaches the rear of a car that keeps its speed at t = TTC (once the car is
// in its path: a sharp cut-in at 5 m/s is there within a quarter of a second).
TEST(CutIn, DoingNothingHitsTheRearAtTheTtc) {
  const SceneConfig config = cut_in_scene();
  for (const double ttc : {0.8, 1.5, 2.5}) {
    const Scene scene(config, cell(config, {.ttc_s = ttc, .lateral_mps = 5.0, .decel_mps2 = 0.0}));
    const auto model = make_vehicle_model(config.simulation.vehicle_model, config.ego);
    const RolloutResult nothing = no_action_rollout(scene, *model);
    EXPECT_EQ(nothing.termination, Termination::kContact) << ttc;
    EXPECT_NEAR(nothing.end_time_s, ttc, 2.0 * config.simulation.dt_s) << ttc;
  }
}

// Against a car that cuts in and keeps its speed, the ego's braking is the same in the car's frame
// as from the relative speed to a stop: the gap closes by the stopping distance through the
// actuators from v_rel, so the emergency stop avoids exactly from TTC = d_stop(v_rel)/v_rel on
// (stop_boundary_ttc_s at the relative speed), whatever the ego's own speed.
TEST(CutIn, TheEmergencyStopAvoidsFromTheRelativeSpeedsStopBoundary) {
  const SceneConfig config = cut_in_scene();
  CellOptions options;
  options.strategies = {"emergency_stop"};
  for (const auto& [speed, mu] : {std::pair{80.0, 1.0}, std::pair{120.0, 0.6}})
    for (const double relative : {20.0, 40.0}) {
      const double boundary = stop_boundary_ttc_s(relative, mu, config.actuation);
      for (const double offset : {-0.05, 0.05}) {
        const CutIn c{.speed_kph = speed,
                      .ttc_s = boundary + offset,
                      .mu = mu,
                      .relative_kph = relative,
                      .lateral_mps = 5.0,
                      .decel_mps2 = 0.0};
        const CellResult r = simulate_cell(config, cell(config, c), options);
        EXPECT_EQ(outcome(r, "emergency_stop").avoided, offset > 0.0)
            << speed << " km/h, " << relative << " km/h slower, mu " << mu << ", TTC " << c.ttc_s;
      }
    }
}

}  // namespace cut_in_test
}  // namespace emrm::sim
