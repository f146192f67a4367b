#include "emrm/sim/actuation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace emrm::sim {
namespace {

// Knots closer than this to a step's ends are the ends themselves (sample times are sums of steps).
constexpr double kKnotTolerance_s = 1e-12;

// A first-order lag with time constant `tc` over `h`, from `y0`, driven by an input moving
// linearly from `u0` to `u1`: exact (y' = (u − y)/tc with u = u0 + k·σ has y = u − k·tc + C·e^(−σ/tc)).
double lag_linear(double y0, double u0, double u1, double h, double tc) {
  if (tc <= 0.0) return u1;
  const double k = (u1 - u0) / h;
  return u1 - k * tc + (y0 - u0 + k * tc) * std::exp(-h / tc);
}

struct RampPiece {
  double level = 0.0;     // at the piece's end
  double integral = 0.0;  // of the level over the piece
};

// The brake level moving towards `target` at `rate` (infinite: at once) for `h` from `level`.
RampPiece ramp(double level, double target, double rate, double h) {
  if (!(rate < INFINITY)) return {target, target * h};
  const double reach_s = std::abs(target - level) / rate;
  if (reach_s >= h) {
    const double end = level + std::copysign(rate * h, target - level);
    return {end, 0.5 * (level + end) * h};
  }
  return {target, 0.5 * (level + target) * reach_s + target * (h - reach_s)};
}

}  // namespace

double ActuationConfig::full_decel_mps2(double mu) const noexcept {
  const double friction = mu * kGravity_mps2;
  return max_decel_mps2 > 0.0 ? std::min(friction, max_decel_mps2) : friction;
}

std::string ActuationConfig::summary() const {
  if (instant() && perception_latency_s == 0.0) return "instant";
  return fmt::format(
      "perception latency {:g} s, brake dead time {:g} s, brake ramp {:g} s, {}, steering dead time {:g} s, "
      "steering lag {:g} s",
      perception_latency_s, brake_dead_time_s, brake_ramp_s,
      max_decel_mps2 > 0.0 ? fmt::format("brake cap {:g} m/s²", max_decel_mps2) : std::string("no brake cap"),
      steer_dead_time_s, steer_time_constant_s);
}

double ActuationConfig::stopping_time_s(double speed_mps, double mu, bool with_perception) const noexcept {
  const double a = full_decel_mps2(mu);
  const double wait = brake_dead_time_s + (with_perception ? perception_latency_s : 0.0);
  if (!(a > 0.0)) return INFINITY;
  const double tr = brake_ramp_s;
  // Within the ramp the speed falls by a·t²/(2 t_r): it reaches zero there if v ≤ a·t_r/2.
  if (tr > 0.0 && speed_mps <= 0.5 * a * tr) return wait + std::sqrt(2.0 * speed_mps * tr / a);
  return wait + tr / 2.0 + speed_mps / a;
}

double ActuationConfig::stopping_distance_m(double speed_mps, double mu, bool with_perception) const noexcept {
  const double a = full_decel_mps2(mu);
  const double wait = brake_dead_time_s + (with_perception ? perception_latency_s : 0.0);
  if (!(a > 0.0)) return INFINITY;
  const double v = speed_mps;
  const double tr = brake_ramp_s;
  if (tr > 0.0 && v <= 0.5 * a * tr) {
    const double t = std::sqrt(2.0 * v * tr / a);
    return v * wait + v * t - a * t * t * t / (6.0 * tr);
  }
  return v * wait + v * tr / 2.0 + v * v / (2.0 * a) - a * tr * tr / 24.0;
}

Actuators::Actuators(const ActuationConfig& config, const VehicleParams& params, double mu, double dt_s)
    : config_(config),
      max_steer_rad_(params.max_steer_rad),
      max_steer_rate_radps_(params.max_steer_rate_radps),
      brake_scale_(config.full_decel_mps2(mu) / (mu * kGravity_mps2)),
      dt_s_(dt_s),
      memory_s_(std::max(config.brake_dead_time_s, config.steer_dead_time_s) + 2.0 * dt_s) {
  if (!std::isfinite(brake_scale_)) brake_scale_ = 1.0;
}

ActuatorState Actuators::at_rest(const VehicleState& s) { return {s.steer_rad, 0.0, {}}; }

const CommandSample* Actuators::sample_at(const ActuatorState& a, double t_s) const noexcept {
  // The last sample issued at or before t_s (commands before the first one: none, the hazard
  // had not been seen).
  const CommandSample* found = nullptr;
  for (const CommandSample& c : a.history) {
    if (c.t_s > t_s + kKnotTolerance_s) break;
    found = &c;
  }
  return found;
}

