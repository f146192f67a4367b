// Single-track model with Fiala brush tires (docs/physics.md). Equations, body frame:
//   m (vx' - r vy) = Fxf cos(d) - Fyf sin(d) + Fxr
//   m (vy' + r vx) = Fxf sin(d) + Fyf cos(d) + Fyr
//   Iz r'          = lf (Fxf sin(d) + Fyf cos(d)) - lr Fyr
// with wheel-frame axle forces (Fx, Fy), loads from quasi-static longitudinal load transfer, a
// friction circle per axle and ABS braking that keeps a combined-slip lateral floor on rolling axles.
// Below kinematic_blend_speed_mps the rates blend into the kinematic model.

#include <algorithm>
#include <cmath>

#include "emrm/core/trig.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {
namespace {

// A lateral limit below this counts as "no lateral grip left" (the axle brakes at the friction limit).
constexpr double kNoGrip_n = 1e-6;

struct LateralForce {
  double force_n;
  bool sliding;
};

// Fiala brush tire. With z = C |tan(alpha)| / Fy_max the force is Fy_max (z - z^2/3 + z^3/27) against
// the slip up to z = 3 (the sliding angle tan(alpha_sl) = 3 Fy_max / C) and Fy_max beyond.
LateralForce fiala_lateral(double tan_alpha, double stiffness_n_per_rad, double limit_n) {
  if (limit_n <= kNoGrip_n) return {0.0, true};
  const double z = stiffness_n_per_rad * std::abs(tan_alpha) / limit_n;
  if (z >= 3.0) return {-std::copysign(limit_n, tan_alpha), true};
  const double magnitude = limit_n * z * (1.0 - z / 3.0 + z * z / 27.0);
  return {-std::copysign(magnitude, tan_alpha), false};
}

// Wheel-frame forces of a rolling (not locked) axle.
struct RollingAxle {
  double longitudinal_n;
  double lateral_n;
  double lateral_limit_n;
  bool saturated;
  bool capped;  // the ABS braked with less than the commanded force
};

// A rolling axle braked with `commanded_n` (signed, |commanded_n| = brake * grip) under ABS. The ABS
// holds the tire at the sliding limit of the isotropic combined-slip brush model (theta*sigma = 1),
// where the resultant grip_n points along the slip, so its lateral part is C tan(alpha) / 3: the
// braking force is capped at sqrt(grip^2 - Fy_abs^2), Fy_abs = min(grip, C |tan(alpha)| / 3). Below the
// cap this is the plain friction circle with Fiala; at the cap the Fiala force under the remaining
// limit would be below Fy_abs, so the axle slides at Fy_abs (continuous in the brake: both meet there).
RollingAxle abs_axle(double commanded_n, double tan_alpha, double stiffness_n_per_rad, double grip_n) {
  if (commanded_n != 0.0) {  // without brake pressure there is nothing for the ABS to release
    const double floor_n = std::min(grip_n, stiffness_n_per_rad * std::abs(tan_alpha) / 3.0);
    const double cap_n = std::sqrt(std::max(0.0, grip_n * grip_n - floor_n * floor_n));
    if (std::abs(commanded_n) > cap_n)
      return {std::copysign(cap_n, commanded_n), -std::copysign(floor_n, tan_alpha), floor_n, true, true};
  }
  const double limit_n = std::sqrt(std::max(0.0, grip_n * grip_n - commanded_n * commanded_n));
  const LateralForce fy = fiala_lateral(tan_alpha, stiffness_n_per_rad, limit_n);
  return {commanded_n, fy.force_n, limit_n, fy.sliding, false};
}

void set_rolling(AxleForces& axle, const RollingAxle& forces) {
  axle.longitudinal_n = forces.longitudinal_n;
  axle.lateral_n = forces.lateral_n;
  axle.lateral_limit_n = forces.lateral_limit_n;
  axle.saturated = forces.saturated;
}

// Everything the derivative and the diagnostics need, computed once per evaluation.
struct AxleSolution {
  TireForces tires{};  // wheel frames; slip angles left at zero (they need atan2, diagnostics only)
  double front_lateral_velocity_mps = 0.0;  // wheel frame
  double front_rolling_velocity_mps = 0.0;
  double rear_lateral_velocity_mps = 0.0;
  double force_x_n = 0.0;  // body frame, both axles
  double force_y_n = 0.0;
  double yaw_moment_nm = 0.0;
  double commanded_accel_mps2 = 0.0;  // longitudinal, from the commanded (braking) forces
};

AxleSolution solve_axles(const VehicleParams& p, const VehicleState& s, const Control& u, double mu) {
  const double lf = p.cg_to_front_axle_m;
  const double lr = p.cg_to_rear_axle_m;
  const double wheelbase = lf + lr;
  const double m = p.mass_kg;
  const double g = kGravity_mps2;
  const double brake = std::clamp(u.brake, 0.0, 1.0);
  const double steer = std::clamp(s.steer_rad, -p.max_steer_rad, p.max_steer_rad);
  const auto [cos_steer, sin_steer] = core::cos_sin(steer);

  // Velocities of the axle centres, body frame, and of the front wheel in its own frame.
  const double vy_front = s.vy_mps + lf * s.yaw_rate_radps;
  const double vy_rear = s.vy_mps - lr * s.yaw_rate_radps;
  const double u_front = s.vx_mps * cos_steer + vy_front * sin_steer;
  const double w_front = -s.vx_mps * sin_steer + vy_front * cos_steer;

  // Longitudinal body-frame force per newton of axle load as commanded (before the ABS cap). Both are
  // linear in the load, so the load transfer (which depends on the resulting deceleration) is solved in
  // closed form. Like the braking, it leaves out the lateral forces' share (-Fyf sin(d)).
  const double front_sign = detail::rolling_sign(u_front);
  const double front_per_load = -brake * mu * front_sign * cos_steer;
  const double rear_rolling_sign = detail::rolling_sign(s.vx_mps);
  double rear_per_load = 0.0;
  double rear_inv_speed = 0.0;
  if (u.rear_lock) {
    const double rear_speed = std::sqrt(s.vx_mps * s.vx_mps + vy_rear * vy_rear);
    rear_inv_speed = 1.0 / std::max(rear_speed, detail::kRollingEpsilon_mps);
    rear_per_load = -mu * s.vx_mps * rear_inv_speed;
  } else {
    rear_per_load = -brake * mu * rear_rolling_sign;
  }
  // m ax = a_f Fzf + a_r Fzr, Fzf = m (g lr - ax h) / L, Fzr = m g - Fzf.
  const double split = front_per_load - rear_per_load;
  const double accel = g * (rear_per_load * wheelbase + split * lr) /
                       std::max(wheelbase + split * p.cg_height_m, 0.25 * wheelbase);
  const auto front_load_at = [&](double accel_mps2) {
    return std::clamp(m * (g * lr - accel_mps2 * p.cg_height_m) / wheelbase, 0.0, m * g);
  };

  AxleSolution out;
  out.commanded_accel_mps2 = accel;
  out.front_lateral_velocity_mps = w_front;
  out.front_rolling_velocity_mps = u_front;
  out.rear_lateral_velocity_mps = vy_rear;
  AxleForces& front = out.tires.front;
  AxleForces& rear = out.tires.rear;
  const double tan_front = w_front / std::max(std::abs(u_front), detail::kRollingEpsilon_mps);
  const double tan_rear = vy_rear / std::max(std::abs(s.vx_mps), detail::kRollingEpsilon_mps);

  // Both axles for a front load; true when the ABS capped a braking force.
  const auto solve = [&](double load_front) {
    const double load_rear = m * g - load_front;
    front.normal_load_n = load_front;
    const double front_grip = mu * load_front;
    const RollingAxle f = abs_axle(-brake * mu * load_front * front_sign, tan_front,
                                   p.front_cornering_stiffness_n_per_rad, front_grip);
    set_rolling(front, f);
    bool capped = f.capped;
    rear.normal_load_n = load_rear;
    const double rear_grip = mu * load_rear;
    if (u.rear_lock) {
      // A locked axle slides: mu Fz against its velocity, in both directions; no cornering grip.
      rear.longitudinal_n = -rear_grip * s.vx_mps * rear_inv_speed;
      rear.lateral_n = -rear_grip * vy_rear * rear_inv_speed;
      rear.lateral_limit_n =
          std::sqrt(std::max(0.0, rear_grip * rear_grip - rear.longitudinal_n * rear.longitudinal_n));
      rear.saturated = true;
    } else {
      const RollingAxle r = abs_axle(-brake * rear_grip * rear_rolling_sign, tan_rear,
                                     p.rear_cornering_stiffness_n_per_rad, rear_grip);
      set_rolling(rear, r);
      capped = capped || r.capped;
    }
    return capped;
  };
  // Where the ABS brakes less than commanded, the loads are taken once more from the braking it applies
  // (else a released front keeps the load of full braking, and the light rear spins the car); without a
  // cap (straight braking, coasting) the closed form is already exact. One pass, not a fixed point.
  if (solve(front_load_at(accel)))
    solve(front_load_at((front.longitudinal_n * cos_steer + rear.longitudinal_n) / m));

  const double front_x = front.longitudinal_n * cos_steer - front.lateral_n * sin_steer;
  const double front_y = front.longitudinal_n * sin_steer + front.lateral_n * cos_steer;
  out.force_x_n = front_x + rear.longitudinal_n;
  out.force_y_n = front_y + rear.lateral_n;
  out.yaw_moment_nm = lf * front_y - lr * rear.lateral_n;
  return out;
}

// Weight of the dynamic model: 0 below half the blend speed, 1 above it, linear between, so the
// tire model (singular at standstill) never acts alone at walking pace.
double dynamic_weight(const VehicleParams& p, double speed_mps) {
  const double half = 0.5 * p.kinematic_blend_speed_mps;
  if (half <= 0.0) return 1.0;
  return std::clamp((speed_mps - half) / half, 0.0, 1.0);
}

}  // namespace

