// The controls of a rollout (controls.hpp): pure pursuit, the friction circle's share left for
// braking, and the schedule of a plan and its tail.

#include "emrm/sim/controls.hpp"

#include <algorithm>
#include <cmath>

#include "emrm/core/trig.hpp"

namespace emrm::sim {

double pursuit_steer_rate(const VehicleState& s, const core::Vec2& target, const VehicleParams& p, double mu,
                          double grip, double dt_s) noexcept {
  const double dx = target.x - s.x_m;
  const double dy = target.y - s.y_m;
  const double alpha = core::wrap_angle(std::atan2(dy, dx) - s.yaw_rad);
  const double lookahead = std::max(std::hypot(dx, dy), 1.0);
  const double v2 = std::max(s.vx_mps * s.vx_mps, 1.0);
  const double grip_limit = std::min(p.max_steer_rad, std::atan(p.wheelbase_m() * grip * mu * kGravity_mps2 / v2));
  const double wanted =
      std::clamp(std::atan(2.0 * p.wheelbase_m() * std::sin(alpha) / lookahead), -grip_limit, grip_limit);
  return std::clamp((wanted - s.steer_rad) / (2.0 * dt_s), -p.max_steer_rate_radps, p.max_steer_rate_radps);
}

double friction_circle_share(const VehicleState& s, double mu) noexcept {
  const double lateral = std::abs(s.vx_mps * s.yaw_rate_radps) / (mu * kGravity_mps2);
  return std::sqrt(std::max(0.0, 1.0 - lateral * lateral));
}

ControlSchedule::ControlSchedule(const std::vector<ControlSegment>& plan, const std::optional<Tail>& tail,
                                 const VehicleParams& params, const ControlLimits& limits, double mu, double dt_s)
    : plan_(plan),
      tail_(tail),
      params_(params),
      limits_(limits),
      mu_(mu),
      dt_s_(dt_s),
      segment_left_s_(plan.empty() ? 0.0 : plan.front().duration_s) {}

std::optional<Control> ControlSchedule::control_at(const VehicleState& s) {
  while (segment_ < plan_.size() && segment_left_s_ <= 1e-9) {
    ++segment_;
    if (segment_ < plan_.size()) segment_left_s_ = plan_[segment_].duration_s;
  }
  Control u;
  if (recovery_y_m_) {
    // Recovery: back to a straight line ahead, steering only. Braking here would take load off a
    // rear axle that still carries the turn and make it slide; the safe state asks for stability
    // and room to stop, not for a stop.
    const core::Vec2 ahead{s.x_m + std::max(10.0, 1.5 * s.speed_mps()), *recovery_y_m_};
    u.steer_rate_radps = pursuit_steer_rate(s, ahead, params_, mu_, 0.9, dt_s_);
    return u;
  }
  if (segment_ < plan_.size()) {
    const ControlSegment& segment = plan_[segment_];
    u = segment.control;
    if (segment.pursue) {
      u.steer_rate_radps = pursuit_steer_rate(s, *segment.pursue, params_, mu_, segment.pursuit_grip, dt_s_);
      if (segment.friction_circle_brake) u.brake *= friction_circle_share(s, mu_);
    }
  } else if (tail_) {
    const double max_rate = params_.max_steer_rate_radps;
    u = tail_->control;
    // Back to straight at the largest rate that does not overshoot within a few steps.
    if (tail_->straighten) u.steer_rate_radps = std::clamp(-s.steer_rad / (5.0 * dt_s_), -max_rate, max_rate);
    if (tail_->pursue) u.steer_rate_radps = pursuit_steer_rate(s, *tail_->pursue, params_, mu_, 0.9, dt_s_);
    if (tail_->friction_circle_brake) u.brake *= friction_circle_share(s, mu_);
  } else {
    return std::nullopt;
  }
  if (!limits_.allow_rear_lock) u.rear_lock = false;
  return u;
}

}  // namespace emrm::sim
