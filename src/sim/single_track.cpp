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

// The slip of a rolling axle, fixed within one evaluation (the load passes below change only the
// grip): tan(alpha) and C |tan(alpha)|.
struct AxleSlip {
  double tan_alpha;
  double stiffness_tan_n;  // C |tan(alpha)|
};

[[gnu::always_inline]] inline AxleSlip axle_slip(double tan_alpha, double stiffness_n_per_rad) {
  return {tan_alpha, stiffness_n_per_rad * std::abs(tan_alpha)};
}

// Fiala brush tire. With z = C |tan(alpha)| / Fy_max the force is Fy_max (z - z^2/3 + z^3/27) against
// the slip up to z = 3 (the sliding angle tan(alpha_sl) = 3 Fy_max / C) and Fy_max beyond.
[[gnu::always_inline]] inline LateralForce fiala_lateral(const AxleSlip& slip, double limit_n) {
  if (limit_n <= kNoGrip_n) return {0.0, true};
  const double z = slip.stiffness_tan_n / limit_n;
  if (z >= 3.0) return {-std::copysign(limit_n, slip.tan_alpha), true};
  const double magnitude = limit_n * z * (1.0 - z / 3.0 + z * z / 27.0);
  return {-std::copysign(magnitude, slip.tan_alpha), false};
}

// The braking of a rolling axle under the ABS, before its lateral force: what the load transfer needs.
struct AbsBraking {
  double commanded_n;
  double longitudinal_n;
  double floor_n;  // the lateral floor Fy_abs; set only when capped
  bool capped;     // the ABS braked with less than the commanded force
};

// A rolling axle braked with `commanded_n` (signed, |commanded_n| = brake * grip) under ABS. The ABS
// holds the tire at the sliding limit of the isotropic combined-slip brush model (theta*sigma = 1),
// where the resultant grip_n points along the slip, so its lateral part is C tan(alpha) / 3: the
// braking force is capped at sqrt(grip^2 - Fy_abs^2), Fy_abs = min(grip, C |tan(alpha)| / 3). Below the
// cap this is the plain friction circle with Fiala; at the cap the Fiala force under the remaining
// limit would be below Fy_abs, so the axle slides at Fy_abs (continuous in the brake: both meet there).
[[gnu::always_inline]] inline AbsBraking abs_braking(double commanded_n, const AxleSlip& slip, double grip_n) {
  if (commanded_n != 0.0) {  // without brake pressure there is nothing for the ABS to release
    const double floor_n = std::min(grip_n, slip.stiffness_tan_n / 3.0);
    const double cap_n = std::sqrt(std::max(0.0, grip_n * grip_n - floor_n * floor_n));
    if (std::abs(commanded_n) > cap_n) return {commanded_n, std::copysign(cap_n, commanded_n), floor_n, true};
  }
  return {commanded_n, commanded_n, 0.0, false};
}

