// Positions resolved to a world pose and lane coordinates (runtime.hpp), and the world state of
// the entities that hold them.

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "runtime.hpp"

namespace emrm::openscenario {

WorldPose lane_to_world(const RoadAccess& roads, const LaneCoord& at) {
  return roads.road_to_world(at.road_id, at.s_m, roads.lane_center_t(at.road_id, at.lane_id, at.s_m) + at.offset_m);
}

double s_step_for(const RoadAccess& roads, const LaneCoord& at, double distance_m) {
  constexpr double kSmallNumber = 1e-6;  // esmini's
  const double curvature = roads.curvature(at.road_id, at.s_m);
  if (std::fabs(curvature) <= kSmallNumber) return distance_m;
  const double t = roads.lane_center_t(at.road_id, at.lane_id, at.s_m) + at.offset_m;
  // Past the centre of curvature (esmini then re-attaches to another road): no scaling.
  if (curvature * t > 1.0 - kSmallNumber) return distance_m;
  return distance_m / (1.0 - curvature * t);
}

const Entity* Scenario::find_entity(const std::string& name) const {
  for (const Entity& e : entities)
    if (e.name == name) return &e;
  return nullptr;
}

namespace detail {
namespace {

double wrap(double angle) { return std::remainder(angle, 2.0 * std::numbers::pi); }

// +1 when a heading points along the road's s direction at `at`, -1 when against it.
int direction_of(const RoadAccess& roads, const LaneCoord& at, double heading_rad) {
  const double road_heading = roads.road_to_world(at.road_id, at.s_m, 0.0).heading_rad;
  return std::cos(heading_rad - road_heading) >= 0.0 ? 1 : -1;
}

// The heading of a lane's driving direction by its road's traffic rule (right-hand: the lanes
// right of the reference line, negative ids, are driven along s).
double lane_heading(const RoadAccess& roads, const LaneCoord& at) {
  const double h = lane_to_world(roads, at).heading_rad;
  return roads.driven_along_s(at.road_id, at.lane_id) ? h : h + std::numbers::pi;
}

double oriented(const std::optional<Orientation>& o, double base_rad) {
  if (!o) return base_rad;
  return o->relative ? base_rad + o->h_rad : o->h_rad;
}

// The lane coordinates of an entity a relative position refers to.
LaneCoord lane_of(const EntityState& ref, const RoadAccess& roads, const Position& position) {
  if (ref.on_lane) return ref.lane;
  const auto lane = roads.world_to_lane(ref.pose.x_m, ref.pose.y_m, nullptr);
  if (!lane)
    throw InputError(position.where, fmt::format("entity '{}' is on no road at ({}, {}), so a position relative to "
                                                 "its lane or road is undefined",
                                                 ref.spec->name, ref.pose.x_m, ref.pose.y_m));
  return *lane;
}

const RoadAccess& need_roads(const World& world, const Position& position) {
  if (world.roads == nullptr)
    throw InputError(position.where,
                     "this position needs a road network (RoadNetwork LogicFile) and the scenario has none");
  return *world.roads;
}

ResolvedPosition on_lane(const RoadAccess& roads, const LaneCoord& lane, const std::optional<Orientation>& o,
                         const Position& position) {
  if (!roads.has_road(lane.road_id))
    throw InputError(position.where, fmt::format("road '{}' does not exist in the road network", lane.road_id));
  // Lane 0, the centre lane, is a position on it (esmini's samples use it as a point to reach).
  if (lane.lane_id != 0 && !roads.has_lane(lane.road_id, lane.lane_id, lane.s_m))
    throw InputError(position.where,
                     fmt::format("road '{}' has no lane {} at s = {} m", lane.road_id, lane.lane_id, lane.s_m));
  ResolvedPosition r;
  r.lane = lane;
  r.pose = lane_to_world(roads, lane);
  r.pose.heading_rad = wrap(oriented(o, lane_heading(roads, lane)));
  r.direction = direction_of(roads, lane, r.pose.heading_rad);
  return r;
}

ResolvedPosition at_world(const World& world, WorldPose pose, const LaneCoord* hint) {
  ResolvedPosition r;
  pose.heading_rad = wrap(pose.heading_rad);
  r.pose = pose;
  if (world.roads != nullptr) {
    r.lane = world.roads->world_to_lane(pose.x_m, pose.y_m, hint);
    if (r.lane) r.direction = direction_of(*world.roads, *r.lane, pose.heading_rad);
  }
  return r;
}

// esmini's RelativeLanePosition (RoadManager's Position::ReleaseRelation): `ds` moves along the
// road's s and dLane counts towards higher lane ids, the heading relative to the road's s; `dsLane`
// moves in the driving direction of the referred entity's lane and counts dLane to its left (as
// esmini decides it: the entity heading along s in a right-hand-traffic right lane, or against s
// in a left-hand-traffic left lane), the heading relative to the new lane's driving direction.
ResolvedPosition relative_lane(const RoadAccess& roads, const LaneCoord& from, const EntityState& ref,
                               const RelativeLanePosition& p, const Position& position) {
  const bool along_s = roads.driven_along_s(from.road_id, from.lane_id);
  const double ds = p.ds_along_lane ? (along_s ? p.ds_m : -p.ds_m) : p.ds_m;
  int d_lane = p.d_lane;
  double offset = p.offset_m;
  if (p.ds_along_lane) {
    const bool rule_right = roads.driven_along_s(from.road_id, -1);
    const bool forward = ref.direction > 0;
    if (!((forward && from.lane_id < 0 && rule_right) || (!forward && from.lane_id > 0 && !rule_right))) {
      d_lane = -d_lane;
      offset = -offset;
    }
  }
  // esmini's GetRelativeLaneId: skips lane 0 when the sign changes.
  int lane = from.lane_id + d_lane;
  if (from.lane_id != 0 && d_lane != 0 && (lane == 0 || (lane > 0) != (from.lane_id > 0))) lane += d_lane > 0 ? 1 : -1;
  // As esmini: the referred entity's lane moved along, then the lane id counted from its own.
  LaneCoord at = roads.step_along({from.road_id, from.lane_id, from.s_m, 0.0}, ds).to;
  at.lane_id = lane;
  at.offset_m = offset;
  if (!roads.has_road(at.road_id))
    throw InputError(position.where, fmt::format("road '{}' does not exist in the road network", at.road_id));
  if (!roads.has_lane(at.road_id, at.lane_id, at.s_m))
    throw InputError(position.where,
                     fmt::format("road '{}' has no lane {} at s = {} m", at.road_id, at.lane_id, at.s_m));
  ResolvedPosition r;
  r.lane = at;
  r.pose = lane_to_world(roads, at);
  const double road_heading = r.pose.heading_rad;
  const double base = p.ds_along_lane ? lane_heading(roads, at) : road_heading;
  r.pose.heading_rad = wrap(oriented(p.orientation, base));
  r.direction = direction_of(roads, at, r.pose.heading_rad);
  return r;
}

}  // namespace

ResolvedPosition resolve(const World& world, const Position& position, const EntityState* subject) {
  const auto relative_to = [&](const std::string& name) -> const EntityState& { return world.entity(name); };
  return std::visit(
      [&](const auto& p) -> ResolvedPosition {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, WorldPosition>) {
          const double h = p.h_rad.value_or(0.0);
          return at_world(world, {p.x_m, p.y_m, h}, subject != nullptr && subject->on_lane ? &subject->lane : nullptr);
        } else if constexpr (std::is_same_v<P, LanePosition>) {
          return on_lane(need_roads(world, position), {p.road_id, p.lane_id, p.s_m, p.offset_m}, p.orientation,
                         position);
        } else if constexpr (std::is_same_v<P, RoadPosition>) {
          const RoadAccess& roads = need_roads(world, position);
          if (!roads.has_road(p.road_id))
            throw InputError(position.where, fmt::format("road '{}' does not exist in the road network", p.road_id));
          WorldPose pose = roads.road_to_world(p.road_id, p.s_m, p.t_m);
          pose.heading_rad = oriented(p.orientation, pose.heading_rad);
          LaneCoord hint{p.road_id, 0, p.s_m, 0.0};
          return at_world(world, pose, &hint);
        } else if constexpr (std::is_same_v<P, RelativeWorldPosition> || std::is_same_v<P, RelativeObjectPosition>) {
          const EntityState& ref = relative_to(p.entity);
          double dx = p.dx_m, dy = p.dy_m;
          if constexpr (std::is_same_v<P, RelativeObjectPosition>) {
            const double c = std::cos(ref.pose.heading_rad), s = std::sin(ref.pose.heading_rad);
            dx = c * p.dx_m - s * p.dy_m;
            dy = s * p.dx_m + c * p.dy_m;
          }
          const WorldPose pose{ref.pose.x_m + dx, ref.pose.y_m + dy, oriented(p.orientation, ref.pose.heading_rad)};
          return at_world(world, pose, ref.on_lane ? &ref.lane : nullptr);
        } else if constexpr (std::is_same_v<P, RelativeLanePosition>) {
          const RoadAccess& roads = need_roads(world, position);
          const EntityState& ref = relative_to(p.entity);
          const LaneCoord from = lane_of(ref, roads, position);
          return relative_lane(roads, from, ref, p, position);
        } else {
          static_assert(std::is_same_v<P, RelativeRoadPosition>);
          const RoadAccess& roads = need_roads(world, position);
          const EntityState& ref = relative_to(p.entity);
          const LaneCoord from = lane_of(ref, roads, position);
          const double t = roads.lane_center_t(from.road_id, from.lane_id, from.s_m) + from.offset_m;
          const LaneStep moved = roads.step_along(from, p.ds_m);
          WorldPose pose = roads.road_to_world(moved.to.road_id, moved.to.s_m, t + p.dt_m);
          pose.heading_rad = oriented(p.orientation, pose.heading_rad);
          return at_world(world, pose, &moved.to);
        }
      },
      position.kind);
}

EntityState& World::entity(const std::string& name) {
  for (EntityState& e : entities)
    if (e.spec->name == name) return e;
  throw InputError({}, fmt::format("entity '{}' does not exist", name));  // the reader checked every reference
}

const EntityState& World::entity(const std::string& name) const { return const_cast<World*>(this)->entity(name); }

void World::update_pose(EntityState& e) const {
  const WorldPose p = lane_to_world(*roads, e.lane);
  const double along = e.direction > 0 ? p.heading_rad : p.heading_rad + std::numbers::pi;
  e.pose = {p.x_m, p.y_m, wrap(along + e.heading_offset_rad)};
}

void World::place_on_lane(EntityState& e, const LaneCoord& at, int direction) const {
  e.on_lane = true;
  e.lane = at;
  e.direction = direction;
  update_pose(e);
}

bool World::place_at(EntityState& e, const WorldPose& pose) const {
  e.pose = pose;
  e.pose.heading_rad = wrap(pose.heading_rad);
  e.on_lane = false;
  if (roads != nullptr) {
    if (const auto lane = roads->world_to_lane(pose.x_m, pose.y_m, e.lane.road_id.empty() ? nullptr : &e.lane)) {
      e.lane = *lane;
      e.direction = direction_of(*roads, e.lane, pose.heading_rad);
      return true;
    }
  }
  return false;
}

}  // namespace detail
}  // namespace emrm::openscenario
