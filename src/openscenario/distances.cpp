// Distances between entities and to positions as the conditions measure them (runtime.hpp):
// between reference points or bounding boxes (freespace), in the entity's frame or along the road.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "runtime.hpp"

namespace emrm::openscenario::detail {
namespace {

using Corner = std::array<double, 2>;

std::array<Corner, 4> corners(const WorldPose& pose, const BoundingBox& box) {
  const double c = std::cos(pose.heading_rad), s = std::sin(pose.heading_rad);
  std::array<Corner, 4> out{};
  const double hl = box.length_m / 2.0, hw = box.width_m / 2.0;
  const std::array<Corner, 4> local = {{{hl, hw}, {-hl, hw}, {-hl, -hw}, {hl, -hw}}};
  for (std::size_t i = 0; i < 4; ++i) {
    const double lx = box.center_x_m + local[i][0], ly = box.center_y_m + local[i][1];
    out[i] = {pose.x_m + c * lx - s * ly, pose.y_m + s * lx + c * ly};
  }
  return out;
}

double point_to_segment(const Corner& p, const Corner& a, const Corner& b) {
  const double vx = b[0] - a[0], vy = b[1] - a[1];
  const double len2 = vx * vx + vy * vy;
  const double u = len2 > 0.0 ? std::clamp(((p[0] - a[0]) * vx + (p[1] - a[1]) * vy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p[0] - a[0] - u * vx, p[1] - a[1] - u * vy);
}

// Whether two convex quadrilaterals overlap (separating axes of both).
bool overlap(const std::array<Corner, 4>& a, const std::array<Corner, 4>& b) {
  for (const auto* poly : {&a, &b})
    for (std::size_t i = 0; i < 4; ++i) {
      const Corner& p = (*poly)[i];
      const Corner& q = (*poly)[(i + 1) % 4];
      const double nx = q[1] - p[1], ny = p[0] - q[0];
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const Corner& c : a)
        amin = std::min(amin, c[0] * nx + c[1] * ny), amax = std::max(amax, c[0] * nx + c[1] * ny);
      for (const Corner& c : b)
        bmin = std::min(bmin, c[0] * nx + c[1] * ny), bmax = std::max(bmax, c[0] * nx + c[1] * ny);
      if (amax < bmin || bmax < amin) return false;
    }
  return true;
}

double box_distance(const std::array<Corner, 4>& a, const std::array<Corner, 4>& b) {
  if (overlap(a, b)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t k = 0; k < 4; ++k) {
      best = std::min(best, point_to_segment(a[i], b[k], b[(k + 1) % 4]));
      best = std::min(best, point_to_segment(b[i], a[k], a[(k + 1) % 4]));
    }
  return best;
}

// The interval a set of points covers along the unit vector (ux, uy) from `origin`.
std::pair<double, double> span(const std::array<Corner, 4>& points, const WorldPose& origin, double ux, double uy) {
  double lo = 1e300, hi = -1e300;
  for (const Corner& p : points) {
    const double d = (p[0] - origin.x_m) * ux + (p[1] - origin.y_m) * uy;
    lo = std::min(lo, d), hi = std::max(hi, d);
  }
  return {lo, hi};
}

// The signed gap between two intervals: positive when `b` lies beyond `a`, negative before it.
double gap(std::pair<double, double> a, std::pair<double, double> b) {
  if (b.first > a.second) return b.first - a.second;
  if (b.second < a.first) return b.second - a.first;
  return 0.0;
}

double measure(const World& world, const EntityState& from, const WorldPose& to, const BoundingBox* to_box,
               const DistanceSpec& spec) {
  const BoundingBox& box = from.spec->box;
  // esmini measures a euclidean distance in the world whatever the coordinate system, signed by
  // whether the target is ahead (+) or not (-) in the entity's frame (Position::getRelativeDistance).
  const bool along_road = (spec.system == CoordinateSystem::kLane || spec.system == CoordinateSystem::kRoad) &&
                          spec.type != DistanceType::kEuclidean && world.roads != nullptr;
  if (along_road) {
    // s and t differences in the road coordinates of the entity's road (esmini: along the road).
    const auto here_found = from.on_lane ? std::optional<LaneCoord>(from.lane)
                                         : world.roads->world_to_lane(from.pose.x_m, from.pose.y_m, nullptr);
    if (!here_found) return std::numeric_limits<double>::infinity();  // off road: no road distance (esmini: none)
    const LaneCoord& here = *here_found;
    const auto there_found = world.roads->world_to_lane(to.x_m, to.y_m, &here);
    if (!there_found) return std::numeric_limits<double>::infinity();
    const LaneCoord& there = *there_found;
    const double t_here = world.roads->lane_center_t(here.road_id, here.lane_id, here.s_m) + here.offset_m;
    const double t_there = world.roads->lane_center_t(there.road_id, there.lane_id, there.s_m) + there.offset_m;
    double ds = (there.s_m - here.s_m) * from.direction;
    double dt = (t_there - t_here) * from.direction;
    if (spec.freespace) {
      // Each box reaches from its reference point by half its length plus or minus its centre's
      // offset: the entity's front (or rear) and the other's rear (or front), both heading along s.
      const double own = box.length_m / 2.0 + (ds >= 0.0 ? box.center_x_m : -box.center_x_m);
      const double other =
          to_box != nullptr ? to_box->length_m / 2.0 + (ds >= 0.0 ? -to_box->center_x_m : to_box->center_x_m) : 0.0;
      ds = ds >= 0.0 ? std::max(0.0, ds - own - other) : std::min(0.0, ds + own + other);
      const double own_w = box.width_m / 2.0, other_w = to_box != nullptr ? to_box->width_m / 2.0 : 0.0;
      dt = dt >= 0.0 ? std::max(0.0, dt - own_w - other_w) : std::min(0.0, dt + own_w + other_w);
    }
    if (spec.type == DistanceType::kLongitudinal) return ds;
    if (spec.type == DistanceType::kLateral) return dt;
    return std::hypot(ds, dt);
  }
  const double ux = std::cos(from.pose.heading_rad), uy = std::sin(from.pose.heading_rad);
  if (!spec.freespace) {
    const double dx = to.x_m - from.pose.x_m, dy = to.y_m - from.pose.y_m;
    if (spec.type == DistanceType::kLongitudinal) return dx * ux + dy * uy;
    if (spec.type == DistanceType::kLateral) return -dx * uy + dy * ux;
    return dx * ux + dy * uy > 0.0 ? std::hypot(dx, dy) : -std::hypot(dx, dy);
  }
  const auto own = corners(from.pose, box);
  const std::array<Corner, 4> other =
      to_box != nullptr
          ? corners(to, *to_box)
          : std::array<Corner, 4>{{{to.x_m, to.y_m}, {to.x_m, to.y_m}, {to.x_m, to.y_m}, {to.x_m, to.y_m}}};
  const double longitudinal = gap(span(own, from.pose, ux, uy), span(other, from.pose, ux, uy));
  if (spec.type == DistanceType::kLongitudinal) return longitudinal;
  if (spec.type == DistanceType::kLateral) return gap(span(own, from.pose, -uy, ux), span(other, from.pose, -uy, ux));
  const double d = box_distance(own, other);
  return longitudinal < 0.0 ? -d : d;  // esmini: the sign says ahead (+) or behind (-)
}

}  // namespace

double measured_distance(const World& world, const EntityState& from, const EntityState& to, const DistanceSpec& spec) {
  return measure(world, from, to.pose, &to.spec->box, spec);
}

bool boxes_overlap(const EntityState& a, const EntityState& b) {
  return overlap(corners(a.pose, a.spec->box), corners(b.pose, b.spec->box));
}

double measured_distance(const World& world, const EntityState& from, const WorldPose& to, const DistanceSpec& spec) {
  return measure(world, from, to, nullptr, spec);
}

}  // namespace emrm::openscenario::detail