// The wheel-frame forces of a rolling axle with its braking settled: at the cap it slides at the
// floor, below it the Fiala force under what the friction circle leaves. These helpers are inlined
// so that the two axles' chains of square roots and divisions overlap.
[[gnu::always_inline]] inline void set_rolling(AxleForces& axle, const AbsBraking& braking, const AxleSlip& slip,
                                               double grip_n) {
  axle.longitudinal_n = braking.longitudinal_n;
  if (braking.capped) {
    axle.lateral_n = -std::copysign(braking.floor_n, slip.tan_alpha);
    axle.lateral_limit_n = braking.floor_n;
    axle.saturated = true;
    return;
  }
  const double commanded_n = braking.commanded_n;
  const double limit_n = std::sqrt(std::max(0.0, grip_n * grip_n - commanded_n * commanded_n));
  const LateralForce fy = fiala_lateral(slip, limit_n);
  axle.lateral_n = fy.force_n;
  axle.lateral_limit_n = limit_n;
  axle.saturated = fy.sliding;
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

// Inlined into each caller: the derivative uses only the body-frame sums, and the compiler drops
// the rest.
[[gnu::always_inline]] inline AxleSolution solve_axles(const VehicleParams& p, const VehicleState& s, const Control& u,
                                                       double mu) {
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
  const double accel =
      g * (rear_per_load * wheelbase + split * lr) / std::max(wheelbase + split * p.cg_height_m, 0.25 * wheelbase);
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
  const AxleSlip front_slip = axle_slip(w_front / std::max(std::abs(u_front), detail::kRollingEpsilon_mps),
                                        p.front_cornering_stiffness_n_per_rad);
  const AxleSlip rear_slip = axle_slip(vy_rear / std::max(std::abs(s.vx_mps), detail::kRollingEpsilon_mps),
                                       p.rear_cornering_stiffness_n_per_rad);

  // The braking of both axles for a front load (a locked rear slides at mu Fz against its velocity).
  struct Braking {
    double load_front_n, load_rear_n;
    AbsBraking front, rear;
    double rear_locked_x_n;
  };
  const auto brake_axles = [&](double load_front) {
    Braking b{};
    b.load_front_n = load_front;
    b.load_rear_n = m * g - load_front;
    b.front = abs_braking(-brake * mu * load_front * front_sign, front_slip, mu * load_front);
    const double rear_grip = mu * b.load_rear_n;
    if (u.rear_lock)
      b.rear_locked_x_n = -rear_grip * s.vx_mps * rear_inv_speed;
    else
      b.rear = abs_braking(-brake * rear_grip * rear_rolling_sign, rear_slip, rear_grip);
    return b;
  };
  // Where the ABS brakes less than commanded, the loads are taken once more from the braking it applies
  // (else a released front keeps the load of full braking, and the light rear spins the car); without a
  // cap (straight braking, coasting) the closed form is already exact. One pass, not a fixed point; the
  // lateral forces are worked out only for the pass that stands.
  Braking b = brake_axles(front_load_at(accel));
  if (b.front.capped || b.rear.capped) {
    const double rear_x = u.rear_lock ? b.rear_locked_x_n : b.rear.longitudinal_n;
    b = brake_axles(front_load_at((b.front.longitudinal_n * cos_steer + rear_x) / m));
  }
  front.normal_load_n = b.load_front_n;
  set_rolling(front, b.front, front_slip, mu * b.load_front_n);
  rear.normal_load_n = b.load_rear_n;
  const double rear_grip = mu * b.load_rear_n;
  if (u.rear_lock) {
    // A locked axle slides: mu Fz against its velocity, in both directions; no cornering grip.
    rear.longitudinal_n = b.rear_locked_x_n;
    rear.lateral_n = -rear_grip * vy_rear * rear_inv_speed;
    rear.lateral_limit_n = std::sqrt(std::max(0.0, rear_grip * rear_grip - rear.longitudinal_n * rear.longitudinal_n));
    rear.saturated = true;
  } else {
    set_rolling(rear, b.rear, rear_slip, rear_grip);
  }

  const double front_x = front.longitudinal_n * cos_steer - front.lateral_n * sin_steer;
  const double front_y = front.longitudinal_n * sin_steer + front.lateral_n * cos_steer;
  out.force_x_n = front_x + rear.longitudinal_n;
  out.force_y_n = front_y + rear.lateral_n;
  out.yaw_moment_nm = lf * front_y - lr * rear.lateral_n;
  return out;
}

// Weight of the dynamic model: 0 below half the blend speed, 1 above it, linear between, so the
// tire model (singular at standstill) never acts alone at walking pace.
double dynamic_weight(const VehicleParams& p, const VehicleState& s) {
  const double half = 0.5 * p.kinematic_blend_speed_mps;
  if (half <= 0.0) return 1.0;
  // Above four times half the blend speed the ratio is near 3, clamped to 1 for certain: decided on
  // the squared speed, without the square root and the division (the common case).
  const double speed_sq = s.vx_mps * s.vx_mps + s.vy_mps * s.vy_mps;
  if (speed_sq >= 16.0 * half * half) return 1.0;
  return std::clamp((std::sqrt(speed_sq) - half) / half, 0.0, 1.0);
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

  const double w = dynamic_weight(p, s);
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
  out.front.slip_angle_rad = std::atan2(axles.front_lateral_velocity_mps, std::abs(axles.front_rolling_velocity_mps));
  out.rear.slip_angle_rad = std::atan2(axles.rear_lateral_velocity_mps, std::abs(s.vx_mps));
  return out;
}

bool SingleTrackFiala::rear_axle_sliding(const VehicleState& s, const Control& u, double mu,
                                         double min_slip_angle_rad) const {
  // The rear slip angle is atan2(vy_rear, |vx|), as in tire_forces. Where |vy_rear| is at most
  // 0.999 min_slip |vx| it is certainly within the limit (tan(x) > x on (0, pi/2), and the rounding
  // of the product and of atan2 is far below 0.1 %): no atan2 and no axle solution needed.
  const double vy_rear = s.vy_mps - params_.cg_to_rear_axle_m * s.yaw_rate_radps;
  const double vx = std::abs(s.vx_mps);
  if (std::abs(vy_rear) <= 0.999 * min_slip_angle_rad * vx) return false;
  if (!(std::abs(std::atan2(vy_rear, vx)) > min_slip_angle_rad)) return false;
  return solve_axles(params_, s, u, mu).tires.rear.saturated;
}

}  // namespace emrm::sim