VehicleState SingleTrackFiala::derivative(const VehicleState& s, const Control& u, double mu) const {
  const VehicleParams& p = params_;
  const AxleSolution axles = solve_axles(p, s, u, mu);
  const auto [cos_yaw, sin_yaw] = core::cos_sin(s.yaw_rad);

  VehicleState d;
  d.x_m = s.vx_mps * cos_yaw - s.vy_mps * sin_yaw;
  d.y_m = s.vx_mps * sin_yaw + s.vy_mps * cos_yaw;
  d.yaw_rad = s.yaw_rate_radps;
  d.vx_mps = axles.force_x_n / p.mass_kg + s.yaw_rate_radps * s.vy_mps;
  d.vy_mps = axles.force_y_n / p.mass_kg - s.yaw_rate_radps * s.vx_mps;
  d.yaw_rate_radps = axles.yaw_moment_nm / p.yaw_inertia_kgm2;
  d.steer_rad = detail::limited_steer_rate(p, s, u);

  const double w = dynamic_weight(p, s.speed_mps());
  if (w < 1.0) {
    const detail::KinematicBodyRates kin =
        detail::kinematic_body_rates(p, s, d.steer_rad, axles.commanded_accel_mps2, mu * kGravity_mps2);
    d.vx_mps = w * d.vx_mps + (1.0 - w) * kin.vx_mps2;
    d.vy_mps = w * d.vy_mps + (1.0 - w) * kin.vy_mps2;
    d.yaw_rate_radps = w * d.yaw_rate_radps + (1.0 - w) * kin.yaw_rate_radps2;
  }
  return d;
}

TireForces SingleTrackFiala::tire_forces(const VehicleState& s, const Control& u, double mu) const {
  const AxleSolution axles = solve_axles(params_, s, u, mu);
  TireForces out = axles.tires;
  // atan2(lateral, |rolling|): equal to atan2(vy + lf r, vx) - delta for a wheel rolling forwards.
  out.front.slip_angle_rad =
      std::atan2(axles.front_lateral_velocity_mps, std::abs(axles.front_rolling_velocity_mps));
  out.rear.slip_angle_rad = std::atan2(axles.rear_lateral_velocity_mps, std::abs(s.vx_mps));
  return out;
}

}  // namespace emrm::sim
