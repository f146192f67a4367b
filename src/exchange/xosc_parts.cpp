// The parts of an OpenSCENARIO document every cell export writes (xosc_parts.hpp).

#include "xosc_parts.hpp"

#include <algorithm>
#include <cmath>

#include "emrm/sim/termination.hpp"

namespace emrm::exchange::detail {

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

void pline_interpolation(XmlWriter& x) { x.leaf("Property", {{"name", "plineInterpolation"}, {"value", "segment"}}); }

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

void maneuver_group(XmlWriter& x, const std::string& name, const std::string& entity) {
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
    world_position(x, num(s.x_m - back * std::cos(s.yaw_rad)), num(s.y_m - back * std::sin(s.yaw_rad)), num(s.yaw_rad));
  });
  x.close();
  maneuver_group_end(x, "EgoStartsAtHazard");
}

void ego_entity(XmlWriter& x, const sim::SceneConfig& config, const ExportOptions& options) {
  const sim::VehicleParams& ego = config.ego;
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
}

void road_friction(XmlWriter& x, const std::string& friction) {
  x.open("GlobalAction");
  x.open("EnvironmentAction");
  x.open("Environment", {{"name", "emrm_road"}});
  x.leaf("RoadCondition", {{"frictionScaleFactor", friction}});
  x.close();
  x.close();
  x.close();
}

void start_state(XmlWriter& x, const std::string& entity, const std::string& px, const std::string& py,
                 const std::string& heading, const std::string& speed) {
  x.open("Private", {{"entityRef", entity}});
  x.open("PrivateAction");
  x.open("TeleportAction");
  world_position(x, px, py, heading);
  x.close();
  x.close();
  x.open("PrivateAction");
  speed_action(x, "step", "time", "0", speed);
  x.close();
  x.close();
}

std::vector<ScenarioField> scenario_fields(const sim::FactorTable& factors, const sim::CellInput& cell,
                                           const std::string& road_file, const std::string& scenario_id) {
  std::vector<ScenarioField> out;
  for (std::size_t f = 0; f < factors.size(); ++f) out.push_back({factors[f].key, "double", num(cell[f])});
  out.push_back({"road_network", "string", road_file});
  out.push_back({"scenario_id", "string", scenario_id});
  return out;
}

void parameter_declarations(XmlWriter& x, const std::vector<ScenarioField>& fields) {
  x.open("ParameterDeclarations");
  for (const auto& f : fields)
    x.leaf("ParameterDeclaration", {{"name", f.name}, {"parameterType", f.type}, {"value", f.value}});
  x.close();
}

double storyboard_end_s(const sim::SceneConfig& config, const std::vector<sim::PathPoint>& vertices) {
  return !vertices.empty() ? vertices.back().t_s : config.simulation.horizon_s + config.safe_state.horizon_s;
}

void act_end(XmlWriter& x, const sim::SceneConfig& config, const EgoTrajectory* trajectory,
             const std::vector<sim::PathPoint>& vertices, double end_s) {
  if (trajectory != nullptr && !vertices.empty()) ego_maneuver(x, config, *trajectory, vertices);
  start_at_zero(x, "ActStartsAtHazard");
  x.close();
  x.close();
  x.open("StopTrigger");
  time_condition(x, "EndOfRun", "greaterOrEqual", end_s);
  x.close();
  x.close();
  x.close();
}

}  // namespace emrm::exchange::detail
