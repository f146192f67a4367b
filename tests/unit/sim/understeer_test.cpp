// Steady-state steering of the single-track Fiala model with the shipped parameters: a BMW 320i class
// sedan understeers (docs/physics.md).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {
namespace understeer_test {

constexpr double kDt = 0.01;
constexpr double kG = kGravity_mps2;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct SteadyTurn {
  double lateral_accel_mps2;  // a_y = V r
  double understeer_rad;      // delta - L r / V: steering beyond the Ackermann angle
  double yaw_rate_change;     // relative change of r over the last second: how steady the turn is
};

// Constant-speed, constant-steer turn on a flat road (the constant-speed variant of the steady-state
// circular test). The model has no drive: after every step the velocity is scaled back to
// `speed_mps`, as an ideal drive along the path that pays the tire drag would.
SteadyTurn steady_turn(const VehicleModel& model, double speed_mps, double steer_rad, double mu) {
  VehicleState s;
  s.vx_mps = speed_mps;
  s.steer_rad = steer_rad;
  double yaw_rate_a_second_ago = 0.0;
  for (int i = 1; i <= 1000; ++i) {
    s = model.step(s, {}, mu, kDt);
    const double scale = speed_mps / s.speed_mps();
    s.vx_mps *= scale;
    s.vy_mps *= scale;
    if (i == 900) yaw_rate_a_second_ago = s.yaw_rate_radps;
  }
  const double r = s.yaw_rate_radps;
  return {speed_mps * r, steer_rad - model.params().wheelbase_m() * r / speed_mps,
          std::abs(r - yaw_rate_a_second_ago) / r};
}

// Inverse of the normalised Fiala curve f(z) = z - z^2/3 + z^3/27 on [0, 3), by bisection.
double inverse_fiala(double f) {
  double lo = 0.0;
  double hi = 3.0;
  for (int i = 0; i < 100; ++i) {
    const double z = 0.5 * (lo + hi);
    (z - z * z / 3.0 + z * z * z / 27.0 < f ? lo : hi) = z;
  }
  return 0.5 * (lo + hi);
}

// Linear understeer gradient K = Wf/Cf - Wr/Cr in rad/g (static axle loads W).
double linear_gradient_rad_per_g(const VehicleParams& p) {
  const double weight = p.mass_kg * kG;
  const double front = weight * p.cg_to_rear_axle_m / p.wheelbase_m();
  return front / p.front_cornering_stiffness_n_per_rad - (weight - front) / p.rear_cornering_stiffness_n_per_rad;
}

// Steering angles at 22 m/s on dry road, lateral accelerations between 0.1 g and 0.4 g; the slope of
// the understeer angle over a_y is the measured understeer gradient. A BMW 320i class sedan
// understeers mildly: the gradient must be positive and of the order of passenger cars, 0.5-4 deg/g.
// Both axles share the normalised Fiala curve and carry Fy = W a_y / g, so the understeer angle is
// in closed form mu K f^-1(a_y / (mu g)): K itself at small a_y, growing towards the limit.
TEST(Understeer, SteadyStateSteerTestGivesAPassengerCarUndersteerGradient) {
  const SingleTrackFiala model{VehicleParams{}};
  const double mu = 1.0;
  const double speed = 22.0;
  const double gradient = linear_gradient_rad_per_g(model.params());
  double sum_a = 0.0;
  double sum_u = 0.0;
  double sum_aa = 0.0;
  double sum_au = 0.0;
  int points = 0;
  for (int i = 2; i < 30; ++i) {
    const double steer = 0.002 * i;
    const SteadyTurn turn = steady_turn(model, speed, steer, mu);
    const double a_g = turn.lateral_accel_mps2 / kG;
    if (a_g < 0.1 || a_g > 0.4) continue;
    ASSERT_LT(turn.yaw_rate_change, 1e-6) << "not steady at steer " << steer;
    EXPECT_NEAR(turn.understeer_rad, mu * gradient * inverse_fiala(a_g / mu),
                0.01 * std::abs(mu * gradient * inverse_fiala(a_g / mu)) + 2e-5)
        << "at a_y " << a_g << " g";
    sum_a += a_g;
    sum_u += turn.understeer_rad;
    sum_aa += a_g * a_g;
    sum_au += a_g * turn.understeer_rad;
    ++points;
  }
  ASSERT_GE(points, 5);
  // Least-squares slope of the understeer angle over a_y / g.
  const double slope_rad_per_g = (points * sum_au - sum_a * sum_u) / (points * sum_aa - sum_a * sum_a);
  const double slope_deg_per_g = slope_rad_per_g * kDegPerRad;
  EXPECT_GE(slope_deg_per_g, 0.5);
  EXPECT_LE(slope_deg_per_g, 4.0);
}

}  // namespace understeer_test
}  // namespace emrm::sim
