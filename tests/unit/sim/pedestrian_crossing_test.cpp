// The family "pedestrian_crossing" (docs/families.md) and a pedestrian's and a cyclist's harm by
// impact speed (docs/physics.md, "Pedestrians", "Cyclists"): the injury-risk curves against their
// sources' own published numbers, their loss levels, the street's layout from the factors, and what braking does for a
// pedestrian stepping out from behind a parked car.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "emrm/sim/crossing.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "emrm/sim/validity.hpp"
#include "outcomes.hpp"

namespace emrm::sim {
namespace pedestrian_crossing_test {

using test::outcome;

constexpr double kMph = 1.609344;  // km/h per mph

// The speed (km/h) at which a logistic risk 1 / (1 + exp(a − b·v)) reaches p.
double speed_at(double p, double intercept, double slope) { return (intercept + std::log(p / (1.0 - p))) / slope; }

// Hussain, Feng, Grzebieta, Brijs & Olivier 2019 (AAP 129:241–249), abstract: the risk of death
// "reaches 5% at … 30 km/h, 10% at 37 km/h, 50% at 59 km/h, 75% at 69 km/h and 90% at 80 km/h"
// (odds ratio 1.11 per km/h).
TEST(PedestrianHarm, DeathFollowsHussain2019) {
  const SeverityConfig c;
  const std::vector<std::pair<double, double>> published{{0.05, 30}, {0.10, 37}, {0.50, 59}, {0.75, 69}, {0.90, 80}};
  for (const auto& [p, kph] : published) {
    EXPECT_NEAR(speed_at(p, c.pedestrian_fatal_intercept, c.pedestrian_fatal_slope_per_kph), kph, 1.5) << p;
    EXPECT_NEAR(pedestrian_p_fatal(kph, c), p, 0.03) << kph;
  }
  EXPECT_NEAR(std::exp(c.pedestrian_fatal_slope_per_kph), 1.11, 1e-4);  // the published odds ratio
}

// Tefft 2013 (AAP 50:871–878), abstract: the average risk of a severe injury (AIS 4+) "reaches 10% at
// an impact speed of 17.1 mph, 25% at 24.9 mph, 50% at 33.0 mph, 75% at 40.8 mph, and 90% at 48.1 mph".
// Lubbe, Wu & Jeppsson 2022 (TSR 2:000006): a 10 % risk of MAIS3+ at a closing speed of 29 km/h.
TEST(PedestrianHarm, SeriousInjuryFollowsTefft2013) {
  const SeverityConfig c;
  const std::vector<std::pair<double, double>> published{
      {0.10, 17.1}, {0.25, 24.9}, {0.50, 33.0}, {0.75, 40.8}, {0.90, 48.1}};
  for (const auto& [p, mph] : published)
    EXPECT_NEAR(speed_at(p, c.pedestrian_serious_intercept, c.pedestrian_serious_slope_per_kph) / kMph, mph, 1.0) << p;
  EXPECT_NEAR(speed_at(0.10, c.pedestrian_serious_intercept, c.pedestrian_serious_slope_per_kph), 29.0, 2.0);
  // Both risks rise with the speed, and a fatal injury is rarer than a serious one below 70 km/h.
  for (double v = 1.0; v < 100.0; v += 1.0) {
    EXPECT_LT(pedestrian_p_fatal(v, c), pedestrian_p_fatal(v + 1.0, c));
    EXPECT_LT(pedestrian_p_serious(v, c), pedestrian_p_serious(v + 1.0, c));
    if (v < 70.0) {
      EXPECT_LT(pedestrian_p_fatal(v, c), pedestrian_p_serious(v, c)) << v;
    }
  }
}

// The loss levels: a person struck is injured (L6); L7 from the speed at which P(fatal) reaches
// l7_p_fatal (10 %: Hussain's 37 km/h).
TEST(PedestrianHarm, LevelsAreL6ThenL7FromTheTenPercentDeathSpeed) {
  const SeverityConfig c;
  const double l7_from_kph = speed_at(c.l7_p_fatal, c.pedestrian_fatal_intercept, c.pedestrian_fatal_slope_per_kph);
  EXPECT_NEAR(l7_from_kph, 37.0, 1.5);
  for (double kph = 1.0; kph < 90.0; kph += 0.5) {
    const ImpactAssessment a = with_road_user(ImpactAssessment{}, ActorKind::kPedestrian, kph / 3.6, c);
    EXPECT_EQ(a.loss_level, kph < l7_from_kph ? 6 : 7) << kph;
    // Hussain et al.'s model itself: odds of death 1.11 times higher per km/h, even odds at 59 km/h.
    EXPECT_NEAR(a.p_fatal, 1.0 / (1.0 + std::pow(1.11, 59.0 - kph)), 1e-3) << kph;
  }
  // The occupants' risk counts when it is the higher one.
  ImpactAssessment occupants;
  occupants.p_fatal = 0.5;
  EXPECT_EQ(with_road_user(occupants, ActorKind::kPedestrian, 5.0 / 3.6, c).p_fatal, 0.5);
  EXPECT_EQ(with_road_user(occupants, ActorKind::kPedestrian, 5.0 / 3.6, c).loss_level, 7);
}

// Lubbe, Wu & Jeppsson 2022 (Traffic Safety Research 2:000006): a cyclist's risk of MAIS3+ is
// logistic in the closing speed and the rider's age, logit = −7.467 + 0.079 v + 0.047 age; the
// abstract: "a 10% risk of sustaining at-least-serious injuries corresponds to a closing speed of 29
// km/h for pedestrians, 44 km/h for cyclists". Ours is that model for a 40-year-old rider.
TEST(CyclistHarm, SeriousInjuryIsLubbe2022ForAFortyYearOld) {
  const SeverityConfig c;
  EXPECT_NEAR(-c.cyclist_serious_intercept, -7.467 + 0.047 * 40.0, 1e-12);
  EXPECT_EQ(c.cyclist_serious_slope_per_kph, 0.079);
  EXPECT_NEAR(speed_at(0.10, c.cyclist_serious_intercept, c.cyclist_serious_slope_per_kph), 44.0, 1.5);
  // The paper's order of vulnerability: at every speed a cyclist fares better than a pedestrian, and
  // the cyclist's risk grows with the speed.
  for (double v = 0.0; v < 120.0; v += 1.0) {
    EXPECT_LT(cyclist_p_serious(v, c), pedestrian_p_serious(v, c)) << v;
    EXPECT_LT(cyclist_p_serious(v, c), cyclist_p_serious(v + 1.0, c)) << v;
  }
}

// A cyclist struck is a person injured (L6), L7 from the pedestrian's 10 % death speed; the serious
// risk is the cyclist's own curve, the occupants' when higher.
TEST(CyclistHarm, LevelsAndRisksOfACyclistStruck) {
  const SeverityConfig c;
  const double l7_from_kph = speed_at(c.l7_p_fatal, c.pedestrian_fatal_intercept, c.pedestrian_fatal_slope_per_kph);
  for (double kph = 1.0; kph < 90.0; kph += 0.5) {
    const ImpactAssessment a = with_road_user(ImpactAssessment{}, ActorKind::kCyclist, kph / 3.6, c);
    EXPECT_EQ(a.loss_level, kph < l7_from_kph ? 6 : 7) << kph;
    EXPECT_DOUBLE_EQ(a.p_mais3, cyclist_p_serious(kph, c)) << kph;
    EXPECT_DOUBLE_EQ(a.p_fatal, pedestrian_p_fatal(kph, c)) << kph;
  }
  ImpactAssessment occupants;
  occupants.p_mais3 = 0.9;
  EXPECT_EQ(with_road_user(occupants, ActorKind::kCyclist, 5.0 / 3.6, c).p_mais3, 0.9);
  EXPECT_TRUE(vulnerable_road_user(ActorKind::kCyclist));
  EXPECT_TRUE(vulnerable_road_user(ActorKind::kPedestrian));
  for (const ActorKind k : {ActorKind::kCar, ActorKind::kTruck, ActorKind::kAnimal, ActorKind::kStaticObject})
    EXPECT_FALSE(vulnerable_road_user(k));
}

SceneConfig crossing_scene() {
  SceneConfig config = load_scene_config(EMRM_SOURCE_DIR "/examples/pedestrian_crossing/scene.yaml");
  return config;
}

CellInput cell(const SceneConfig& config, double speed_kph, double ttc_s, double pedestrian_kph,
               std::string_view oncoming) {
  const FactorTable factors = scenario_factors(config);
  CellInput c = factors.defaults();
  c[0] = speed_kph;
  c[1] = ttc_s;
  c[*factors.find("pedestrian_speed_kph")] = pedestrian_kph;
  c[*factors.find("oncoming")] = factors[*factors.find("oncoming")].parse(oncoming);
  factors.validate(c);
  return c;
}

TEST(PedestrianCrossing, LaysOutThePedestrianTheParkedCarAndTheOncomingCar) {
  const SceneConfig config = crossing_scene();
  EXPECT_EQ(scenario_factors(config).key_list(), "speed_kph, ttc_s, mu, pedestrian_speed_kph, oncoming");
  const Scene alone(config, cell(config, 40, 1.2, 5, "none"));
  ASSERT_EQ(alone.actors().size(), 2u);
  const Scene met(config, cell(config, 40, 1.2, 5, "car"));
  ASSERT_EQ(met.actors().size(), 3u);
  const Actor& pedestrian = met.hazard();
  EXPECT_EQ(pedestrian.body().kind, ActorKind::kPedestrian);
  // Its near side v·TTC ahead; stepping out at the parked car's side and walking across, never resting.
  EXPECT_NEAR(pedestrian.at(0.0).box.center.x - config.crossing.pedestrian.width_m / 2.0, 40 / 3.6 * 1.2, 1e-12);
  EXPECT_NEAR(pedestrian.y_extent_at(0.0).second, -config.crossing.parked_gap_m, 1e-12);
  EXPECT_NEAR(pedestrian.y_extent_at(2.0).second - pedestrian.y_extent_at(0.0).second, 2.0 * 5 / 3.6, 1e-12);
  EXPECT_TRUE(std::isinf(pedestrian.motion().rest_time_s()));
  // The parked car stands beyond the right edge, just short of the pedestrian.
  const Actor& parked = met.actors()[1];
  EXPECT_LE(parked.y_extent_at(0.0).second, met.road().min_y_m);
  EXPECT_LT(parked.at(0.0).box.center.x, pedestrian.at(0.0).box.center.x);
  EXPECT_EQ(parked.at(3.0).box.center.x, parked.at(0.0).box.center.x);
  // The oncoming car in the left lane draws level with the pedestrian at t = TTC.
  const Actor& oncoming = met.actors()[2];
  EXPECT_NEAR(oncoming.motion().front_at(1.2).x, pedestrian.at(0.0).box.center.x, 1e-9);
  EXPECT_GT(oncoming.y_extent_at(0.0).first, config.crossing.lane_width_m);
  // A walking pedestrian keeps going: braking need not stop short of them for certain.
  EXPECT_FALSE(hazard_in_the_way(config, cell(config, 40, 1.2, 5, "none")));
}

// The contact check reads the actor's kind: the same body struck the same way harms a pedestrian by
// its curve, a cyclist by its own (lower) one, and a car of that mass by the occupants' Δv alone.
TEST(CyclistHarm, AContactIsJudgedByTheKindOfWhatIsStruck) {
  const SceneConfig config = crossing_scene();
  const Scene scene(config, cell(config, 40, 1.2, 5, "none"));
  const Actor& pedestrian = scene.hazard();
  const ActorState at = pedestrian.at(0.5);
  VehicleState s = scene.ego_initial();
  s.x_m = at.box.center.x - config.ego.length_m / 2.0 - pedestrian.body().length_m / 2.0 + 0.05;
  s.y_m = at.box.center.y;
  s.vx_mps = 30.0 / 3.6;
  ActorBody body = pedestrian.body();
  const ImpactAssessment walker = actor_impact(scene, body, s, at);
  body.kind = ActorKind::kCyclist;
  const ImpactAssessment rider = actor_impact(scene, body, s, at);
  body.kind = ActorKind::kCar;
  const ImpactAssessment object = actor_impact(scene, body, s, at);
  // The ego drives straight along x (heading 0, no side slip): its velocity is (vx, 0).
  const double closing_kph = std::hypot(s.vx_mps - at.velocity_mps.x, at.velocity_mps.y) * 3.6;
  EXPECT_GE(walker.loss_level, 6);
  EXPECT_GE(rider.loss_level, 6);
  EXPECT_NEAR(walker.p_mais3, pedestrian_p_serious(closing_kph, config.severity), 1e-12);
  EXPECT_NEAR(rider.p_mais3, cyclist_p_serious(closing_kph, config.severity), 1e-12);
  EXPECT_LT(rider.p_mais3, walker.p_mais3);
  EXPECT_LT(object.loss_level, 6);  // a 75 kg body barely changes the occupants' speed
}

// Braking for a pedestrian who steps out: where the car cannot stop, braking lowers the impact speed
// and with it the pedestrian's risk, never raising the level above doing nothing's (L7 at 40 km/h);
// and the later the pedestrian appears, the faster the braked car hits (monotone in TTC).
TEST(PedestrianCrossing, BrakingLowersTheImpactSpeedAndTheRisk) {
  const SceneConfig config = crossing_scene();
  double previous_kph = -1.0;
  for (const double ttc : {1.0, 0.85, 0.7}) {
    const CellResult r = simulate_cell(config, cell(config, 40, ttc, 5, "none"), {});
    const StrategyOutcome& stop = outcome(r, "emergency_stop");
    ASSERT_FALSE(stop.avoided) << ttc;
    EXPECT_EQ(r.unmitigated.loss_level, 7) << ttc;
    EXPECT_LT(stop.impact.impact_speed_mps * 3.6, 40.0) << ttc;
    EXPECT_LE(stop.impact.loss_level, r.unmitigated.loss_level) << ttc;
    EXPECT_LT(stop.impact.p_fatal, r.unmitigated.p_fatal) << ttc;
    EXPECT_GT(stop.impact.impact_speed_mps * 3.6, previous_kph) << ttc;
    previous_kph = stop.impact.impact_speed_mps * 3.6;
    // EMRM's choice is never worse than braking.
    EXPECT_FALSE(less_loss(stop.impact, outcome(r, "emrm").impact)) << ttc;
  }
}

}  // namespace pedestrian_crossing_test
}  // namespace emrm::sim
