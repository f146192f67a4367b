// A scenario played open loop, laid out as one cell's scene (played.hpp).

#include "emrm/sim/played.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "emrm/core/trig.hpp"

namespace emrm::sim {

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

core::OrientedBox box_of(const Track::Sample& p, double length_m, double width_m) {
  return {{p.x_m, p.y_m}, p.heading_rad, length_m, width_m};
}

core::Vec2 velocity_of(const Track::Sample& p) { return core::Vec2::unit(p.heading_rad) * p.speed_mps; }

// A world-frame sample in the road frame of `road`, moved back along it by `shift_m`.
Track::Sample in_road_frame(const Track::Sample& p, const StraightRoad& road, double shift_m) {
  const core::Vec2 along = core::Vec2::unit(road.heading_rad);
  const core::Vec2 across{-along.y, along.x};
  const core::Vec2 d = core::Vec2{p.x_m, p.y_m} - road.origin;
  return {d.dot(along) - shift_m, d.dot(across), core::wrap_angle(p.heading_rad - road.heading_rad), p.speed_mps};
}

// The road user with the least TTC at step k, if any has one within `ttc_s`.
std::optional<Onset> least_ttc_at(const PlayedScenario& played, std::size_t k, double ttc_s, double ego_length_m,
                                  double ego_width_m) {
  const Track::Sample& e = played.ego.path[k];
  const core::OrientedBox ego = box_of(e, ego_length_m, ego_width_m);
  std::optional<Onset> nearest;
  for (std::size_t a = 0; a < played.others.size(); ++a) {
    const PlayedUser& other = played.others[a];
    if (k >= other.path.size()) continue;
    const Track::Sample& o = other.path[k];
    const auto ttc = core::time_to_overlap(ego, velocity_of(e), box_of(o, other.body.length_m, other.body.width_m),
                                           velocity_of(o), ttc_s);
    if (ttc && (!nearest || *ttc < nearest->ttc_s)) nearest = Onset{k, a, *ttc};
  }
  return nearest;
}

}  // namespace

std::optional<Onset> threat_onset(const PlayedScenario& played, double ttc_s, double ego_length_m, double ego_width_m) {
  for (std::size_t k = 0; k < played.ego.path.size(); ++k)
    if (auto onset = least_ttc_at(played, k, ttc_s, ego_length_m, ego_width_m)) return onset;
  return std::nullopt;
}

Onset onset_at(const PlayedScenario& played, std::size_t step, double ego_length_m, double ego_width_m) {
  if (auto onset = least_ttc_at(played, step, std::numeric_limits<double>::max(), ego_length_m, ego_width_m))
    return *onset;
  // No road user is on a collision course: the nearest one is the hazard.
  const Track::Sample& e = played.ego.path.at(step);
  Onset out{step, 0, std::numeric_limits<double>::infinity()};
  double nearest_m = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < played.others.size(); ++a) {
    if (step >= played.others[a].path.size()) continue;
    const Track::Sample& o = played.others[a].path[step];
    const double d = std::hypot(o.x_m - e.x_m, o.y_m - e.y_m);
    if (d < nearest_m) {
      nearest_m = d;
      out.hazard = a;
    }
  }
  return out;
}

SceneLayout layout_from_onset(const PlayedScenario& played, const StraightRoad& road, const std::optional<Onset>& onset,
                              double ego_length_m, const std::string& why) {
  SceneLayout out;
  out.road = road.band;
  const std::size_t k0 = onset ? onset->step : 0;
  const std::size_t hazard = onset ? onset->hazard : 0;
  const Track::Sample& ego_world = played.ego.path.at(k0);
  // The ego's box centre across and along the road; its front bumper is half a length ahead.
  const Track::Sample ego = in_road_frame(ego_world, road, 0.0);
  const double shift_m = ego.x_m + ego_length_m / 2.0;
  out.ego_y_m = ego.y_m;
  out.ego_speed_mps = ego.speed_mps;
  std::vector<std::size_t> order{hazard};
  for (std::size_t a = 0; a < played.others.size(); ++a)
    if (a != hazard) order.push_back(a);
  for (const std::size_t a : order) {
    const PlayedUser& user = played.others.at(a);
    std::vector<Track::Sample> samples;
    for (std::size_t k = std::min(k0, user.path.size() - 1); k < user.path.size(); ++k)
      samples.push_back(in_road_frame(user.path[k], road, shift_m));
    const Track::Sample start = samples.front();
    out.actors.emplace_back(user.body,
                            ActorMotion{.front = {start.x_m, start.y_m},
                                        .direction = core::Vec2::unit(start.heading_rad),
                                        .track = std::make_shared<const Track>(played.dt_s, std::move(samples))});
  }
  // The hazard's near and far side along the road at the onset.
  double near = std::numeric_limits<double>::infinity();
  double far = -near;
  for (const core::Vec2& c : out.actors.front().at(0.0).box.corners()) {
    near = std::min(near, c.x);
    far = std::max(far, c.x);
  }
  out.initial_distance_m = std::max(near, 0.0);
  out.passed_x_m = far;
  if (!onset)
    out.infeasible = why;
  else if (const double off = std::abs(ego.heading_rad); off > kMaxOnsetHeading_rad)
    out.infeasible = fmt::format(
        "the ego heads {:.1f}° off the road at the threat onset (t = {:.2f} s); emrm starts it along the road (at most "
        "{:.1f}° off)",
        off * kDegrees, static_cast<double>(k0) * played.dt_s, kMaxOnsetHeading_rad * kDegrees);
  return out;
}

}  // namespace emrm::sim
