#include "emrm/sim/loss.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {
namespace loss_test {

constexpr double kEgoMass = 1093.0;
constexpr double kEgoInertia = 1792.0;
constexpr double kTruckMass = 12000.0;
constexpr double kTruckInertia = 130000.0;

// The documented curves, written out independently of the code under test.
double expected_p_mais3(double dv) { return 1.0 / (1.0 + std::exp(4.591 - 0.185 * dv)); }
double expected_p_fatal(double dv) { return std::min(1.0, std::pow(dv / 31.74, 4.0)); }
// Thresholds from inverting the curves at 0.10.
const double kL6DeltaV = (4.591 - std::log(9.0)) / 0.185;
const double kL7DeltaV = 31.74 * std::pow(0.1, 0.25);

int expected_level(double dv) { return dv >= kL7DeltaV ? 7 : (dv >= kL6DeltaV ? 6 : 4); }

ImpactBody body(double mass, double inertia, core::Vec2 position, core::Vec2 velocity, double yaw_rate = 0.0) {
  return {mass, inertia, position, velocity, yaw_rate};
}

core::Contact contact_at(core::Vec2 point, core::Vec2 normal) {
  core::Contact c;
  c.touching = true;
  c.normal = normal;
  c.point = point;
  c.depth_m = 0.01;
  return c;
}

// A car driving +x at `speed` into a resting truck, hit at `offset_m` to the side of the car's CG
// (the truck's CG 1.25 m beyond the contact point, in line with the car's).
ImpactAssessment frontal_hit(double speed, double offset_m, const SeverityConfig& c = {}) {
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {speed, 0});
  const auto truck = body(kTruckMass, kTruckInertia, {3.5, 0}, {0, 0});
  return assess_impact(ego, truck, contact_at({2.25, offset_m}, {1, 0}), c);
}

struct Kinetics {
  core::Vec2 momentum;
  double angular_momentum = 0;  // about the origin
  double energy = 0;
};

// The two bodies after receiving ±impulse at `point`.
Kinetics after_impulse(ImpactBody a, ImpactBody b, core::Vec2 point, core::Vec2 impulse_on_a) {
  a.velocity_mps = a.velocity_mps + impulse_on_a * (1.0 / a.mass_kg);
  a.yaw_rate_radps += (point - a.position_m).cross(impulse_on_a) / a.yaw_inertia_kgm2;
  b.velocity_mps = b.velocity_mps - impulse_on_a * (1.0 / b.mass_kg);
  b.yaw_rate_radps -= (point - b.position_m).cross(impulse_on_a) / b.yaw_inertia_kgm2;
  Kinetics k;
  for (const auto& x : {a, b}) {
    k.momentum = k.momentum + x.velocity_mps * x.mass_kg;
    k.angular_momentum += x.mass_kg * x.position_m.cross(x.velocity_mps) + x.yaw_inertia_kgm2 * x.yaw_rate_radps;
    k.energy += 0.5 * x.mass_kg * x.velocity_mps.dot(x.velocity_mps) +
                0.5 * x.yaw_inertia_kgm2 * x.yaw_rate_radps * x.yaw_rate_radps;
  }
  return k;
}

// ---- closed forms --------------------------------------------------------------------------------

