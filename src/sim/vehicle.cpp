#include "emrm/sim/vehicle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "emrm/core/error.hpp"
#include "emrm/core/registry.hpp"

namespace emrm::sim {
namespace {

// Below this speed a braked vehicle counts as stopped even if no RK4 stage saw the sign change.
constexpr double kRestSpeed_mps = 1e-6;
// Time constant with which the kinematic model pulls vx, vy and r onto its own values; short
// against any manoeuvre, long against dt = 0.01 s so that RK4 stays accurate.
constexpr double kKinematicRelaxation_s = 0.05;

VehicleState add_scaled(const VehicleState& s, const VehicleState& d, double h) {
  return {s.x_m + h * d.x_m,
          s.y_m + h * d.y_m,
          s.yaw_rad + h * d.yaw_rad,
          s.vx_mps + h * d.vx_mps,
          s.vy_mps + h * d.vy_mps,
          s.yaw_rate_radps + h * d.yaw_rate_radps,
          s.steer_rad + h * d.steer_rad};
}

// True when the longitudinal velocity of `stage` has left the direction of travel of `start`:
// the Euler predictions inside RK4 already see the vehicle stop within the step.
bool reverses(const VehicleState& start, const VehicleState& stage) {
  return start.vx_mps > 0.0 ? stage.vx_mps <= 0.0 : stage.vx_mps >= 0.0;
}

// The vehicle, braked, comes to rest within this step. Only a vehicle that travels roughly along its
// body axis (or is slow) can stop this way; a car sliding sideways while it spins has vx through
// zero at full speed and must keep sliding.
bool comes_to_rest(const VehicleParams& p, const VehicleState& s, const std::array<VehicleState, 4>& stages) {
  const double speed = s.speed_mps();
  if (speed < kRestSpeed_mps) return true;
  if (std::abs(s.vy_mps) > std::abs(s.vx_mps) && speed >= p.kinematic_blend_speed_mps) return false;
  if (stages.back().speed_mps() < kRestSpeed_mps) return true;
  return std::any_of(stages.begin(), stages.end(), [&](const VehicleState& x) { return reverses(s, x); });
}

// The state where a vehicle that starts the step at `s` with rates `k1` stops, assuming a constant
// deceleration: exact for straight braking, and never further than one step's travel otherwise.
VehicleState rest_state(const VehicleState& s, const VehicleState& k1, double dt_s, double steer_rad) {
  const double speed = s.speed_mps();
  // d|v|/dt from the body-frame rates; the rotation of the frame does not change the speed.
  const double speed_rate = speed > 0.0 ? (s.vx_mps * k1.vx_mps + s.vy_mps * k1.vy_mps) / speed : 0.0;
  const double stop_s = speed_rate < 0.0 ? std::min(dt_s, speed / -speed_rate) : dt_s;
  VehicleState out = add_scaled(s, k1, 0.5 * stop_s);
  out.vx_mps = 0.0;
  out.vy_mps = 0.0;
  out.yaw_rate_radps = 0.0;
  out.steer_rad = steer_rad;
  return out;
}

template <class Model>
VehicleModelInfo shipped(std::string description, bool certificate_bound) {
  return {std::string(Model::kName), std::move(description),
          [](const VehicleParams& p) -> std::unique_ptr<VehicleModel> { return std::make_unique<Model>(p); },
          certificate_bound};
}

// The registry (esmini-style): the shipped models, then whatever a program registers.
core::Registry<VehicleModelInfo>& registry() {
  static core::Registry<VehicleModelInfo> models(
      "vehicle model",
      {shipped<SingleTrackFiala>("single-track model with Fiala brush tires (docs/physics.md)", true),
       shipped<KinematicBicycle>("kinematic single-track model, for comparison", false)},
      [](const VehicleModelInfo& m) -> std::string_view { return m.name; });
  return models;
}

}  // namespace

double VehicleState::slip_angle_rad() const {
  // atan2(0, -0.0) would be pi: a vehicle at rest has no slip.
  if (vx_mps == 0.0 && vy_mps == 0.0) return 0.0;
  return std::atan2(vy_mps, vx_mps);
}

VehicleState VehicleModel::step(const VehicleState& s, const Control& u, double mu, double dt_s) const {
  const VehicleState k1 = derivative(s, u, mu);
  const VehicleState s2 = add_scaled(s, k1, 0.5 * dt_s);
  const VehicleState k2 = derivative(s2, u, mu);
  const VehicleState s3 = add_scaled(s, k2, 0.5 * dt_s);
  const VehicleState k3 = derivative(s3, u, mu);
  const VehicleState s4 = add_scaled(s, k3, dt_s);
  const VehicleState k4 = derivative(s4, u, mu);

  VehicleState sum = k1;
  sum = add_scaled(sum, k2, 2.0);
  sum = add_scaled(sum, k3, 2.0);
  sum = add_scaled(sum, k4, 1.0);
  VehicleState out = add_scaled(s, sum, dt_s / 6.0);
  // The derivative stops the steering at the limit, but a stage may step over it.
  out.steer_rad = std::clamp(out.steer_rad, -params_.max_steer_rad, params_.max_steer_rad);

  const bool braking = u.brake > 0.0 || u.rear_lock;
  if (braking && comes_to_rest(params_, s, {s2, s3, s4, out})) return rest_state(s, k1, dt_s, out.steer_rad);
  return out;
}

bool VehicleModel::rear_axle_sliding(const VehicleState& s, const Control& u, double mu,
                                     double min_slip_angle_rad) const {
  const AxleForces rear = tire_forces(s, u, mu).rear;
  return rear.saturated && std::abs(rear.slip_angle_rad) > min_slip_angle_rad;
}

void validate(const VehicleParams& params) { core::validate_fields("vehicle", params); }

VehicleModelRegistration::VehicleModelRegistration(VehicleModelInfo info) : name_(info.name) {
  if (!info.make) throw UsageError(fmt::format("vehicle model '{}' has no factory", info.name));
  registry().add(std::move(info));
}

VehicleModelRegistration::~VehicleModelRegistration() { registry().remove(name_); }

std::optional<VehicleModelInfo> find_vehicle_model(std::string_view name) {
  const auto table = registry().table();
  for (const auto& m : *table)
    if (m.name == name) return m;
  return std::nullopt;
}

std::unique_ptr<VehicleModel> make_vehicle_model(std::string_view name, const VehicleParams& params) {
  validate(params);
  const auto table = registry().table();
  for (const auto& m : *table)
    if (m.name == name) return m.make(params);
  throw Error(fmt::format("unknown vehicle model '{}' (known: {})", name, fmt::join(vehicle_model_names(), ", ")));
}

std::vector<std::string> vehicle_model_names() { return registry().names(); }

namespace detail {

double limited_steer_rate(const VehicleParams& p, const VehicleState& s, const Control& u) {
  const double rate = std::clamp(u.steer_rate_radps, -p.max_steer_rate_radps, p.max_steer_rate_radps);
  if ((s.steer_rad >= p.max_steer_rad && rate > 0.0) || (s.steer_rad <= -p.max_steer_rad && rate < 0.0)) return 0.0;
  return rate;
}

KinematicBodyRates kinematic_body_rates(const VehicleParams& p, const VehicleState& s, double steer_rate_radps,
                                        double speed_rate_mps2, double max_correction_mps2) {
  const double wheelbase = p.wheelbase_m();
  const double rear_share = p.cg_to_rear_axle_m / wheelbase;
  const double tan_steer = std::tan(std::clamp(s.steer_rad, -p.max_steer_rad, p.max_steer_rad));
  const double sec2_steer = 1.0 + tan_steer * tan_steer;
  // beta = atan(k): cos and sin without trigonometric calls.
  const double k = rear_share * tan_steer;
  const double cos_beta = 1.0 / std::sqrt(1.0 + k * k);
  const double sin_beta = k * cos_beta;
  const double beta_rate = rear_share * sec2_steer / (1.0 + k * k) * steer_rate_radps;
  // Signed path speed: the kinematic model drives along +x of the body unless vx is negative.
  const double speed = std::copysign(s.speed_mps(), s.vx_mps);

  const double vx = speed * cos_beta;
  const double vy = speed * sin_beta;
  const double yaw_rate = vx * tan_steer / wheelbase;
  const double vx_rate = speed_rate_mps2 * cos_beta - speed * sin_beta * beta_rate;
  const double vy_rate = speed_rate_mps2 * sin_beta + speed * cos_beta * beta_rate;
  const double yaw_acc = (vx_rate * tan_steer + vx * sec2_steer * steer_rate_radps) / wheelbase;

  constexpr double kGain = 1.0 / kKinematicRelaxation_s;
  double correction_x = kGain * (vx - s.vx_mps);
  double correction_y = kGain * (vy - s.vy_mps);
  const double correction = std::sqrt(correction_x * correction_x + correction_y * correction_y);
  if (correction > max_correction_mps2) {
    const double scale = std::max(max_correction_mps2, 0.0) / correction;
    correction_x *= scale;
    correction_y *= scale;
  }
  return {vx_rate + correction_x, vy_rate + correction_y, yaw_acc + kGain * (yaw_rate - s.yaw_rate_radps)};
}

}  // namespace detail

}  // namespace emrm::sim
