#include "emrm/exchange/openscenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "emrm/campaign/campaign.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/version.hpp"
#include "xml_writer.hpp"

namespace emrm::exchange {
namespace {

namespace fs = std::filesystem;
using Attributes = XmlWriter::Attributes;

using sim::kKphPerMps;
constexpr int kJunctionId = 100;
constexpr double kApproach_m = 100.0;   // main road before the ego's start
constexpr double kRunOut_m = 300.0;     // main road after the junction: the recovery's room
constexpr double kSideRoadMargin_m = 30.0;  // side road beyond the truck's rear at t = 0

// A fixed date keeps the export reproducible (the files are compared in tests and by diff).
constexpr const char* kDate = "2026-01-01T00:00:00";

std::string num(double x) { return xml_number(x); }

// " + 1.25" or " - 3.75": a constant appended to an expression.
std::string plus(double c) { return c < 0.0 ? " - " + num(-c) : " + " + num(c); }

// A quantity of the scenario: its value for one cell, and the expression of the logical
// scenario's parameters that gives it (empty: a constant).
struct Quantity {
  double value = 0.0;
  std::string expression;
  [[nodiscard]] std::string text(bool parametric) const {
    return parametric && !expression.empty() ? expression : num(value);
  }
};

struct Initial {
  Quantity ego_x, ego_y, ego_speed, truck_x, truck_y, truck_speed, mu;
};

Initial initial_of(const sim::SceneConfig& config, const sim::CellInput& cell, const ExportOptions& options) {
  const sim::Scene scene(config, cell);
  const sim::VehicleState ego = scene.ego_initial();
  const sim::TruckState truck = scene.truck_at(0.0);
  const double ego_back = ego_reference_offset_m(config.ego);
  const double truck_back = truck_reference_offset_m(config.truck, options);
  Initial i;
  i.ego_x = {ego.x_m - ego_back, ""};
  i.ego_y = {ego.y_m, ""};
  i.ego_speed = {ego.vx_mps, "${$speed_kph / 3.6}"};
  // The truck heads -y: its rear axle is above its centre.
  i.truck_x = {truck.box.center.x, "${$speed_kph / 3.6 * $ttc_s" + plus(config.truck.width_m / 2.0) + "}"};
  const double y_constant = config.road.drivable_min_y_m() + config.truck.length_m / 2.0 + truck_back;
  const std::string travel = config.truck.decel_mps2 > 0.0
                                 ? "$truck_speed_kph / 3.6 * $truck_speed_kph / 3.6 / " +
                                       num(2.0 * config.truck.decel_mps2)
                                 : "$truck_speed_kph / 3.6 * $ttc_s";
  i.truck_y = {truck.box.center.y + truck_back, "${$passage_m + " + travel + plus(y_constant) + "}"};
  i.truck_speed = {cell.truck_speed_kph / kKphPerMps, "${$truck_speed_kph / 3.6}"};
  i.mu = {cell.mu, "$mu"};
  return i;
}

// ---- OpenDRIVE ---------------------------------------------------------------------------------

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

// ---- OpenSCENARIO ------------------------------------------------------------------------------

void file_header(XmlWriter& x, const std::string& description) {
  x.leaf("FileHeader", {{"revMajor", "1"},
                        {"revMinor", "2"},
                        {"date", kDate},
                        {"description", description},
                        {"author", fmt::format("emrm {}", kVersion)}});
}

void time_condition(XmlWriter& x, const std::string& name, const char* rule, double t_s) {
  x.open("ConditionGroup");
  x.open("Condition", {{"name", name}, {"delay", "0"}, {"conditionEdge", "none"}});
  x.open("ByValueCondition");
  x.leaf("SimulationTimeCondition", {{"value", num(t_s)}, {"rule", rule}});
  x.close();
  x.close();
  x.close();
}

void start_at_zero(XmlWriter& x, const std::string& name) {
  x.open("StartTrigger");
  time_condition(x, name, "greaterOrEqual", 0.0);
  x.close();
}

void bounding_box(XmlWriter& x, double center_x, double height, double length, double width) {
  x.open("BoundingBox");
  x.leaf("Center", {{"x", num(center_x)}, {"y", "0"}, {"z", num(height / 2.0)}});
  x.leaf("Dimensions", {{"width", num(width)}, {"length", num(length)}, {"height", num(height)}});
  x.close();
}

void axles(XmlWriter& x, double wheelbase, double max_steer, double track, double wheel_diameter) {
  x.open("Axles");
  x.leaf("FrontAxle", {{"maxSteering", num(max_steer)},
                       {"wheelDiameter", num(wheel_diameter)},
                       {"trackWidth", num(track)},
                       {"positionX", num(wheelbase)},
                       {"positionZ", num(wheel_diameter / 2.0)}});
  x.leaf("RearAxle", {{"maxSteering", "0"},
                      {"wheelDiameter", num(wheel_diameter)},
                      {"trackWidth", num(track)},
                      {"positionX", "0"},
                      {"positionZ", num(wheel_diameter / 2.0)}});
  x.close();
}

// esmini's own switch (an entity property, which other engines ignore): the heading interpolated
// linearly over each segment of a trajectory, so that it is the vertices' at their times. Without
// it, followingMode "position" makes esmini blend the headings of neighbouring vertices, half a
// step late, and snap to the last one at the end (docs/openscenario.md, "esmini").
void pline_interpolation(XmlWriter& x) { x.leaf("Property", {{"name", "plineInterpolation"}, {"value", "segment"}}); }

void entities(XmlWriter& x, const sim::SceneConfig& config, const ExportOptions& options) {
  const sim::VehicleParams& ego = config.ego;
  const sim::TruckConfig& truck = config.truck;
  x.open("Entities");
  x.open("ScenarioObject", {{"name", kEgoEntity}});
  x.open("Vehicle", {{"name", "emrm_ego"}, {"vehicleCategory", "car"}, {"mass", num(ego.mass_kg)}});
  // The box's centre ahead of the rear axle: CG to rear axle plus the CG's offset from the middle.
  bounding_box(x, ego_reference_offset_m(ego) + (ego.cg_to_front_m() - ego.cg_to_rear_m()) / 2.0, options.ego_height_m,
               ego.length_m, ego.width_m);
  x.leaf("Performance", {{"maxSpeed", num(options.ego_max_speed_mps)},
                         {"maxAcceleration", num(options.ego_max_acceleration_mps2)},
                         {"maxDeceleration", num(config.actuation.full_decel_mps2(2.0))}});
  axles(x, ego.wheelbase_m(), ego.max_steer_rad, std::max(ego.width_m - 0.2, 0.1), options.ego_wheel_diameter_m);
  x.open("Properties");
  x.leaf("Property", {{"name", "yaw_inertia_kgm2"}, {"value", num(ego.yaw_inertia_kgm2)}});
  x.leaf("Property", {{"name", "cg_to_rear_axle_m"}, {"value", num(ego.cg_to_rear_axle_m)}});
  pline_interpolation(x);
  x.close();
  x.close();
  x.close();

  x.open("ScenarioObject", {{"name", kTruckEntity}});
  x.open("Vehicle", {{"name", "emrm_truck"}, {"vehicleCategory", "truck"}, {"mass", num(truck.mass_kg)}});
  bounding_box(x, truck_reference_offset_m(truck, options), options.truck_height_m, truck.length_m, truck.width_m);
  x.leaf("Performance", {{"maxSpeed", num(options.truck_max_speed_mps)},
                         {"maxAcceleration", num(options.truck_max_acceleration_mps2)},
                         {"maxDeceleration", num(std::max(truck.decel_mps2, options.truck_max_acceleration_mps2))}});
  const double overhang = options.truck_rear_axle_share * truck.length_m;
  axles(x, truck.length_m - 2.0 * overhang, 0.6, std::max(truck.width_m - 0.3, 0.1), options.truck_wheel_diameter_m);
  x.open("Properties");
  x.leaf("Property", {{"name", "yaw_inertia_kgm2"}, {"value", num(truck.yaw_inertia_kgm2)}});
  pline_interpolation(x);
  x.close();
  x.close();
  x.close();
  x.close();
}

void world_position(XmlWriter& x, const std::string& px, const std::string& py, const std::string& heading) {
  x.open("Position");
  x.leaf("WorldPosition", {{"x", px}, {"y", py}, {"z", "0"}, {"h", heading}, {"p", "0"}, {"r", "0"}});
  x.close();
}

void speed_action(XmlWriter& x, const char* shape, const char* dimension, const std::string& value,
                  const std::string& target) {
  x.open("LongitudinalAction");
  x.open("SpeedAction");
  x.leaf("SpeedActionDynamics", {{"dynamicsShape", shape}, {"value", value}, {"dynamicsDimension", dimension}});
  x.open("SpeedActionTarget");
  x.leaf("AbsoluteTargetSpeed", {{"value", target}});
  x.close();
  x.close();
  x.close();
}

void init(XmlWriter& x, const Initial& i, bool parametric) {
  x.open("Init");
  x.open("Actions");
  x.open("GlobalAction");
  x.open("EnvironmentAction");
  x.open("Environment", {{"name", "emrm_road"}});
  x.leaf("RoadCondition", {{"frictionScaleFactor", i.mu.text(parametric)}});
  x.close();
  x.close();
  x.close();
  const std::string truck_heading = num(-std::numbers::pi / 2.0);
  for (const auto& [entity, px, py, heading, speed] :
       {std::tuple{kEgoEntity, &i.ego_x, &i.ego_y, std::string("0"), &i.ego_speed},
        std::tuple{kTruckEntity, &i.truck_x, &i.truck_y, truck_heading, &i.truck_speed}}) {
    x.open("Private", {{"entityRef", entity}});
    x.open("PrivateAction");
    x.open("TeleportAction");
    world_position(x, px->text(parametric), py->text(parametric), heading);
    x.close();
    x.close();
    x.open("PrivateAction");
    speed_action(x, "step", "time", "0", speed->text(parametric));
    x.close();
    x.close();
  }
  x.close();
  x.close();
}

void maneuver_group(XmlWriter& x, const std::string& name, const char* entity) {
  x.open("ManeuverGroup", {{"name", name}, {"maximumExecutionCount", "1"}});
  x.open("Actors", {{"selectTriggeringEntities", "false"}});
  x.leaf("EntityRef", {{"entityRef", entity}});
  x.close();
}

void maneuver_group_end(XmlWriter& x, const std::string& trigger) {
  start_at_zero(x, trigger);
  x.close();
  x.close();
  x.close();
}

// A FollowTrajectoryAction along a timed polyline (absolute times from the hazard); `vertex`
// writes the position of the k-th of `times`.
template <class Vertex>
void follow_trajectory(XmlWriter& x, const std::string& name, const std::vector<double>& times, Vertex&& vertex) {
  x.open("PrivateAction");
  x.open("RoutingAction");
  x.open("FollowTrajectoryAction");
  x.open("TrajectoryRef");
  x.open("Trajectory", {{"name", name}, {"closed", "false"}});
  x.open("Shape");
  x.open("Polyline");
  for (std::size_t k = 0; k < times.size(); ++k) {
    x.open("Vertex", {{"time", num(times[k])}});
    vertex(k);
    x.close();
  }
  x.close();
  x.close();
  x.close();
  x.close();
  x.open("TimeReference");
  x.leaf("Timing", {{"domainAbsoluteRelative", "absolute"}, {"scale", "1"}, {"offset", "0"}});
  x.close();
  x.leaf("TrajectoryFollowingMode", {{"followingMode", "position"}});
  x.close();
  x.close();
  x.close();
}

// The times of the truck's polyline: every frame while it moves, the moment it comes to rest (the
// latest of the scenarios the file stands for), and the end of the run; a truck that does not brake
// moves on a straight line at one speed, which its two ends give exactly.
std::vector<double> truck_vertex_times(const sim::SceneConfig& config, double rest_s, double end_s) {
  if (!(config.truck.decel_mps2 > 0.0)) return {0.0, end_s};
  const double dt = config.simulation.dt_s;
  const double moving_s = std::min(rest_s, end_s);
  std::vector<double> times;
  for (int k = 0; static_cast<double>(k) * dt < moving_s - 1e-9; ++k) times.push_back(static_cast<double>(k) * dt);
  times.push_back(moving_s);
  if (end_s > moving_s + 1e-9) times.push_back(end_s);
  return times;
}

// The y of the truck's rear axle at time t: where the scene's truck is (Scene::truck_at), or for
// the logical scenario the expression of the parameters that gives it: the passage plus the travel
// still ahead of the truck, max(v − a·t, 0)² / 2a, its max written with the standard's operators as
// (w + sqrt(w·w)) / 2.
std::string truck_y_at(const sim::Scene& scene, const ExportOptions& options, double t_s, bool parametric) {
  const sim::SceneConfig& config = scene.config();
  const double back = truck_reference_offset_m(config.truck, options);
  if (!parametric) return num(scene.truck_at(t_s).box.center.y + back);
  const double y_constant = config.road.drivable_min_y_m() + config.truck.length_m / 2.0 + back;
  const double a = config.truck.decel_mps2;
  std::string ahead;
  if (a > 0.0) {
    const std::string w = "($truck_speed_kph / 3.6" + plus(-a * t_s) + ")";
    const std::string moving = "((" + w + " + sqrt(" + w + " * " + w + ")) / 2)";
    ahead = moving + " * " + moving + " / " + num(2.0 * a);
  } else {
    ahead = "$truck_speed_kph / 3.6 * ($ttc_s" + plus(-t_s) + ")";
  }
  return "${$passage_m + " + ahead + plus(y_constant) + "}";
}

// The truck: its driver brakes from t = 0 at the scene's deceleration to a standstill (or, without
// braking, keeps its speed), as a timed trajectory of the scene's motion: a simulator then has the
// truck where the cell has it at every frame, instead of integrating a SpeedAction its own way
// (esmini's semi-implicit step leaves it v·dt/2 short of the cell's passage).
void truck_maneuver(XmlWriter& x, const sim::SceneConfig& config, const sim::CellInput& cell, const Initial& i,
                    const ExportOptions& options, bool parametric, double rest_s, double end_s) {
  maneuver_group(x, "TruckManeuverGroup", kTruckEntity);
  x.open("Maneuver", {{"name", "TruckCrossing"}});
  x.open("Event", {{"name", "TruckBrakes"}, {"priority", "override"}, {"maximumExecutionCount", "1"}});
  x.open("Action", {{"name", "TruckBrakeToStop"}});
  const sim::Scene scene(config, cell);
  const std::vector<double> times = truck_vertex_times(config, rest_s, end_s);
  const std::string truck_x = i.truck_x.text(parametric);
  const std::string heading = num(-std::numbers::pi / 2.0);
  follow_trajectory(x, "emrm_truck", times, [&](std::size_t k) {
    world_position(x, truck_x, truck_y_at(scene, options, times[k], parametric), heading);
  });
  x.close();
  maneuver_group_end(x, "TruckBrakesAtHazard");
}

// The ego follows its executed trajectory, reference point (rear axle) at each vertex's time.
void ego_maneuver(XmlWriter& x, const sim::SceneConfig& config, const EgoTrajectory& trajectory,
                  const std::vector<sim::PathPoint>& vertices) {
  const double back = ego_reference_offset_m(config.ego);
  maneuver_group(x, "EgoManeuverGroup", kEgoEntity);
  x.open("Maneuver", {{"name", "EgoExecutedTrajectory"}});
  x.open("Event", {{"name", "EgoFollowsTrajectory"}, {"priority", "override"}, {"maximumExecutionCount", "1"}});
  x.open("Action", {{"name", "EgoFollowTrajectory"}});
  std::vector<double> times;
  for (const auto& p : vertices) times.push_back(p.t_s);
  follow_trajectory(x, "emrm_" + trajectory.strategy, times, [&](std::size_t k) {
    const auto& s = vertices[k].state;
    world_position(x, num(s.x_m - back * std::cos(s.yaw_rad)), num(s.y_m - back * std::sin(s.yaw_rad)),
                   num(s.yaw_rad));
  });
  x.close();
  maneuver_group_end(x, "EgoStartsAtHazard");
}

void parameter_declarations(XmlWriter& x, const sim::CellInput& cell, const std::string& road_file,
                            const std::string& scenario_id) {
  x.open("ParameterDeclarations");
  for (const auto& [name, value] : {std::pair{"speed_kph", cell.speed_kph}, std::pair{"ttc_s", cell.ttc_s},
                                    std::pair{"mu", cell.mu}, std::pair{"passage_m", cell.passage_m},
                                    std::pair{"truck_speed_kph", cell.truck_speed_kph}})
    x.leaf("ParameterDeclaration", {{"name", name}, {"parameterType", "double"}, {"value", num(value)}});
  x.leaf("ParameterDeclaration", {{"name", "road_network"}, {"parameterType", "string"}, {"value", road_file}});
  x.leaf("ParameterDeclaration", {{"name", "scenario_id"}, {"parameterType", "string"}, {"value", scenario_id}});
  x.close();
}

// `truck_rest_s`: when the truck comes to rest (the latest over the scenarios a logical scenario
// stands for), infinite when it does not brake.
std::string scenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell, const EgoTrajectory* trajectory,
                         const ExportOptions& options, const std::string& road_file, bool parametric,
                         const std::string& scenario_id, double truck_rest_s) {
  const Initial i = initial_of(config, cell, options);
  std::vector<sim::PathPoint> vertices;
  if (trajectory != nullptr)
    vertices = ended_on_frame_grid(thin_path(with_final_stop(trajectory->path, config.simulation.dt_s), options.tolerance_m),
                                   config.simulation.dt_s);
  // The storyboard ends with the trajectory (the ego's final state), else after the longest run
  // the simulator would make: the horizon, then the recovery after the truck.
  const double end_s = !vertices.empty() ? vertices.back().t_s : config.simulation.horizon_s + config.safe_state.horizon_s;
  XmlWriter x;
  x.open("OpenSCENARIO");
  file_header(x, parametric ? fmt::format("{}: logical scenario of an emrm plan", config.name)
                            : fmt::format("{}: speed {} km/h, TTC {} s, mu {}, passage {} m, truck {} km/h{}",
                                          config.name, cell.speed_kph, cell.ttc_s, cell.mu, cell.passage_m,
                                          cell.truck_speed_kph,
                                          trajectory != nullptr ? ", strategy " + trajectory->strategy : ""));
  parameter_declarations(x, cell, road_file, scenario_id);
  x.leaf("CatalogLocations");
  x.open("RoadNetwork");
  x.leaf("LogicFile", {{"filepath", parametric ? "$road_network" : road_file}});
  x.close();
  entities(x, config, options);
  x.open("Storyboard");
  init(x, i, parametric);
  x.open("Story", {{"name", "EmrmStory"}});
  x.open("Act", {{"name", "EmrmAct"}});
  truck_maneuver(x, config, cell, i, options, parametric, truck_rest_s, end_s);
  if (!vertices.empty()) ego_maneuver(x, config, *trajectory, vertices);
  start_at_zero(x, "ActStartsAtHazard");
  x.close();
  x.close();
  x.open("StopTrigger");
  time_condition(x, "EndOfRun", "greaterOrEqual", end_s);
  x.close();
  x.close();
  x.close();
  return std::move(x).str();
}

// When the cell's truck comes to rest (infinite when it does not brake).
double truck_rest_s(const sim::SceneConfig& config, const sim::CellInput& cell) {
  return config.truck.decel_mps2 > 0.0 ? cell.truck_speed_kph / kKphPerMps / config.truck.decel_mps2
                                       : std::numeric_limits<double>::infinity();
}

void require_feasible(const sim::SceneConfig& config, const sim::CellInput& cell) {
  sim::validate_cell(config, cell);
  if (!sim::Scene(config, cell).feasible())
    throw UsageError(fmt::format("the cell is infeasible: the truck would appear {} m ahead (v·TTC), beyond the "
                                 "scene's max_initial_distance_m = {} m",
                                 cell.speed_kph / kKphPerMps * cell.ttc_s, config.max_initial_distance_m));
}

std::string road_file_of(const JunctionLayout& l) {
  return fmt::format("{}/tjunction_x{:.3f}.xodr", kRoadsFolder, l.side_road_x_m);
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
  const double truck_x = scene.truck_at(0.0).box.center.x;
  l.side_road_x_m = truck_x + w / 2.0;
  l.junction_min_x_m = l.side_road_x_m - w;
  l.junction_max_x_m = l.side_road_x_m + w;
  l.main_start_x_m = std::min(-kApproach_m - config.ego.length_m, l.junction_min_x_m - kApproach_m);
  l.main_end_x_m = l.junction_max_x_m + kRunOut_m;
  l.side_road_start_y_m = road.drivable_max_y_m();
  const double truck_rear_y = scene.truck_at(0.0).box.center.y + config.truck.length_m / 2.0;
  l.side_road_length_m = std::max(truck_rear_y - l.side_road_start_y_m, 0.0) + kSideRoadMargin_m;
  return l;
}

double ego_reference_offset_m(const sim::VehicleParams& ego) noexcept { return ego.cg_to_rear_axle_m; }

double truck_reference_offset_m(const sim::TruckConfig& truck, const ExportOptions& options) noexcept {
  return truck.length_m / 2.0 - options.truck_rear_axle_share * truck.length_m;
}

std::string opendrive_xml(const sim::SceneConfig& config, const sim::CellInput& cell) {
  const JunctionLayout l = junction_layout(config, cell);
  const double w = config.road.lane_width_m;
  XmlWriter x;
  x.open("OpenDRIVE");
  x.leaf("header", {{"revMajor", "1"},
                    {"revMinor", "6"},
                    {"name", config.name},
                    {"version", "1"},
                    {"date", kDate},
                    {"north", num(l.side_road_start_y_m + l.side_road_length_m)},
                    {"south", num(config.road.drivable_min_y_m())},
                    {"east", num(l.main_end_x_m)},
                    {"west", num(l.main_start_x_m)},
                    {"vendor", "emrm"}});
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
  x.open("road", {{"name", "side_road"},
                  {"length", num(l.side_road_length_m)},
                  {"id", "3"},
                  {"junction", "-1"},
                  {"rule", "RHT"}});
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

std::vector<sim::PathPoint> with_final_stop(const std::vector<sim::PathPoint>& path, double dt_s) {
  if (path.size() < 2) return path;
  const sim::PathPoint& from = path[path.size() - 2];
  const sim::PathPoint& rest = path.back();
  const double span_s = rest.t_s - from.t_s;
  const double speed = from.state.speed_mps();
  if (!(rest.state.speed_mps() == 0.0 && speed > 0.0 && span_s > 1.5 * dt_s)) return path;
  std::vector<sim::PathPoint> out(path.begin(), path.end() - 1);
  const double decel = speed / span_s;
  const auto [c, s] = core::cos_sin(from.state.yaw_rad);
  for (double tau = dt_s; tau < span_s - 0.5 * dt_s; tau += dt_s) {
    sim::PathPoint p = from;
    const double travelled = speed * tau - 0.5 * decel * tau * tau;
    p.t_s = from.t_s + tau;
    p.state.x_m += travelled * c;
    p.state.y_m += travelled * s;
    const double k = (speed - decel * tau) / speed;
    p.state.vx_mps *= k;
    p.state.vy_mps *= k;
    p.state.yaw_rate_radps = 0.0;
    out.push_back(p);
  }
  out.push_back(rest);
  return out;
}

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
  if (last.state.speed_mps() < kStoppedSpeed_mps) {
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

std::string openscenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                             const EgoTrajectory* trajectory, const ExportOptions& options,
                             const std::string& road_file) {
  return scenario_xml(config, cell, trajectory, options, road_file, false, "cell", truck_rest_s(config, cell));
}

std::vector<fs::path> export_cell(const fs::path& dir, const sim::SceneConfig& config, const sim::CellInput& cell,
                                  const EgoTrajectory* trajectory, const ExportOptions& options) {
  require_feasible(config, cell);
  const std::vector<core::FileContent> files{
      {dir / kRoadFile, opendrive_xml(config, cell)},
      {dir / kScenarioFile, openscenario_xml(config, cell, trajectory, options, kRoadFile)}};
  core::write_files(files);
  return {files[0].path, files[1].path};
}

std::vector<std::string> plan_parameter_names() {
  return {"speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph", "road_network", "scenario_id"};
}

PlanExport export_plan(const fs::path& dir, const sim::SceneConfig& config, const scenario::ScenarioFile& scenarios,
                       const ExportOptions& options) {
  if (scenarios.rows.empty())
    throw InputError({scenarios.file, 1, 1}, "expected at least one scenario in the plan");
  struct Concrete {
    std::string id;
    sim::CellInput cell;
    std::string road_file;
  };
  std::vector<Concrete> concrete;
  std::map<std::string, sim::CellInput> roads;  // file -> the cell whose road network it is
  for (const auto& row : scenarios.rows) {
    sim::CellInput cell;
    cell.truck_speed_kph = config.truck.speed_kph;
    for (std::size_t i = 0; i < scenarios.factors.size(); ++i)
      (void)campaign::set_cell_factor(cell, scenarios.factors[i], row.values[i]);
    try {
      require_feasible(config, cell);
    } catch (const UsageError& e) {
      throw InputError(row.where, fmt::format("scenario {}: {}", row.id, e.what()));
    }
    const JunctionLayout layout = junction_layout(config, cell);
    const std::string road = road_file_of(layout);
    // Scenarios sharing a junction share its road network: the one whose side road reaches furthest
    // (its truck starts highest), so that every truck of the group starts on it.
    const auto [it, added] = roads.emplace(road, cell);
    if (!added && junction_layout(config, it->second).side_road_length_m < layout.side_road_length_m) it->second = cell;
    concrete.push_back({row.id, cell, road});
  }

  std::vector<core::FileContent> files;
  double rest_s = 0.0;
  for (const auto& c : concrete) rest_s = std::max(rest_s, truck_rest_s(config, c.cell));
  files.push_back({dir / kScenarioFile, scenario_xml(config, concrete.front().cell, nullptr, options,
                                                     concrete.front().road_file, true, concrete.front().id, rest_s)});
  XmlWriter x;
  x.open("OpenSCENARIO");
  file_header(x, fmt::format("{}: the {} concrete scenarios of an emrm plan ({})", config.name, concrete.size(),
                             fs::path(scenarios.file).filename().string()));
  x.open("ParameterValueDistribution");
  x.leaf("ScenarioFile", {{"filepath", kScenarioFile}});
  x.open("Deterministic");
  x.open("DeterministicMultiParameterDistribution");
  x.open("ValueSetDistribution");
  for (const auto& c : concrete) {
    x.open("ParameterValueSet");
    const std::vector<std::string> values{num(c.cell.speed_kph), num(c.cell.ttc_s),  num(c.cell.mu),
                                          num(c.cell.passage_m), num(c.cell.truck_speed_kph), c.road_file, c.id};
    const auto names = plan_parameter_names();
    for (std::size_t i = 0; i < names.size(); ++i)
      x.leaf("ParameterAssignment", {{"parameterRef", names[i]}, {"value", values[i]}});
    x.close();
  }
  x.close();
  x.close();
  x.close();
  x.close();
  x.close();
  files.push_back({dir / kDistributionFile, std::move(x).str()});
  for (const auto& [file, cell] : roads) files.push_back({dir / file, opendrive_xml(config, cell)});
  core::write_files(files);

  PlanExport out;
  out.scenarios = concrete.size();
  out.road_networks = roads.size();
  for (const auto& f : files) out.files.push_back(f.path);
  return out;
}

}  // namespace emrm::exchange