// The unmitigated reference is the no-action trajectory's contact, assessed by the impact model
// every strategy's contact goes through: the hit lands off the truck's CG (the ego's lane is not
// the truck's middle), so rotation lowers the effective mass and Δv lies below the central
// formula's (the one the reference used before), and the risks are the curves at that Δv.
TEST(Loss, UnmitigatedReferenceIsTheNoActionContactThroughTheImpactModel) {
  const SceneConfig config;
  const auto model = make_vehicle_model("single_track_fiala", config.ego);
  for (const double speed_kph : {30.0, 50.0, 72.0}) {
    const Scene scene(config, CellInput{speed_kph, 1.0, 1.0, 3.0, 10.0});
    const RolloutResult coast = no_action_rollout(scene, *model);
    ASSERT_EQ(coast.termination, Termination::kContact) << speed_kph;
    const auto& impact = coast.impact;
    const double v = speed_kph / 3.6;
    const double central = central_delta_v_mps(kEgoMass, kTruckMass, v, 0.0);
    EXPECT_NEAR(impact.impact_speed_mps, v, 1e-6);
    EXPECT_LT(impact.delta_v_mps, central);
    EXPECT_GT(impact.delta_v_mps, 0.5 * central);
    EXPECT_NEAR(coast.end_time_s, 1.0, 1e-4);  // TTC: distance over speed, the truck moves across
    EXPECT_NEAR(impact.p_mais3, expected_p_mais3(impact.delta_v_mps), 1e-12);
    EXPECT_NEAR(impact.p_fatal, expected_p_fatal(impact.delta_v_mps), 1e-12);
    EXPECT_EQ(impact.loss_level, expected_level(impact.delta_v_mps)) << speed_kph << " km/h";
  }
}

TEST(Loss, CentralDeltaVSharesTheClosingSpeedByMass) {
  EXPECT_NEAR(central_delta_v_mps(1000, 3000, 10, 0), 7.5, 1e-12);
  EXPECT_NEAR(central_delta_v_mps(1000, 3000, -10, 0), 7.5, 1e-12);
  EXPECT_NEAR(central_delta_v_mps(1000, 1000, 10, 0.5), 7.5, 1e-12);
}

TEST(Loss, LossLevelThresholdsAreTheInvertedRiskCurves) {
  const SeverityConfig c;
  const auto level = [&](double dv) { return loss_level(true, false, p_mais3(dv, c), p_fatal(dv, c), c); };
  ASSERT_LT(kL6DeltaV, kL7DeltaV);
  EXPECT_EQ(level(kL6DeltaV * (1 - 1e-9)), 4);
  EXPECT_EQ(level(kL6DeltaV * (1 + 1e-9)), 6);
  EXPECT_EQ(level(kL7DeltaV * (1 - 1e-9)), 6);
  EXPECT_EQ(level(kL7DeltaV * (1 + 1e-9)), 7);
  EXPECT_NEAR(p_mais3(kL6DeltaV, c), 0.1, 1e-12);
  EXPECT_NEAR(p_fatal(kL7DeltaV, c), 0.1, 1e-12);
}

TEST(Loss, RiskCurvesFollowTheirFormulasAndStayProbabilities) {
  const SeverityConfig c;
  for (double dv = 0.0; dv <= 100.0; dv += 0.25) {
    EXPECT_NEAR(p_mais3(dv, c), expected_p_mais3(dv), 1e-12);
    EXPECT_NEAR(p_fatal(dv, c), expected_p_fatal(dv), 1e-12);
    EXPECT_GE(p_mais3(dv, c), 0.0);
    EXPECT_LE(p_mais3(dv, c), 1.0);
    EXPECT_GE(p_fatal(dv, c), 0.0);
    EXPECT_LE(p_fatal(dv, c), 1.0);
  }
  EXPECT_EQ(p_fatal(0.0, c), 0.0);
  EXPECT_EQ(p_fatal(1e6, c), 1.0);
  EXPECT_LE(p_mais3(1e6, c), 1.0);
}

// ---- loss levels ---------------------------------------------------------------------------------

TEST(Loss, LossLevelOfOutcomes) {
  const SeverityConfig c;
  EXPECT_EQ(loss_level(false, false, 0.0, 0.0, c), 0);
  EXPECT_EQ(loss_level(false, true, 0.0, 0.0, c), 4);  // road departure without contact
  EXPECT_EQ(loss_level(true, false, 0.0, 0.0, c), 4);
  EXPECT_EQ(loss_level(true, false, 0.10, 0.0, c), 6);
  EXPECT_EQ(loss_level(true, false, 0.5, 0.10, c), 7);
}

