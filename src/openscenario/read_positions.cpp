// Positions as the document writes them (read_context.hpp): every road and lane a position names
// must exist in the road network.

#include <fmt/format.h>

#include "read_context.hpp"

namespace emrm::openscenario::detail {
namespace {

constexpr double kMaxCoordinate = 1e7;  // m: beyond any road network

std::optional<Orientation> read_orientation(const xml::Element& position, const ReadContext& c) {
  const auto o = position.child("Orientation");
  if (!o) return std::nullopt;
  const auto h = c.optional_number(*o, "h", "rad");
  if (!h) return std::nullopt;  // no heading: along the road, as without an Orientation (esmini)
  const auto type = c.optional_text(*o, "type");
  bool relative = c.rev_minor >= 3;  // esmini: absolute by default up to 1.2, relative from 1.3
  if (type) relative = c.choice(*o, "type", {"relative", "absolute"}) == 0;
  return Orientation{*h, relative};
}

std::string road_ref(const xml::Element& e, const ReadContext& c) {
  std::string id = c.text(e, "roadId");
  if (c.roads() == nullptr) e.fail("roadId", "roadId: the scenario has no road network (RoadNetwork LogicFile)");
  if (!c.roads()->has_road(id)) e.fail("roadId", fmt::format("roadId: road '{}' is not in the road network", id));
  return id;
}

}  // namespace

Position read_position(const xml::Element& position, const ReadContext& c) {
  const xml::Element p = c.chosen(position, "Position");
  Position out{WorldPosition{}, p.where()};
  const std::string_view kind = p.name();
  const auto orientation = read_orientation(p, c);
  if (kind == "WorldPosition") {
    out.kind = WorldPosition{c.number(p, "x", "m", -kMaxCoordinate, kMaxCoordinate),
                             c.number(p, "y", "m", -kMaxCoordinate, kMaxCoordinate), c.optional_number(p, "h", "rad")};
  } else if (kind == "LanePosition") {
    LanePosition lane{road_ref(p, c), 0, c.number(p, "s", "m", 0.0, kMaxCoordinate),
                      c.optional_number(p, "offset", "m", -100.0, 100.0).value_or(0.0), orientation};
    const std::string id = c.text(p, "laneId");
    lane.lane_id = c.integer(p, "laneId", -100, 100);
    if (lane.lane_id != 0 && !c.roads()->has_lane(lane.road_id, lane.lane_id, lane.s_m))  // 0: the centre lane
      p.fail("laneId", fmt::format("laneId: road '{}' has no lane {} at s = {} m", lane.road_id, id, lane.s_m));
    out.kind = lane;
  } else if (kind == "RoadPosition") {
    out.kind = RoadPosition{road_ref(p, c), c.number(p, "s", "m", 0.0, kMaxCoordinate),
                            c.number(p, "t", "m", -1000.0, 1000.0), orientation};
  } else if (kind == "RelativeWorldPosition") {
    out.kind =
        RelativeWorldPosition{c.entity_ref(p, "entityRef"), c.number(p, "dx", "m", -kMaxCoordinate, kMaxCoordinate),
                              c.number(p, "dy", "m", -kMaxCoordinate, kMaxCoordinate), orientation};
  } else if (kind == "RelativeObjectPosition") {
    out.kind =
        RelativeObjectPosition{c.entity_ref(p, "entityRef"), c.number(p, "dx", "m", -kMaxCoordinate, kMaxCoordinate),
                               c.number(p, "dy", "m", -kMaxCoordinate, kMaxCoordinate), orientation};
  } else if (kind == "RelativeLanePosition") {
    RelativeLanePosition r{c.entity_ref(p, "entityRef"),
                           c.integer(p, "dLane", -100, 100),
                           0.0,
                           false,
                           c.optional_number(p, "offset", "m", -100.0, 100.0).value_or(0.0),
                           orientation};
    const auto ds = c.optional_number(p, "ds", "m", -kMaxCoordinate, kMaxCoordinate);
    const auto ds_lane = c.optional_number(p, "dsLane", "m", -kMaxCoordinate, kMaxCoordinate);
    if (ds.has_value() == ds_lane.has_value()) p.fail("<RelativeLanePosition> needs exactly one of ds and dsLane");
    r.ds_m = ds.value_or(ds_lane.value_or(0.0));
    r.ds_along_lane = ds_lane.has_value();
    out.kind = r;
  } else {
    out.kind =
        RelativeRoadPosition{c.entity_ref(p, "entityRef"), c.number(p, "ds", "m", -kMaxCoordinate, kMaxCoordinate),
                             c.number(p, "dt", "m", -1000.0, 1000.0), orientation};
  }
  return out;
}

}  // namespace emrm::openscenario::detail
