// An actor's motion given as samples (actor.hpp, Track): an imported scenario's storyboard played
// open loop.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "emrm/core/trig.hpp"
#include "emrm/sim/actor.hpp"

namespace emrm::sim {

namespace {

bool same_pose(const Track::Sample& a, const Track::Sample& b) noexcept {
  return a.x_m == b.x_m && a.y_m == b.y_m && a.heading_rad == b.heading_rad;
}

}  // namespace

Track::Track(double dt, std::vector<Sample> points) : dt_s(dt), samples(std::move(points)) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) throw std::invalid_argument("a track's spacing must be finite and > 0");
  if (samples.empty()) throw std::invalid_argument("a track needs at least one sample");
  for (const Sample& p : samples)
    if (!(std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.heading_rad) && std::isfinite(p.speed_mps) &&
          p.speed_mps >= 0.0))
      throw std::invalid_argument("a track's samples must be finite, with speeds >= 0");
  // At rest for good from the first of the trailing samples that keep the last pose at speed 0.
  if (samples.back().speed_mps > 0.0) {
    rest_time_s_ = std::numeric_limits<double>::infinity();
    return;
  }
  std::size_t k = samples.size() - 1;
  while (k > 0 && samples[k - 1].speed_mps == 0.0 && same_pose(samples[k - 1], samples.back())) --k;
  rest_time_s_ = static_cast<double>(k) * dt_s;
}

double Track::top_speed_mps(double length_m, double width_m) const noexcept {
  const double half_diagonal = 0.5 * std::hypot(length_m, width_m);
  double top = samples.back().speed_mps;  // going on after the last sample
  for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
    const Sample& a = samples[i];
    const Sample& b = samples[i + 1];
    const double travel = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
    const double turn = std::abs(core::wrap_angle(b.heading_rad - a.heading_rad));
    top = std::max(top, (travel + turn * half_diagonal) / dt_s);
  }
  return top;
}

Track::Sample Track::at(double t_s, core::Vec2* velocity_mps) const noexcept {
  const double t = std::max(t_s, 0.0);
  const double last_s = static_cast<double>(samples.size() - 1) * dt_s;
  if (t >= last_s) {  // on straight at the last speed
    Sample p = samples.back();
    const core::Vec2 v = core::Vec2::unit(p.heading_rad) * p.speed_mps;
    p.x_m += v.x * (t - last_s);
    p.y_m += v.y * (t - last_s);
    if (velocity_mps != nullptr) *velocity_mps = v;
    return p;
  }
  const auto i = std::min(static_cast<std::size_t>(t / dt_s), samples.size() - 2);
  const Sample& a = samples[i];
  const Sample& b = samples[i + 1];
  const double u = std::clamp(t / dt_s - static_cast<double>(i), 0.0, 1.0);
  Sample p;
  p.x_m = a.x_m + u * (b.x_m - a.x_m);
  p.y_m = a.y_m + u * (b.y_m - a.y_m);
  p.heading_rad = a.heading_rad + u * core::wrap_angle(b.heading_rad - a.heading_rad);
  p.speed_mps = a.speed_mps + u * (b.speed_mps - a.speed_mps);
  // The velocity of the interpolated path: the interval's secant.
  if (velocity_mps != nullptr) *velocity_mps = {(b.x_m - a.x_m) / dt_s, (b.y_m - a.y_m) / dt_s};
  return p;
}

}  // namespace emrm::sim