double Actuators::steer_command_at(const ActuatorState& a, double t_s) const noexcept {
  const auto& h = a.history;
  if (h.empty() || t_s <= h.front().t_s) return h.empty() ? a.steer_command_rad : h.front().steer_command_rad;
  for (std::size_t k = 0; k < h.size(); ++k) {
    const double t1 = k + 1 < h.size() ? h[k + 1].t_s : h[k].t_s + dt_s_;
    if (t_s <= t1) {
      const double v1 = k + 1 < h.size() ? h[k + 1].steer_command_rad : a.steer_command_rad;
      const double w = (t_s - h[k].t_s) / (t1 - h[k].t_s);
      return h[k].steer_command_rad + w * (v1 - h[k].steer_command_rad);
    }
  }
  return a.steer_command_rad;
}

Control Actuators::apply(ActuatorState& a, const VehicleState& s, const Control& command, double t_s) const {
  const double dt = dt_s_;
  const double end_s = t_s + dt;
  // The commanded angle: integrated from the commanded rate within the steering limits.
  const double rate = std::clamp(command.steer_rate_radps, -max_steer_rate_radps_, max_steer_rate_radps_);
  a.history.push_back({t_s, a.steer_command_rad, command.brake, command.rear_lock});
  a.steer_command_rad = std::clamp(a.steer_command_rad + rate * dt, -max_steer_rad_, max_steer_rad_);

  // Pieces of the step between the knots of the delayed inputs (sample times shifted by a dead time).
  // Samples are a step apart, so at most one delayed sample time falls strictly inside the step;
  // the buffer has room to spare and no allocation in the per-step path.
  struct Knots {
    std::array<double, 6> at{};
    std::size_t size = 0;
  };
  const auto pieces = [&](double dead_time_s) {
    Knots knots;
    knots.at[knots.size++] = t_s;
    for (const CommandSample& c : a.history)
      if (const double k = c.t_s + dead_time_s;
          k > t_s + kKnotTolerance_s && k < end_s - kKnotTolerance_s && knots.size + 1 < knots.at.size())
        knots.at[knots.size++] = k;
    knots.at[knots.size++] = end_s;
    return knots;
  };

  // Steering: the lag driven by the delayed commanded angle, linear between knots.
  const double ts = config_.steer_dead_time_s;
  double wheel = s.steer_rad;
  const Knots steer = pieces(ts);
  for (std::size_t i = 1; i < steer.size; ++i) {
    const double u0 = steer_command_at(a, steer.at[i - 1] - ts);
    const double u1 = steer_command_at(a, steer.at[i] - ts);
    wheel = lag_linear(wheel, u0, u1, steer.at[i] - steer.at[i - 1], config_.steer_time_constant_s);
  }

  // Braking: the pressure ramps towards the delayed demand, constant between knots.
  const double tb = config_.brake_dead_time_s;
  const double ramp_rate = config_.brake_ramp_s > 0.0 ? 1.0 / config_.brake_ramp_s : INFINITY;
  double integral = 0.0;
  const Knots brake = pieces(tb);
  for (std::size_t i = 1; i < brake.size; ++i) {
    const CommandSample* c = sample_at(a, 0.5 * (brake.at[i - 1] + brake.at[i]) - tb);
    const RampPiece piece =
        ramp(a.brake_level, c ? std::clamp(c->brake, 0.0, 1.0) : 0.0, ramp_rate, brake.at[i] - brake.at[i - 1]);
    a.brake_level = piece.level;
    integral += piece.integral;
  }

  // Forget what no dead time reaches any more (keeping the sample that spans the oldest moment).
  const double oldest = end_s - memory_s_;
  std::size_t drop = 0;
  while (drop + 1 < a.history.size() && a.history[drop + 1].t_s < oldest) ++drop;
  a.history.erase(a.history.begin(), a.history.begin() + static_cast<std::ptrdiff_t>(drop));

  Control applied;
  applied.steer_rate_radps = (wheel - s.steer_rad) / dt;
  applied.brake = integral / dt * brake_scale_;
  const CommandSample* lock = sample_at(a, t_s + 0.5 * dt - tb);
  applied.rear_lock = lock != nullptr && lock->rear_lock;
  return applied;
}

bool Actuators::full_brake_held(const ActuatorState& a, const Control& command) const noexcept {
  if (!(command.brake >= 0.999) || command.rear_lock || !(a.brake_level >= 0.999)) return false;
  const double now = a.history.empty() ? 0.0 : a.history.back().t_s + dt_s_;
  for (const CommandSample& c : a.history)
    if (c.t_s + dt_s_ > now - config_.brake_dead_time_s - kKnotTolerance_s && (!(c.brake >= 0.999) || c.rear_lock))
      return false;
  return true;
}

}  // namespace emrm::sim