TEST(Loss, LossLevelIsMonotoneInDeltaV) {
  const SeverityConfig c;
  int previous = 0;
  for (double dv = 0.0; dv <= 40.0; dv += 0.01) {
    const int level = loss_level(true, false, p_mais3(dv, c), p_fatal(dv, c), c);
    EXPECT_GE(level, previous) << dv;
    EXPECT_TRUE(level == 4 || level == 6 || level == 7);
    previous = level;
  }
  EXPECT_EQ(previous, 7);
}

// ---- impacts -------------------------------------------------------------------------------------

TEST(Loss, HeadOnHitThroughBothCentresEqualsTheCentralFormula) {
  const SeverityConfig c;
  for (const double v : {5.0, 13.9, 20.0}) {
    const auto impact = frontal_hit(v, 0.0, c);
    const double dv = central_delta_v_mps(kEgoMass, kTruckMass, v, 0.0);
    EXPECT_NEAR(impact.delta_v_mps, dv, 1e-12);
    EXPECT_NEAR(impact.impact_speed_mps, v, 1e-12);
    EXPECT_NEAR(impact.p_mais3, expected_p_mais3(dv), 1e-12);
    EXPECT_NEAR(impact.p_fatal, expected_p_fatal(dv), 1e-12);
    EXPECT_EQ(impact.loss_level, expected_level(dv));
  }
  // The truck moving towards the car adds to the closing speed.
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {10, 0});
  const auto truck = body(kTruckMass, kTruckInertia, {3.5, 0}, {-2, 0});
  EXPECT_NEAR(assess_impact(ego, truck, contact_at({2.25, 0}, {1, 0}), c).delta_v_mps,
              central_delta_v_mps(kEgoMass, kTruckMass, 12.0, 0.0), 1e-12);
}

TEST(Loss, AnImmovableObstacleTakesAllTheClosingSpeed) {
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {10, 0});
  const auto wall = body(0.0, 0.0, {3, 0}, {0, 0});
  EXPECT_NEAR(assess_impact(ego, wall, contact_at({2.25, 0}, {1, 0}), {}).delta_v_mps, 10.0, 1e-12);
}

TEST(Loss, OffCentreAndGlancingHitsAreMilderThanCentral) {
  const SeverityConfig c;
  const double v = 15.0;
  const double central = frontal_hit(v, 0.0, c).delta_v_mps;
  double previous = central;
  for (const double offset : {0.2, 0.5, 0.8}) {  // further off the CG: the car spins away more
    const double dv = frontal_hit(v, offset, c).delta_v_mps;
    EXPECT_LT(dv, previous) << offset;
    previous = dv;
  }
  // Glancing: the normal turns away from the velocity.
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {v, 0});
  const auto truck = body(kTruckMass, kTruckInertia, {3.5, 0}, {0, 0});
  previous = central;
  for (const double angle_deg : {20.0, 45.0, 70.0}) {
    const double a = angle_deg * std::numbers::pi / 180;
    const double dv = assess_impact(ego, truck, contact_at({2.25, 0}, {std::cos(a), -std::sin(a)}), c).delta_v_mps;
    EXPECT_LT(dv, previous) << angle_deg;
    previous = dv;
  }
}

TEST(Loss, PerfectlyElasticCentralImpactDoublesDeltaV) {
  SeverityConfig plastic, elastic;
  elastic.restitution = 1.0;
  for (const double v : {4.0, 12.0})
    EXPECT_NEAR(frontal_hit(v, 0, elastic).delta_v_mps, 2 * frontal_hit(v, 0, plastic).delta_v_mps, 1e-12);
}

TEST(Loss, SeparatingBodiesGiveNoDeltaV) {
  const SeverityConfig c;
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {-3, 0});  // backing away from the truck
  const auto truck = body(kTruckMass, kTruckInertia, {3.5, 0}, {0, 0});
  const auto impact = assess_impact(ego, truck, contact_at({2.25, 0.3}, {1, 0}), c);
  EXPECT_EQ(impact.delta_v_mps, 0.0);
  EXPECT_EQ(impact.ego_impulse_ns, (core::Vec2{0, 0}));
  EXPECT_EQ(impact.loss_level, 4);  // they do touch
  EXPECT_NEAR(impact.impact_speed_mps, 3.0, 1e-12);
  // Both moving the same way, the truck faster: also separating.
  const auto fleeing = body(kTruckMass, kTruckInertia, {3.5, 0}, {5, 0});
  EXPECT_EQ(
      assess_impact(body(kEgoMass, kEgoInertia, {0, 0}, {4, 0}), fleeing, contact_at({2.25, 0}, {1, 0}), c).delta_v_mps,
      0.0);
}

