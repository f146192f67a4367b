// FollowTrajectoryAction (runtime.hpp): the trajectory resolved into the world frame when the
// action starts, followed by time (TimeReference Timing) or at the entity's speed (None), as
// esmini's FollowTrajectoryAction does. Clothoids come from opendrive::clothoid, their one owner.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "emrm/opendrive/geometry.hpp"
#include "runtime.hpp"

namespace emrm::openscenario::detail {

double ResolvedTrajectory::length_m() const {
  if (clothoid) return clothoid->length_m;
  return arc_m.empty() ? 0.0 : arc_m.back();
}

WorldPose ResolvedTrajectory::at_arc(double s_m) const {
  const double s = std::clamp(s_m, 0.0, length_m());
  if (clothoid) {
    const opendrive::Pose p = opendrive::clothoid({clothoid_start.x_m, clothoid_start.y_m, clothoid_start.heading_rad},
                                                  clothoid->curvature_1pm, clothoid->curvature_rate_1pm2, s);
    return {p.x, p.y, p.heading};
  }
  if (points.size() == 1) return points.front();
  const auto upper = std::upper_bound(arc_m.begin(), arc_m.end(), s);
  std::size_t i = upper == arc_m.begin() ? 0 : static_cast<std::size_t>(upper - arc_m.begin()) - 1;
  i = std::min(i, points.size() - 2);
  const double span = arc_m[i + 1] - arc_m[i];
  const double u = span > 0.0 ? (s - arc_m[i]) / span : 0.0;
  return {points[i].x_m + u * (points[i + 1].x_m - points[i].x_m),
          points[i].y_m + u * (points[i + 1].y_m - points[i].y_m), points[i].heading_rad};
}

bool ResolvedTrajectory::timed() const {
  if (clothoid) return clothoid->start_time_s.has_value() && clothoid->stop_time_s.has_value();
  return !times_s.empty();
}

double ResolvedTrajectory::start_time_s() const {
  if (clothoid) return clothoid->start_time_s.value_or(0.0);
  return times_s.empty() ? 0.0 : times_s.front();
}

double ResolvedTrajectory::end_time_s() const {
  if (clothoid) return clothoid->stop_time_s.value_or(0.0);
  return times_s.empty() ? 0.0 : times_s.back();
}

double ResolvedTrajectory::arc_at_time(double t_s) const {
  if (clothoid) {
    const double span = end_time_s() - start_time_s();
    if (span <= 0.0) return length_m();
    return length_m() * std::clamp((t_s - start_time_s()) / span, 0.0, 1.0);
  }
  if (t_s <= times_s.front()) return 0.0;
  if (t_s >= times_s.back()) return arc_m.back();
  const auto upper = std::upper_bound(times_s.begin(), times_s.end(), t_s);
  const std::size_t i = static_cast<std::size_t>(upper - times_s.begin()) - 1;
  const double span = times_s[i + 1] - times_s[i];
  const double u = span > 0.0 ? (t_s - times_s[i]) / span : 1.0;
  return arc_m[i] + u * (arc_m[i + 1] - arc_m[i]);
}

void ActionRuntime::start_trajectory(World& world, const FollowTrajectoryAction& a) {
  EntityState& e = world.entity(actor_);
  path_ = ResolvedTrajectory{};
  if (const auto* c = std::get_if<ClothoidShape>(&a.trajectory.shape)) {
    path_.clothoid = *c;
    path_.clothoid_start = c->start ? resolve(world, *c->start, &e).pose : e.pose;
  } else {
    const auto& vertices = std::get<std::vector<PolylineVertex>>(a.trajectory.shape);
    double arc = 0.0;
    for (const PolylineVertex& v : vertices) {
      WorldPose p = resolve(world, v.position, &e).pose;
      if (!path_.points.empty()) {
        WorldPose& previous = path_.points.back();
        const double d = std::hypot(p.x_m - previous.x_m, p.y_m - previous.y_m);
        if (d > kSmall) previous.heading_rad = std::atan2(p.y_m - previous.y_m, p.x_m - previous.x_m);
        p.heading_rad = previous.heading_rad;
        arc += d;
      }
      path_.points.push_back(p);
      path_.arc_m.push_back(arc);
      if (v.time_s) path_.times_s.push_back(*v.time_s);
    }
    if (path_.times_s.size() != vertices.size()) path_.times_s.clear();
  }
  path_time_s_ = 0.0;
  path_s_m_ = a.initial_distance_offset_m;
  e.on_lane = false;
  e.heading_offset_rad = 0.0;
  const WorldPose start = path_.at_arc(path_s_m_);
  e.pose = start;
  if (a.timing && path_.timed()) {
    // The speed the timing asks for at its start.
    const double t0 = path_.start_time_s();
    const double probe = std::min(path_.end_time_s(), t0 + 1e-3);
    if (probe > t0) e.speed_mps = (path_.arc_at_time(probe) - path_.arc_at_time(t0)) / (probe - t0);
  }
}

bool ActionRuntime::step_trajectory(World& world, const FollowTrajectoryAction& a, double time_s, double dt_s) {
  EntityState& e = world.entity(actor_);
  e.moved_longitudinally = true;
  const double old_s = path_s_m_;
  const bool timed = a.timing.has_value() && path_.timed();
  double overshoot_m = 0.0;
  bool done = false;
  if (!timed) {
    path_s_m_ += e.speed_mps * dt_s;
    if (path_s_m_ > path_.length_m() - kSmall && !a.trajectory.closed) {
      overshoot_m = std::fabs(e.speed_mps) * dt_s - std::fabs(path_.length_m() - old_s);
      path_s_m_ = path_.length_m();
      done = true;
    }
  } else {
    const Timing& timing = *a.timing;
    path_time_s_ = timing.absolute ? (time_s + dt_s) * timing.scale : path_time_s_ + timing.scale * dt_s;
    const double t = path_time_s_ + timing.offset_s;
    path_s_m_ = path_.arc_at_time(t);
    if (t < path_.end_time_s() + kSmall && dt_s > kSmall) e.speed_mps = (path_s_m_ - old_s) / dt_s;
    if (t > path_.end_time_s() - kSmall) {
      overshoot_m = (t - path_.end_time_s()) * e.speed_mps;
      done = true;
    }
  }
  WorldPose pose = path_.at_arc(path_s_m_);
  if (done) {
    // The rest of the step along the last heading; then the entity keeps to the lane it is in, at
    // its offset and with its heading relative to the road (esmini keeps h_relative: a following
    // trajectory with a relative orientation starts from it).
    pose.x_m += overshoot_m * std::cos(pose.heading_rad);
    pose.y_m += overshoot_m * std::sin(pose.heading_rad);
    if (world.place_at(e, pose)) {
      e.on_lane = true;
      e.heading_offset_rad = 0.0;
      world.update_pose(e);
      e.heading_offset_rad = std::remainder(pose.heading_rad - e.pose.heading_rad, 2.0 * std::numbers::pi);
      world.update_pose(e);
    }
    return true;
  }
  e.pose = pose;
  return false;
}

}  // namespace emrm::openscenario::detail
