// A car at rest is safe only if nothing that moves on meets it (validity.hpp, touch_at_rest;
// docs/physics.md, "Safe state"): a car cutting in that drifts on into the standing ego, a pedestrian
// who walks on into a car that stopped across the path. Tested against the actors' own closed-form
// motion (clear just before the touch, overlapping just after), for nothing where the car stands
// clear, and as an invariant of the simulator: no strategy of any family ends at rest in the way of
// an actor that is still moving (sampled apart from it).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/validity.hpp"

namespace emrm::sim {
namespace touch_at_rest_test {

SceneConfig example(const std::string& family) {
  return load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/" + family + "/scene.yaml");
}

CellInput defaults_at(const SceneConfig& config, double speed_kph, double ttc_s) {
  CellInput c = scenario_factors(config).defaults();
  c[kEgoSpeedFactor] = speed_kph;
  c[kTtcFactor] = ttc_s;
  return c;
}

// The ego standing with its front `ahead_m` behind where the actor's box is at time t, in the
// actor's lane (same y), or offset sideways by `y_m`.
VehicleState standing_at(const Scene& scene, double x_front_m, double y_m) {
  VehicleState s = scene.ego_initial();
  s.x_m = x_front_m - scene.config().ego.cg_to_front_m();
  s.y_m = y_m;
  s.vx_mps = s.vy_mps = s.yaw_rate_radps = 0.0;
  return s;
}

void expect_touch_at(const Scene& scene, const VehicleState& s, const TouchAtRest& touch) {
  const core::OrientedBox ego = scene.ego_box(s);
  const Actor& actor = scene.actors()[touch.actor];
  EXPECT_GT(core::separation_lower_bound(ego, actor.at(touch.t_s - 1e-4).box), 0.0);
  EXPECT_TRUE(core::contact(ego, actor.at(touch.t_s + 1e-4).box).touching);
}

// The cutting car drifts into the ego's lane at its lateral speed: a car standing in that lane just
// ahead of it is met when the car's side reaches it; one standing well behind it is not.
TEST(TouchAtRest, ACarCuttingInDriftsIntoTheStandingEgo) {
  const SceneConfig config = example("cut_in");
  const Scene scene(config, defaults_at(config, 60.0, 1.0));
  const Actor& car = scene.hazard();
  ASSERT_GT(std::abs(car.motion().lateral_mps) * car.motion().lateral_for_s, 0.0);
  // Ahead of the cutting car at t = 0.2 s, in the lane it drifts into: it catches up as it drifts.
  const ActorState at = car.at(0.2);
  const VehicleState beside = standing_at(scene, at.box.center.x + 8.0, scene.ego_initial().y_m);
  const auto touch = touch_at_rest(scene, beside, 0.2);
  ASSERT_TRUE(touch.has_value());
  EXPECT_EQ(touch->actor, 0u);
  EXPECT_GT(touch->t_s, 0.2);
  expect_touch_at(scene, beside, *touch);
  // Far behind it: it moves on, away along the road.
  const VehicleState behind = standing_at(scene, at.box.center.x - 30.0, scene.ego_initial().y_m);
  EXPECT_FALSE(touch_at_rest(scene, behind, 0.2).has_value());
}

// A pedestrian who walks on across the street meets a car that stopped across the path; a car that
// stopped short of the path is passed by.
TEST(TouchAtRest, APedestrianWalksIntoACarStoppedAcrossThePath) {
  const SceneConfig config = example("pedestrian_crossing");
  const Scene scene(config, defaults_at(config, 40.0, 1.2));
  const Actor& walker = scene.hazard();
  const ActorState at = walker.at(0.0);
  const VehicleState across = standing_at(scene, at.box.center.x + 1.0, scene.ego_initial().y_m);
  const auto touch = touch_at_rest(scene, across, 0.0);
  ASSERT_TRUE(touch.has_value());
  EXPECT_EQ(touch->actor, 0u);
  expect_touch_at(scene, across, *touch);
  const VehicleState short_of = standing_at(scene, at.box.center.x - 2.0, scene.ego_initial().y_m);
  EXPECT_FALSE(touch_at_rest(scene, short_of, 0.0).has_value());
}

// The simulator's invariant, checked apart from touch_at_rest: an avoidance that ends at rest stands
// where no actor that moves on overlaps it, sampled every millisecond over the horizon after the end
// while the actor moves — over cells of every family, every strategy. (The cut-in at 60 km/h, TTC
// 1.0 s is the cell whose stops the cutting car used to brush.)
TEST(TouchAtRest, NoAvoidanceEndsAtRestInTheWayOfAnActor) {
  struct Case {
    const char* family;
    double speed_kph, ttc_s;
  };
  const std::vector<Case> cases{{"cut_in", 60, 1.0},
                                {"cut_in", 80, 0.75},
                                {"cut_in", 100, 1.5},
                                {"pedestrian_crossing", 40, 1.0},
                                {"pedestrian_crossing", 20, 0.5},
                                {"highway_obstacle", 100, 1.2},
                                {"tjunction", 40, 1.0}};
  int at_rest = 0;
  for (const Case& c : cases) {
    const SceneConfig config = example(c.family);
    const CellInput cell = defaults_at(config, c.speed_kph, c.ttc_s);
    const Scene scene(config, cell);
    const CellResult r = simulate_cell(config, cell, {});
    for (const StrategyOutcome& o : r.strategies) {
      if (!o.avoided || o.path.empty() || !(o.path.back().state.speed_mps() < kStoppedSpeed_mps)) continue;
      ++at_rest;
      const core::OrientedBox standing = scene.ego_box(o.path.back().state);
      const double end_s = o.path.back().t_s;
      for (const Actor& actor : scene.actors())
        for (double t = end_s; t <= end_s + config.simulation.horizon_s && t <= actor.motion().rest_time_s() + 1e-3;
             t += 1e-3)
          ASSERT_FALSE(core::contact(standing, actor.at(t).box).touching)
              << c.family << " " << c.speed_kph << " km/h, TTC " << c.ttc_s << " s: " << o.strategy << " meets the "
              << actor.body().name << " at " << t << " s";
    }
  }
  EXPECT_GT(at_rest, 3);
}

}  // namespace touch_at_rest_test
}  // namespace emrm::sim