TEST(Loss, NoContactIsNoImpact) {
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {10, 0});
  const auto truck = body(kTruckMass, kTruckInertia, {3.5, 0}, {0, 0});
  const auto impact = assess_impact(ego, truck, core::Contact{}, {});
  EXPECT_EQ(impact.delta_v_mps, 0.0);
  EXPECT_EQ(impact.p_mais3, 0.0);
  EXPECT_EQ(impact.p_fatal, 0.0);
  EXPECT_EQ(impact.loss_level, 0);
}

TEST(Loss, DeltaVIsMonotoneInImpactSpeed) {
  const SeverityConfig c;
  const core::Vec2 normals[] = {{1, 0}, {std::cos(0.6), -std::sin(0.6)}, {std::cos(1.2), std::sin(1.2)}};
  for (const auto& n : normals)
    for (const double offset : {0.0, 0.4, -0.7}) {
      double previous = 0.0;
      for (double v = 0.0; v <= 30.0; v += 0.5) {
        const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {v, 0}, 0.2);
        const auto truck = body(kTruckMass, kTruckInertia, {3.5, 1.0}, {0, -1.5});
        const double dv = assess_impact(ego, truck, contact_at({2.25, offset}, n), c).delta_v_mps;
        EXPECT_GE(dv, previous - 1e-12) << "v = " << v;
        previous = dv;
      }
    }
}

TEST(Loss, ImpulseConservesMomentumAndRespectsFriction) {
  SeverityConfig c;
  c.contact_friction = 0.3;
  const auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {14, 3}, 0.4);
  const auto truck = body(kTruckMass, kTruckInertia, {4.0, 2.0}, {0, -2.8}, 0.0);
  const core::Vec2 n{std::cos(0.3), std::sin(0.3)};
  const core::Vec2 point{2.2, 0.9};
  const auto impact = assess_impact(ego, truck, contact_at(point, n), c);
  ASSERT_GT(impact.delta_v_mps, 0.0);
  // The two velocity changes balance: m_a Δv_a = −m_b Δv_b.
  const core::Vec2 dv_ego = impact.ego_impulse_ns * (1.0 / ego.mass_kg);
  const core::Vec2 dv_truck = impact.ego_impulse_ns * (-1.0 / truck.mass_kg);
  EXPECT_NEAR(ego.mass_kg * dv_ego.x + truck.mass_kg * dv_truck.x, 0.0, 1e-9);
  EXPECT_NEAR(ego.mass_kg * dv_ego.y + truck.mass_kg * dv_truck.y, 0.0, 1e-9);
  EXPECT_NEAR(dv_ego.norm(), impact.delta_v_mps, 1e-12);
  // Linear and angular momentum of the pair are unchanged; energy is not created.
  const Kinetics before = after_impulse(ego, truck, point, {0, 0});
  const Kinetics after = after_impulse(ego, truck, point, impact.ego_impulse_ns);
  EXPECT_NEAR(after.momentum.x, before.momentum.x, 1e-8);
  EXPECT_NEAR(after.momentum.y, before.momentum.y, 1e-8);
  EXPECT_NEAR(after.angular_momentum, before.angular_momentum, 1e-7);
  EXPECT_LT(after.energy, before.energy);
  // The impulse pushes the ego back along the normal and lies inside the friction cone.
  const core::Vec2 t{-n.y, n.x};
  EXPECT_LT(impact.ego_impulse_ns.dot(n), 0.0);
  EXPECT_LE(std::abs(impact.ego_impulse_ns.dot(t)), c.contact_friction * -impact.ego_impulse_ns.dot(n) + 1e-9);
}

