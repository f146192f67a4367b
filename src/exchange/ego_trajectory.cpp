// The ego's executed trajectory made into a simulator's vertices (ego_trajectory.hpp).

#include "emrm/exchange/ego_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "emrm/core/trig.hpp"
#include "emrm/sim/termination.hpp"

namespace emrm::exchange {

std::vector<sim::PathPoint> thin_path(const std::vector<sim::PathPoint>& path, double tolerance_m) {
  if (tolerance_m <= 0.0 || path.size() <= 2) return path;
  std::vector<sim::PathPoint> kept{path.front()};
  std::size_t anchor = 0;
  // Greedy: extend the chord from the last kept point while every point under it stays within the
  // tolerance of the chord's position at that point's time.
  const auto fits = [&](std::size_t from, std::size_t to) {
    const auto& a = path[from].state;
    const auto& b = path[to].state;
    const double span = path[to].t_s - path[from].t_s;
    for (std::size_t k = from + 1; k < to; ++k) {
      const double u = span > 0.0 ? (path[k].t_s - path[from].t_s) / span : 0.0;
      const double dx = a.x_m + u * (b.x_m - a.x_m) - path[k].state.x_m;
      const double dy = a.y_m + u * (b.y_m - a.y_m) - path[k].state.y_m;
      if (dx * dx + dy * dy > tolerance_m * tolerance_m) return false;
    }
    return true;
  };
  for (std::size_t next = 2; next < path.size(); ++next) {
    if (!fits(anchor, next)) {
      anchor = next - 1;
      kept.push_back(path[anchor]);
    }
  }
  kept.push_back(path.back());
  return kept;
}

std::vector<sim::PathPoint> ended_on_frame_grid(const std::vector<sim::PathPoint>& path, double dt_s) {
  if (path.empty()) return path;
  const sim::PathPoint& last = path.back();
  // The first frame at or after the end (the path's times are sums of steps: a hair of slack).
  const double frame_s = std::ceil(last.t_s / dt_s - 1e-6) * dt_s;
  std::vector<sim::PathPoint> out = path;
  sim::PathPoint held = last;
  if (last.state.speed_mps() < sim::kStoppedSpeed_mps) {
    // At rest: the pose held to one frame after that one, a frame that does not move.
    held.t_s = std::max(frame_s, last.t_s) + dt_s;
    held.state.vx_mps = held.state.vy_mps = held.state.yaw_rate_radps = 0.0;
    out.push_back(held);
  } else if (frame_s > last.t_s + 1e-9 * dt_s) {
    // Moving (a contact, a departure): on at the final velocity and yaw rate to that frame.
    const double tau = frame_s - last.t_s;
    const auto& s = last.state;
    const auto [c, sn] = core::cos_sin(s.yaw_rad);
    held.t_s = frame_s;
    held.state.x_m += (s.vx_mps * c - s.vy_mps * sn) * tau;
    held.state.y_m += (s.vx_mps * sn + s.vy_mps * c) * tau;
    held.state.yaw_rad += last.state.yaw_rate_radps * tau;
    out.push_back(held);
  }
  return out;
}

}  // namespace emrm::exchange
