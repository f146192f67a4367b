// Kinematic single-track model: the wheels roll without side slip, so the CG moves at the slip angle
// beta = atan(lr tan(delta) / L) with yaw rate v cos(beta) tan(delta) / L.

#include <algorithm>
#include <cmath>

#include "emrm/core/trig.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

VehicleState KinematicBicycle::derivative(const VehicleState& s, const Control& u, double mu) const {
  const VehicleParams& p = params_;
  const double wheelbase = p.wheelbase_m();
  const double tan_steer = std::tan(std::clamp(s.steer_rad, -p.max_steer_rad, p.max_steer_rad));
  // beta = atan(k); its cosine and sine follow without trigonometric calls.
  const double k = p.cg_to_rear_axle_m * tan_steer / wheelbase;
  const double cos_beta = 1.0 / std::sqrt(1.0 + k * k);
  const double sin_beta = k * cos_beta;
  const double speed = std::copysign(s.speed_mps(), s.vx_mps);
  // A locked rear axle is taken to stop the car at the friction limit; there are no loads here.
  const double decel = mu * kGravity_mps2 * (u.rear_lock ? 1.0 : std::clamp(u.brake, 0.0, 1.0));
  const double speed_rate = -decel * detail::rolling_sign(speed);

  VehicleState d;
  const auto [cos_yaw, sin_yaw] = core::cos_sin(s.yaw_rad);
  // Along the course yaw + beta.
  d.x_m = speed * (cos_yaw * cos_beta - sin_yaw * sin_beta);
  d.y_m = speed * (sin_yaw * cos_beta + cos_yaw * sin_beta);
  d.yaw_rad = speed * cos_beta * tan_steer / wheelbase;
  d.steer_rad = detail::limited_steer_rate(p, s, u);
  const detail::KinematicBodyRates body =
      detail::kinematic_body_rates(p, s, d.steer_rad, speed_rate, mu * kGravity_mps2);
  d.vx_mps = body.vx_mps2;
  d.vy_mps = body.vy_mps2;
  d.yaw_rate_radps = body.yaw_rate_radps2;
  return d;
}

TireForces KinematicBicycle::tire_forces(const VehicleState& /*s*/, const Control& /*u*/, double /*mu*/) const {
  return {};
}

}  // namespace emrm::sim