TEST(Loss, NormalImpulseWithRotationStopsOrReversesTheContactPoint) {
  // Without friction the impulse makes the normal relative velocity at the contact point −e times
  // what it was, rotation included: this pins down the rotational effective mass.
  for (const double e : {0.0, 0.5, 1.0}) {
    SeverityConfig c;
    c.restitution = e;
    c.contact_friction = 0.0;
    auto ego = body(kEgoMass, kEgoInertia, {0, 0}, {12, 1}, 0.3);
    auto truck = body(kTruckMass, kTruckInertia, {3.0, 2.5}, {0, -2.0}, -0.1);
    const core::Vec2 n{std::cos(0.4), std::sin(0.4)};
    const core::Vec2 p{2.0, 0.7};
    const auto point_velocity = [&](const ImpactBody& b) {
      const core::Vec2 r = p - b.position_m;
      return b.velocity_mps + core::Vec2{-r.y, r.x} * b.yaw_rate_radps;
    };
    const double closing_before = (point_velocity(ego) - point_velocity(truck)).dot(n);
    ASSERT_GT(closing_before, 0.0);
    const auto impact = assess_impact(ego, truck, contact_at(p, n), c);
    const core::Vec2 j = impact.ego_impulse_ns;
    ego.velocity_mps = ego.velocity_mps + j * (1.0 / ego.mass_kg);
    ego.yaw_rate_radps += (p - ego.position_m).cross(j) / ego.yaw_inertia_kgm2;
    truck.velocity_mps = truck.velocity_mps - j * (1.0 / truck.mass_kg);
    truck.yaw_rate_radps -= (p - truck.position_m).cross(j) / truck.yaw_inertia_kgm2;
    const double closing_after = (point_velocity(ego) - point_velocity(truck)).dot(n);
    EXPECT_NEAR(closing_after, -e * closing_before, 1e-9) << "e = " << e;
    if (e == 1.0) {
      const Kinetics k0 = after_impulse(body(kEgoMass, kEgoInertia, {0, 0}, {12, 1}, 0.3),
                                        body(kTruckMass, kTruckInertia, {3.0, 2.5}, {0, -2.0}, -0.1), p, {0, 0});
      const Kinetics k1 = after_impulse(body(kEgoMass, kEgoInertia, {0, 0}, {12, 1}, 0.3),
                                        body(kTruckMass, kTruckInertia, {3.0, 2.5}, {0, -2.0}, -0.1), p, j);
      EXPECT_NEAR(k1.energy, k0.energy, 1e-6 * k0.energy);  // elastic and frictionless: energy kept
    }
  }
}

TEST(Loss, ImpactFromTheSceneGeometry) {
  // The ego's front 0.1 m into the truck's side at t = 0 of a 50 km/h cell, found by the contact
  // test: the hit is on the ego's axis but off the truck's CG, so the truck turns and the ego's
  // Δv is below the central one (friction from the truck's crossing motion adds less than that).
  const SceneConfig config;
  const Scene scene(config, CellInput{50.0, 1.0, 1.0, 1.0, 10.0});
  auto s = scene.ego_initial();
  s.x_m += scene.initial_distance_m() + 0.1;
  const auto truck = scene.hazard_at(0.0);
  const auto c = core::contact(scene.ego_box(s), truck.box);
  ASSERT_TRUE(c.touching);
  const auto ego_body = body(config.ego.mass_kg, config.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, {s.vx_mps, 0});
  const auto truck_body =
      body(config.truck.mass_kg, config.truck.yaw_inertia_kgm2, truck.box.center, truck.velocity_mps);
  const auto impact = assess_impact(ego_body, truck_body, c, config.severity);
  const double central = central_delta_v_mps(kEgoMass, kTruckMass, scene.initial_speed_mps(), 0.0);
  EXPECT_GT(impact.delta_v_mps, 0.5 * central);
  EXPECT_LE(impact.delta_v_mps, central + 1e-9);
  EXPECT_EQ(impact.impact_speed_mps, scene.initial_speed_mps());
}

}  // namespace loss_test
}  // namespace emrm::sim
