// The OpenDRIVE road network of a cell (opendrive.hpp).

#include "emrm/exchange/opendrive.hpp"

#include <algorithm>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "emrm/sim/family.hpp"
#include "export_support.hpp"
#include "xml_writer.hpp"

namespace emrm::exchange {
namespace {

using Attributes = XmlWriter::Attributes;
using detail::kDate;
using detail::num;

constexpr int kJunctionId = 100;
constexpr double kApproach_m = 100.0;       // main road before the ego's start
constexpr double kRunOut_m = 300.0;         // main road after the junction: the recovery's room
constexpr double kSideRoadMargin_m = 30.0;  // side road beyond the truck's rear at t = 0

// The document's header: OpenDRIVE 1.6, the fixed date, and the network's bounds in the road frame.
void header(XmlWriter& x, const std::string& name, double north, double south, double east, double west) {
  x.leaf("header", {{"revMajor", "1"},
                    {"revMinor", "6"},
                    {"name", name},
                    {"version", "1"},
                    {"date", kDate},
                    {"north", num(north)},
                    {"south", num(south)},
                    {"east", num(east)},
                    {"west", num(west)},
                    {"vendor", "emrm"}});
}

void width(XmlWriter& x, double w) {
  x.leaf("width", {{"sOffset", "0"}, {"a", num(w)}, {"b", "0"}, {"c", "0"}, {"d", "0"}});
}

void road_mark(XmlWriter& x, const char* type) {
  x.leaf("roadMark", {{"sOffset", "0"}, {"type", type}, {"color", "standard"}, {"width", "0.12"}});
}

// A lane of a junction's connecting road names the lanes it joins (its predecessor on the incoming
// road, its successor on the outgoing one), so that an engine moving along the lanes finds its way
// through the junction; other lanes end at the junction, whose laneLinks say the rest.
struct LaneLink {
  int predecessor = 0;  // 0: none
  int successor = 0;
};

void lane(XmlWriter& x, int id, const char* type, double w, const char* mark, LaneLink link = {}) {
  x.open("lane", {{"id", std::to_string(id)}, {"type", type}, {"level", "false"}});
  if (link.predecessor != 0 || link.successor != 0) {
    x.open("link");
    if (link.predecessor != 0) x.leaf("predecessor", {{"id", std::to_string(link.predecessor)}});
    if (link.successor != 0) x.leaf("successor", {{"id", std::to_string(link.successor)}});
    x.close();
  }
  width(x, w);
  road_mark(x, mark);
  x.close();
}

void center_lane(XmlWriter& x) {
  x.open("center");
  x.open("lane", {{"id", "0"}, {"type", "none"}, {"level", "false"}});
  road_mark(x, "broken");
  x.close();
  x.close();
}

// The main road's cross-section: left driving lanes, the centre lane, right driving lanes, then
// the paved shoulder. `linked`: inside the junction, each lane joins the same lane before and after.
void main_road_lanes(XmlWriter& x, const sim::RoadConfig& road, const JunctionLayout& l, bool linked = false) {
  const auto same = [&](int id) { return linked ? LaneLink{id, id} : LaneLink{}; };
  x.open("lanes");
  x.open("laneSection", {{"s", "0"}});
  if (l.left_lanes > 0) {
    x.open("left");
    for (int id = l.left_lanes; id >= 1; --id)
      lane(x, id, "driving", road.lane_width_m, id == l.left_lanes ? "solid" : "broken", same(id));
    x.close();
  }
  center_lane(x);
  x.open("right");
  for (int id = 1; id <= l.right_lanes; ++id)
    lane(x, -id, "driving", road.lane_width_m, id == l.right_lanes ? "solid" : "broken", same(-id));
  if (road.shoulder_m > 0.0)
    lane(x, -(l.right_lanes + 1), "shoulder", road.shoulder_m, "none", same(-(l.right_lanes + 1)));
  x.close();
  x.close();
  x.close();
}

void straight(XmlWriter& x, double s, double x0, double y0, double heading, double length) {
  x.open("geometry", {{"s", num(s)}, {"x", num(x0)}, {"y", num(y0)}, {"hdg", num(heading)}, {"length", num(length)}});
  x.leaf("line");
  x.close();
}

void arc(XmlWriter& x, double s, double x0, double y0, double heading, double length, double curvature) {
  x.open("geometry", {{"s", num(s)}, {"x", num(x0)}, {"y", num(y0)}, {"hdg", num(heading)}, {"length", num(length)}});
  x.leaf("arc", {{"curvature", num(curvature)}});
  x.close();
}

struct Link {
  const char* type;  // "road" or "junction"
  int id;
  const char* contact;  // "start", "end" or nullptr (junctions)
};

void links(XmlWriter& x, const Link* predecessor, const Link* successor) {
  x.open("link");
  for (const auto& [tag, l] : {std::pair{"predecessor", predecessor}, std::pair{"successor", successor}}) {
    if (l == nullptr) continue;
    Attributes a{{"elementType", l->type}, {"elementId", std::to_string(l->id)}};
    if (l->contact != nullptr) a.emplace_back("contactPoint", l->contact);
    x.leaf(tag, a);
  }
  x.close();
}

// The right turn from the side road's left lane into road 1's left lane: a straight down to the
// height where a quarter circle of radius min(lane width, drop) meets road 1's reference line,
// then a straight to road 1's end.
void turn_geometry(XmlWriter& x, const JunctionLayout& l, double lane_width_m) {
  const double drop_m = l.side_road_start_y_m - l.reference_line_y_m;
  const double radius = std::min(lane_width_m, drop_m);
  double s = 0.0;
  double px = l.side_road_x_m;
  double py = l.side_road_start_y_m;
  if (drop_m - radius > 1e-9) {
    straight(x, s, px, py, -std::numbers::pi / 2.0, drop_m - radius);
    s += drop_m - radius;
    py -= drop_m - radius;
  }
  const double arc_length = std::numbers::pi / 2.0 * radius;
  arc(x, s, px, py, -std::numbers::pi / 2.0, arc_length, -1.0 / radius);
  s += arc_length;
  px -= radius;
  py -= radius;
  if (lane_width_m - radius > 1e-9) straight(x, s, px, py, std::numbers::pi, lane_width_m - radius);
}

double turn_length(const JunctionLayout& l, double lane_width_m) {
  const double drop_m = l.side_road_start_y_m - l.reference_line_y_m;
  const double radius = std::min(lane_width_m, drop_m);
  return (drop_m - radius) + std::numbers::pi / 2.0 * radius + (lane_width_m - radius);
}

void one_lane_road_lanes(XmlWriter& x, double lane_width_m, LaneLink link) {
  x.open("lanes");
  x.open("laneSection", {{"s", "0"}});
  center_lane(x);
  x.open("right");
  lane(x, -1, "driving", lane_width_m, "none", link);
  x.close();
  x.close();
  x.close();
}

// A straight road's lanes from the family (sim::RoadLane), from the right edge leftwards: one
// driving lane over the drivable width when the family names none.
std::vector<sim::RoadLane> lanes_of(const sim::SceneConfig& config, const sim::Road& road) {
  const auto family = sim::find_family(config.family);
  if (!family->lanes) return {{road.width_m(), "driving"}};
  return family->lanes(config);
}

}  // namespace

JunctionLayout junction_layout(const sim::SceneConfig& config, const sim::CellInput& cell) {
  const sim::RoadConfig& road = config.road;
  const double w = road.lane_width_m;
  JunctionLayout l;
  l.left_lanes = road.lanes / 2;
  l.right_lanes = road.lanes - l.left_lanes;
  l.reference_line_y_m = road.drivable_max_y_m() - l.left_lanes * w;
  const sim::Scene scene(config, cell);
  const double truck_x = scene.hazard_at(0.0).box.center.x;
  l.side_road_x_m = truck_x + w / 2.0;
  l.junction_min_x_m = l.side_road_x_m - w;
  l.junction_max_x_m = l.side_road_x_m + w;
  l.main_start_x_m = std::min(-kApproach_m - config.ego.length_m, l.junction_min_x_m - kApproach_m);
  l.main_end_x_m = l.junction_max_x_m + kRunOut_m;
  l.side_road_start_y_m = road.drivable_max_y_m();
  const double truck_rear_y = scene.hazard_at(0.0).box.center.y + config.truck.length_m / 2.0;
  l.side_road_length_m = std::max(truck_rear_y - l.side_road_start_y_m, 0.0) + kSideRoadMargin_m;
  return l;
}

std::string opendrive_xml(const sim::SceneConfig& config, const sim::CellInput& cell) {
  const JunctionLayout l = junction_layout(config, cell);
  const double w = config.road.lane_width_m;
  XmlWriter x;
  x.open("OpenDRIVE");
  header(x, config.name, l.side_road_start_y_m + l.side_road_length_m, config.road.drivable_min_y_m(), l.main_end_x_m,
         l.main_start_x_m);
  const Link junction{"junction", kJunctionId, nullptr};
  // Roads 1 and 2: the main road up to the junction (where the ego comes from) and beyond it.
  const auto main_road = [&](const char* name, const char* id, double from_x, double to_x, const Link* predecessor,
                             const Link* successor) {
    x.open("road", {{"name", name}, {"length", num(to_x - from_x)}, {"id", id}, {"junction", "-1"}, {"rule", "RHT"}});
    links(x, predecessor, successor);
    x.open("planView");
    straight(x, 0.0, from_x, l.reference_line_y_m, 0.0, to_x - from_x);
    x.close();
    main_road_lanes(x, config.road, l);
    x.close();
  };
  main_road("main_road_approach", "1", l.main_start_x_m, l.junction_min_x_m, nullptr, &junction);
  main_road("main_road_exit", "2", l.junction_max_x_m, l.main_end_x_m, &junction, nullptr);
  // Road 3: the side road on the left, heading away from the junction (+y); the truck comes down
  // its left lane.
  x.open(
      "road",
      {{"name", "side_road"}, {"length", num(l.side_road_length_m)}, {"id", "3"}, {"junction", "-1"}, {"rule", "RHT"}});
  links(x, &junction, nullptr);
  x.open("planView");
  straight(x, 0.0, l.side_road_x_m, l.side_road_start_y_m, std::numbers::pi / 2.0, l.side_road_length_m);
  x.close();
  x.open("lanes");
  x.open("laneSection", {{"s", "0"}});
  x.open("left");
  lane(x, 1, "driving", w, "solid");
  x.close();
  center_lane(x);
  x.open("right");
  lane(x, -1, "driving", w, "solid");
  x.close();
  x.close();
  x.close();
  x.close();
  // Road 4: through the junction along the main road.
  const Link from_approach{"road", 1, "end"};
  const Link to_exit{"road", 2, "start"};
  x.open("road", {{"name", "junction_through"},
                  {"length", num(l.junction_max_x_m - l.junction_min_x_m)},
                  {"id", "4"},
                  {"junction", std::to_string(kJunctionId)},
                  {"rule", "RHT"}});
  links(x, &from_approach, &to_exit);
  x.open("planView");
  straight(x, 0.0, l.junction_min_x_m, l.reference_line_y_m, 0.0, l.junction_max_x_m - l.junction_min_x_m);
  x.close();
  main_road_lanes(x, config.road, l, true);
  x.close();
  // Road 5: from the side road's left lane, turning right into the approach's left lane (when the
  // main road has lanes left of its reference line).
  const bool turn = l.left_lanes > 0;
  if (turn) {
    const Link from_side{"road", 3, "start"};
    const Link to_approach{"road", 1, "end"};
    x.open("road", {{"name", "junction_side_turn"},
                    {"length", num(turn_length(l, w))},
                    {"id", "5"},
                    {"junction", std::to_string(kJunctionId)},
                    {"rule", "RHT"}});
    links(x, &from_side, &to_approach);
    x.open("planView");
    turn_geometry(x, l, w);
    x.close();
    // From the side road's left lane into the approach's innermost left lane.
    one_lane_road_lanes(x, w, {1, 1});
    x.close();
  }
  x.open("junction", {{"name", "tjunction"}, {"id", std::to_string(kJunctionId)}});
  x.open("connection", {{"id", "0"}, {"incomingRoad", "1"}, {"connectingRoad", "4"}, {"contactPoint", "start"}});
  for (int id = 1; id <= l.right_lanes; ++id)
    x.leaf("laneLink", {{"from", std::to_string(-id)}, {"to", std::to_string(-id)}});
  x.close();
  if (turn) {
    x.open("connection", {{"id", "1"}, {"incomingRoad", "3"}, {"connectingRoad", "5"}, {"contactPoint", "start"}});
    x.leaf("laneLink", {{"from", "1"}, {"to", "-1"}});
    x.close();
  }
  x.close();
  x.close();
  return std::move(x).str();
}

std::string straight_road_xml(const sim::SceneConfig& config, const sim::CellInput& cell) {
  const sim::Scene scene(config, cell);
  const sim::Road& road = scene.road();
  const std::vector<sim::RoadLane> lanes = lanes_of(config, road);
  // The reference line between the lanes of the ego's direction (right of it, ids −1 …) and the
  // oncoming ones (left of it, ids 1 …).
  double reference_y = road.min_y_m;
  for (const auto& l : lanes)
    if (!l.oncoming) reference_y += l.width_m;
  // Long enough for the whole run at the ego's speed, past the hazard.
  const double run_s = config.simulation.horizon_s + config.safe_state.horizon_s;
  const double start_x = -kApproach_m - config.ego.length_m;
  const double end_x = scene.initial_distance_m() + std::max(kRunOut_m, scene.initial_speed_mps() * run_s);
  XmlWriter x;
  x.open("OpenDRIVE");
  header(x, config.name, road.max_y_m, road.min_y_m, end_x, start_x);
  x.open("road",
         {{"name", config.family}, {"length", num(end_x - start_x)}, {"id", "1"}, {"junction", "-1"}, {"rule", "RHT"}});
  x.open("planView");
  straight(x, 0.0, start_x, reference_y, 0.0, end_x - start_x);
  x.close();
  x.open("lanes");
  x.open("laneSection", {{"s", "0"}});
  const auto side = [&](const char* tag, bool oncoming, int sign) {
    std::vector<const sim::RoadLane*> these;
    for (const auto& l : lanes)
      if (l.oncoming == oncoming) these.push_back(&l);
    if (these.empty()) return;
    if (!oncoming) std::reverse(these.begin(), these.end());  // outwards from the reference line
    x.open(tag);
    // Left lanes are written outermost first (descending ids), right lanes innermost first.
    for (std::size_t k = 0; k < these.size(); ++k) {
      const std::size_t i = oncoming ? these.size() - 1 - k : k;
      const bool outermost = i + 1 == these.size();
      lane(x, sign * static_cast<int>(i + 1), these[i]->type.c_str(), these[i]->width_m,
           these[i]->type != "driving" ? "none"
           : outermost                 ? "solid"
                                       : "broken");
    }
    x.close();
  };
  side("left", true, 1);
  center_lane(x);
  side("right", false, -1);
  x.close();
  x.close();
  x.close();
  x.close();
  return std::move(x).str();
}

}  // namespace emrm::exchange
