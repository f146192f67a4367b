// The road network's queries: lookups, road/lane coordinates to the world and back, and where a
// lane leads past a road's end (ASAM OpenDRIVE 1.7 §8.2 road linkage, §9.4 lane linkage, §10 junctions).

#include <algorithm>
#include <cmath>
#include <limits>

#include "emrm/opendrive/road_network.hpp"

namespace emrm::opendrive {
namespace {

/// Sample spacing along a reference line (m): for bounding boxes and the projection's start.
constexpr double kSampleStep_m = 1.0;

std::vector<double> sample_s(double length) {
  const auto steps = static_cast<std::size_t>(std::max(8.0, std::ceil(length / kSampleStep_m)));
  std::vector<double> s(steps + 1);
  for (std::size_t i = 0; i <= steps; ++i) s[i] = length * static_cast<double>(i) / static_cast<double>(steps);
  return s;
}

/// (P - C(s)) . T(s): positive while the foot of the perpendicular from P lies further along s.
double along(const Road& road, double x, double y, double s) {
  const Pose c = road.plan_view.at(s);
  return (x - c.x) * std::cos(c.heading) + (y - c.y) * std::sin(c.heading);
}

double distance_squared(const Road& road, double x, double y, double s) {
  const Pose c = road.plan_view.at(s);
  return (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y);
}

/// The s in [lo, hi] nearest to (x, y): bisection on along() where it changes sign, else the
/// nearer end.
double refine(const Road& road, double x, double y, double lo, double hi) {
  double f_lo = along(road, x, y, lo);
  const double f_hi = along(road, x, y, hi);
  if (!(f_lo > 0.0 && f_hi < 0.0))
    return distance_squared(road, x, y, lo) <= distance_squared(road, x, y, hi) ? lo : hi;
  for (int iteration = 0; iteration < 100 && hi - lo > 1e-12 * (1.0 + hi); ++iteration) {
    const double mid = 0.5 * (lo + hi);
    const double f = along(road, x, y, mid);
    if (f > 0.0) {
      lo = mid;
      f_lo = f;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

/// The s of the point of the reference line nearest to (x, y): the nearest sample, refined in the
/// intervals on either side of it (so a joint between segments is no special case).
double project(const Road& road, double x, double y) {
  const auto s = sample_s(road.length);
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double d = distance_squared(road, x, y, s[i]);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  double result = s[best];
  double result_d = best_d;
  for (const auto& [lo, hi] :
       {std::pair{best == 0 ? 0 : best - 1, best}, std::pair{best, std::min(best + 1, s.size() - 1)}}) {
    if (lo == hi) continue;
    const double candidate = refine(road, x, y, s[lo], s[hi]);
    const double d = distance_squared(road, x, y, candidate);
    if (d < result_d) {
      result = candidate;
      result_d = d;
    }
  }
  return result;
}

/// How far a point may lie beyond a road's end and still be on it (m): rounding only.
constexpr double kEndTolerance_m = 1e-7;

}  // namespace

RoadNetwork::RoadNetwork(std::string file, std::vector<Road> roads, std::vector<Junction> junctions)
    : file_(std::move(file)), roads_(std::move(roads)), junctions_(std::move(junctions)) {
  for (std::size_t i = 0; i < roads_.size(); ++i) road_index_.emplace(roads_[i].id, i);
  for (std::size_t i = 0; i < junctions_.size(); ++i) junction_index_.emplace(junctions_[i].id, i);
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (const Road& road : roads_) {
    Box box{inf, inf, -inf, -inf};
    for (const double s : sample_s(road.length)) {
      const auto ids = road.lane_ids(s);
      for (const double t : {road.lane_borders(ids.front(), s).second, road.lane_borders(ids.back(), s).second,
                             road.lane_offset(s), 0.0}) {
        const Pose p = road.to_world(s, t);
        box = {std::min(box.min_x, p.x), std::min(box.min_y, p.y), std::max(box.max_x, p.x), std::max(box.max_y, p.y)};
      }
    }
    // Between samples a border bulges by at most step² curvature / 8 (well under this margin on roads).
    constexpr double margin_m = 1.0;
    boxes_.push_back({box.min_x - margin_m, box.min_y - margin_m, box.max_x + margin_m, box.max_y + margin_m});
  }
}

const Road* RoadNetwork::find_road(std::string_view id) const {
  const auto found = road_index_.find(std::string(id));
  return found == road_index_.end() ? nullptr : &roads_[found->second];
}

const Junction* RoadNetwork::find_junction(std::string_view id) const {
  const auto found = junction_index_.find(std::string(id));
  return found == junction_index_.end() ? nullptr : &junctions_[found->second];
}

Pose RoadNetwork::road_to_world(const Road& road, double s, double t) const { return road.to_world(s, t); }

Pose RoadNetwork::lane_to_world(const Road& road, int lane_id, double s, double offset) const {
  return road.to_world(s, road.lane_center_t(lane_id, s) + offset);
}

std::optional<RoadCoordinates> RoadNetwork::world_to_road(double x, double y, const Road* hint) const {
  const auto on = [&](const Road& road) -> std::optional<RoadCoordinates> {
    const double s = project(road, x, y);
    const Pose c = road.plan_view.at(s);
    const double dx = x - c.x;
    const double dy = y - c.y;
    const double tangential = dx * std::cos(c.heading) + dy * std::sin(c.heading);
    if ((s <= 0.0 && tangential < -kEndTolerance_m) || (s >= road.length && tangential > kEndTolerance_m))
      return std::nullopt;  // before the start or past the end
    const double t = -dx * std::sin(c.heading) + dy * std::cos(c.heading);
    const auto lane = road.lane_at(s, t);
    if (!lane) return std::nullopt;
    return RoadCoordinates{&road, s, t, *lane, c.heading};
  };
  if (hint != nullptr)
    if (auto found = on(*hint)) return found;
  std::optional<RoadCoordinates> best;
  for (std::size_t i = 0; i < roads_.size(); ++i) {
    const Box& b = boxes_[i];
    if (&roads_[i] == hint || x < b.min_x || x > b.max_x || y < b.min_y || y > b.max_y) continue;
    auto found = on(roads_[i]);
    if (found && (!best || std::abs(found->t) < std::abs(best->t))) best = found;
  }
  return best;
}

namespace {

LaneContinuation entering(const Road& road, int lane_id, ContactPoint contact) {
  return contact == ContactPoint::kStart ? LaneContinuation{&road, lane_id, 0.0, Travel::kAlongS}
                                         : LaneContinuation{&road, lane_id, road.length, Travel::kAgainstS};
}

/// The link of `road` at its end `at`.
const std::optional<RoadLink>& link_at(const Road& road, ContactPoint at) {
  return at == ContactPoint::kStart ? road.predecessor : road.successor;
}

}  // namespace

std::vector<LaneContinuation> RoadNetwork::next_lanes(const Road& road, int lane_id, Travel travel) const {
  const bool forward = travel == Travel::kAlongS;
  const ContactPoint leaving = forward ? ContactPoint::kEnd : ContactPoint::kStart;
  const std::optional<RoadLink>& link = link_at(road, leaving);
  if (!link) return {};
  const LaneSection& section = forward ? road.lane_sections.back() : road.lane_sections.front();
  const Lane* lane = section.find(lane_id);
  if (lane == nullptr) return {};
  std::vector<LaneContinuation> next;
  if (link->type == ElementType::kRoad) {
    const Road* other = find_road(link->id);
    if (other == nullptr || !link->contact_point) return {};
    for (const int to : forward ? lane->successors : lane->predecessors) {
      const LaneContinuation c = entering(*other, to, *link->contact_point);
      if (other->section_at(c.s).find(to) != nullptr) next.push_back(c);
    }
    return next;
  }
  const Junction* junction = find_junction(link->id);
  if (junction == nullptr) return {};
  for (const Connection& connection : junction->connections) {
    if (connection.incoming_road != road.id) continue;
    const Road* connecting = find_road(connection.connecting_road);
    if (connecting == nullptr) continue;
    // The connecting road must meet this road's end we leave by, where its link says so.
    const std::optional<RoadLink>& back = link_at(*connecting, connection.contact_point);
    if (back && back->type == ElementType::kRoad && back->id == road.id && back->contact_point &&
        *back->contact_point != leaving)
      continue;
    for (const auto& [from, to] : connection.lane_links) {
      if (from != lane_id) continue;
      const LaneContinuation c = entering(*connecting, to, connection.contact_point);
      if (connecting->section_at(c.s).find(to) != nullptr) next.push_back(c);
    }
  }
  return next;
}

}  // namespace emrm::opendrive
