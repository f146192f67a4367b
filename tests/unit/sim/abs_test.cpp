// ABS braking of the single-track Fiala model (docs/physics.md): a braked rolling axle keeps the
// lateral force of a brush tire held at the sliding limit of combined slip, min(mu Fz, C |tan a| / 3).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {
namespace abs_test {

constexpr double kDt = 0.01;
constexpr double kG = kGravity_mps2;

double kph(double v) { return v / 3.6; }

VehicleState moving(double speed_mps) {
  VehicleState s;
  s.vx_mps = speed_mps;
  return s;
}

using ControlLaw = std::function<Control(double t_s)>;
using Visitor = std::function<void(const VehicleState& before, const Control& u, const VehicleState& after)>;

// Steps until the car has stopped or `max_s` has passed; `visit` sees every step.
VehicleState run(const VehicleModel& model, VehicleState s, const ControlLaw& law, double mu, double max_s,
                 const Visitor& visit = {}) {
  const int steps = static_cast<int>(std::lround(max_s / kDt));
  for (int i = 0; i < steps && s.speed_mps() > 0.0; ++i) {
    const Control u = law(i * kDt);
    const VehicleState next = model.step(s, u, mu, kDt);
    if (visit) visit(s, u, next);
    s = next;
  }
  return s;
}

// The ABS guarantee for one rolling axle: min(mu Fz, C |tan(alpha)| / 3).
double abs_floor_n(const AxleForces& axle, double stiffness_n_per_rad, double mu) {
  return std::min(mu * axle.normal_load_n, stiffness_n_per_rad * std::abs(std::tan(axle.slip_angle_rad)) / 3.0);
}

// Fiala lateral force magnitude for |tan(alpha)| = t under the lateral limit `limit_n`.
double fiala_n(double t, double stiffness_n_per_rad, double limit_n) {
  const double z = stiffness_n_per_rad * t / limit_n;
  return z >= 3.0 ? limit_n : limit_n * (z - z * z / 3.0 + z * z * z / 27.0);
}

// Straight ahead with a lateral velocity: both axles see tan(alpha) = vy / vx.
VehicleState sideslipping(double speed_mps, double tan_alpha) {
  VehicleState s = moving(speed_mps);
  s.vy_mps = speed_mps * tan_alpha;
  return s;
}

// Full braking while steering left at the full rate: the ABS leaves the front axle lateral grip, so
// the car turns towards the steering. Without it a fully braked axle has no lateral force, and the
// braking force of the steered wheel, Fxf sin(d) < 0, yaws the car to the right.
TEST(Abs, FullBrakingWhileSteeringLeftTurnsTheCarLeft) {
  const SingleTrackFiala model{VehicleParams{}};
  const Control u{.steer_rate_radps = model.params().max_steer_rate_radps, .brake = 1.0};
  for (double mu : {1.0, 0.5}) {
    const double v = kph(72.0);
    double min_yaw_rate = 0.0;
    double max_yaw_rate = 0.0;
    const VehicleState end = run(
        model, moving(v), [&](double) { return u; }, mu, 3.0 * v / (mu * kG),
        [&](const VehicleState&, const Control&, const VehicleState& after) {
          min_yaw_rate = std::min(min_yaw_rate, after.yaw_rate_radps);
          max_yaw_rate = std::max(max_yaw_rate, after.yaw_rate_radps);
        });
    EXPECT_EQ(end.speed_mps(), 0.0) << mu;
    // It yaws towards the steering, never against it, and stops turned left, left of y = 0 where a
    // straight stop ends.
    EXPECT_GE(min_yaw_rate, 0.0) << mu;
    EXPECT_GT(max_yaw_rate, 0.0) << mu;
    EXPECT_GT(end.yaw_rad, 0.0) << mu;
    EXPECT_GT(end.y_m, 0.0) << mu;
  }
}

// Under full braking with steering every rolling axle stays on or inside its friction circle and
// keeps at least the ABS lateral floor.
TEST(Abs, FrictionCircleHoldsAndTheLateralFloorIsKeptUnderFullBrakingWithSteering) {
  const SingleTrackFiala model{VehicleParams{}};
  const VehicleParams& p = model.params();
  const double rate = p.max_steer_rate_radps;
  const std::vector<ControlLaw> manoeuvres{
      [&](double) { return Control{.steer_rate_radps = rate, .brake = 1.0}; },
      [&](double t) {
        return Control{.steer_rate_radps = std::sin(2.0 * std::numbers::pi * 0.5 * t) > 0 ? rate : -rate, .brake = 1.0};
      },
  };
  for (double mu : {0.3, 0.5, 1.0}) {
    for (std::size_t m = 0; m < manoeuvres.size(); ++m) {
      int steps = 0;
      double worst_resultant = 0.0;  // |F| / (mu Fz)
      double worst_lateral = 1.0;    // |Fy| / Fy_abs where Fy_abs > 0
      run(model, moving(kph(72.0)), manoeuvres[m], mu, 3.0 * kph(72.0) / (mu * kG),
          [&](const VehicleState& before, const Control& u, const VehicleState&) {
            ++steps;
            const TireForces f = model.tire_forces(before, u, mu);
            const auto check = [&](const AxleForces& axle, double stiffness) {
              const double grip = mu * axle.normal_load_n;
              worst_resultant = std::max(worst_resultant, std::hypot(axle.longitudinal_n, axle.lateral_n) / grip);
              const double floor = abs_floor_n(axle, stiffness, mu);
              if (floor > 0.0) worst_lateral = std::min(worst_lateral, std::abs(axle.lateral_n) / floor);
            };
            check(f.front, p.front_cornering_stiffness_n_per_rad);
            check(f.rear, p.rear_cornering_stiffness_n_per_rad);
          });
      EXPECT_GT(steps, 100) << "mu " << mu << ", manoeuvre " << m;
      EXPECT_LE(worst_resultant, 1.0 + 1e-12) << "mu " << mu << ", manoeuvre " << m;
      EXPECT_GE(worst_lateral, 1.0 - 1e-12) << "mu " << mu << ", manoeuvre " << m;
    }
  }
}

// The ABS of one axle, written out: the lateral floor and the braking force it leaves.
struct AbsAxle {
  double floor_n;
  double braking_n;  // magnitude
  bool capped;
};
AbsAxle abs_axle(double grip_n, double stiffness_n_per_rad, double tan_alpha, double brake) {
  const double floor = std::min(grip_n, stiffness_n_per_rad * std::abs(tan_alpha) / 3.0);
  const double cap = std::sqrt(grip_n * grip_n - floor * floor);
  return {floor, std::min(brake * grip_n, cap), brake * grip_n > cap};
}

// Below the cap an axle is the plain friction circle with Fiala; at the cap the ABS brakes with
// sqrt((mu Fz)^2 - Fy_abs^2) and slides at Fy_abs. The load transfer follows the commanded
// deceleration, and where the ABS capped it, once more the deceleration the capped forces give.
TEST(Abs, ForcesFollowTheCombinedSlipClosedForm) {
  const SingleTrackFiala model{VehicleParams{}};
  const VehicleParams& p = model.params();
  const double mu = 0.8;
  const double tan_alpha = 0.02;
  const double cf = p.front_cornering_stiffness_n_per_rad;
  const double cr = p.rear_cornering_stiffness_n_per_rad;
  const double weight = p.mass_kg * kG;
  // Front load for a deceleration `decel` (quasi-static pitch balance).
  const auto front_load = [&](double decel) {
    return weight * (p.cg_to_rear_axle_m + decel / kG * p.cg_height_m) / p.wheelbase_m();
  };
  const VehicleState s = sideslipping(20.0, tan_alpha);
  for (double brake : {0.0, 0.3, 1.0}) {
    const TireForces f = model.tire_forces(s, {.brake = brake}, mu);
    double load = front_load(brake * mu * kG);
    AbsAxle front = abs_axle(mu * load, cf, tan_alpha, brake);
    AbsAxle rear = abs_axle(mu * (weight - load), cr, tan_alpha, brake);
    ASSERT_EQ(front.capped, brake == 1.0);
    ASSERT_EQ(rear.capped, brake == 1.0);
    if (front.capped || rear.capped) {
      load = front_load((front.braking_n + rear.braking_n) / p.mass_kg);
      front = abs_axle(mu * load, cf, tan_alpha, brake);
      rear = abs_axle(mu * (weight - load), cr, tan_alpha, brake);
    }
    EXPECT_NEAR(f.front.normal_load_n, load, 1e-9 * weight) << brake;
    EXPECT_NEAR(f.rear.normal_load_n, weight - load, 1e-9 * weight) << brake;
    const auto check = [&](const AxleForces& axle, const AbsAxle& expected, double stiffness, const char* name) {
      const double grip = mu * axle.normal_load_n;
      EXPECT_NEAR(axle.longitudinal_n, -expected.braking_n, 1e-9 * grip) << name << " " << brake;
      if (expected.capped) {
        EXPECT_NEAR(axle.lateral_n, -expected.floor_n, 1e-9 * grip) << name;
        EXPECT_TRUE(axle.saturated) << name;
      } else {
        const double limit = grip * std::sqrt(1.0 - brake * brake);
        EXPECT_NEAR(axle.lateral_n, -fiala_n(tan_alpha, stiffness, limit), 1e-9 * grip) << name;
        EXPECT_FALSE(axle.saturated) << name;
      }
    };
    check(f.front, front, cf, "front");
    check(f.rear, rear, cr, "rear");
  }
}

// As the brake goes from 0.95 to 1 the lateral force moves smoothly onto the ABS floor: per step
// of the brake it changes by at most (mu Fz)^2 / Fy_abs * d(brake) (the Fiala force changes at most
// as fast as its limit sqrt(1 - b^2) mu Fz, and the ABS keeps that limit above Fy_abs), plus the
// change of mu Fz itself from the load transfer.
TEST(Abs, LateralForceIsContinuousAsTheBrakeGoesToFull) {
  const SingleTrackFiala model{VehicleParams{}};
  const VehicleParams& p = model.params();
  const double mu = 1.0;
  // A rear floor of a fifth of the static rear grip (less at the front): the ABS takes over inside
  // [0.95, 1], where sqrt(1 - b^2) falls from 0.31 to 0.
  const double rear_static_grip = mu * p.mass_kg * kG * p.cg_to_front_axle_m / p.wheelbase_m();
  const VehicleState s = sideslipping(20.0, 3.0 * 0.2 * rear_static_grip / p.rear_cornering_stiffness_n_per_rad);
  const int steps = 500;
  const double step = 0.05 / steps;
  double worst = 0.0;  // |change of Fy| / bound
  TireForces before = model.tire_forces(s, {.brake = 0.95}, mu);
  for (int i = 1; i <= steps; ++i) {
    const TireForces after = model.tire_forces(s, {.brake = i == steps ? 1.0 : 0.95 + i * step}, mu);
    const auto check = [&](const AxleForces& a, const AxleForces& b, double stiffness) {
      const double grip = mu * std::max(a.normal_load_n, b.normal_load_n);
      const double bound =
          grip * grip / abs_floor_n(b, stiffness, mu) * step + mu * std::abs(b.normal_load_n - a.normal_load_n);
      worst = std::max(worst, std::abs(b.lateral_n - a.lateral_n) / bound);
    };
    check(before.front, after.front, p.front_cornering_stiffness_n_per_rad);
    check(before.rear, after.rear, p.rear_cornering_stiffness_n_per_rad);
    before = after;
  }
  EXPECT_LE(worst, 1.0 + 1e-9);
  // At full braking both axles slide at the floor: lateral grip is left.
  EXPECT_NEAR(std::abs(before.front.lateral_n), abs_floor_n(before.front, p.front_cornering_stiffness_n_per_rad, mu),
              1e-9 * before.front.normal_load_n);
  EXPECT_NEAR(std::abs(before.rear.lateral_n), abs_floor_n(before.rear, p.rear_cornering_stiffness_n_per_rad, mu),
              1e-9 * before.rear.normal_load_n);
  EXPECT_GT(std::abs(before.rear.lateral_n), 0.1 * mu * before.rear.normal_load_n);
}

}  // namespace abs_test
}  // namespace emrm::sim
