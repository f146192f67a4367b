#pragma once

// The parts of an OpenSCENARIO document every cell export writes (openscenario.cpp for the
// T-junction and its logical scenario, family_scenario.cpp for every other family): conditions,
// boxes, positions, speed actions, maneuver groups, timed trajectories, and the ego's entity, start
// and executed trajectory. Internal to src/exchange.

#include <string>
#include <vector>

#include "emrm/exchange/openscenario.hpp"
#include "emrm/sim/scene.hpp"
#include "export_support.hpp"
#include "xml_writer.hpp"

namespace emrm::exchange::detail {

void time_condition(XmlWriter& x, const std::string& name, const char* rule, double t_s);
void start_at_zero(XmlWriter& x, const std::string& name);
void bounding_box(XmlWriter& x, double center_x, double height, double length, double width);
void axles(XmlWriter& x, double wheelbase, double max_steer, double track, double wheel_diameter);
// esmini's own switch (an entity property, which other engines ignore): the heading interpolated
// linearly over each segment of a trajectory, so that it is the vertices' at their times. Without
// it, followingMode "position" makes esmini blend the headings of neighbouring vertices, half a
// step late, and snap to the last one at the end (docs/openscenario.md, "esmini").
void pline_interpolation(XmlWriter& x);
void world_position(XmlWriter& x, const std::string& px, const std::string& py, const std::string& heading);
void speed_action(XmlWriter& x, const char* shape, const char* dimension, const std::string& value,
                  const std::string& target);
void maneuver_group(XmlWriter& x, const std::string& name, const std::string& entity);
void maneuver_group_end(XmlWriter& x, const std::string& trigger);

// What a scenario is of: each factor at the cell's value, the road network's file and the id. A
// logical scenario declares them as parameters, which its expressions read; a concrete scenario,
// whose positions are numbers, names them as its FileHeader's properties instead, so that it
// declares no parameter that changing would not act on.
struct ScenarioField {
  std::string name, type, value;  // type: an OpenSCENARIO parameterType
};
[[nodiscard]] std::vector<ScenarioField> scenario_fields(const sim::FactorTable& factors, const sim::CellInput& cell,
                                                         const std::string& road_file, const std::string& scenario_id);
void parameter_declarations(XmlWriter& x, const std::vector<ScenarioField>& fields);
// The ego's ScenarioObject: its box about the rear axle, performance, axles and properties.
void ego_entity(XmlWriter& x, const sim::SceneConfig& config, const ExportOptions& options);
// The road's friction as the Init's global EnvironmentAction.
void road_friction(XmlWriter& x, const std::string& friction);
// An entity's Init: teleported to a world position, at a speed from the start.
void start_state(XmlWriter& x, const std::string& entity, const std::string& px, const std::string& py,
                 const std::string& heading, const std::string& speed);
// When a cell's storyboard stops: at the ego's last vertex when it follows a trajectory, else after
// the longest run the simulator would make (the horizon, then the recovery after the hazard).
[[nodiscard]] double storyboard_end_s(const sim::SceneConfig& config, const std::vector<sim::PathPoint>& vertices);
// The end of a cell's document: the ego's maneuver (with `vertices`), the Act's start, the stop at
// `end_s`, and the closing of the Act, the Story, the Storyboard and the document.
void act_end(XmlWriter& x, const sim::SceneConfig& config, const EgoTrajectory* trajectory,
             const std::vector<sim::PathPoint>& vertices, double end_s);
// The ego follows its executed trajectory, reference point (rear axle) at each vertex's time.
void ego_maneuver(XmlWriter& x, const sim::SceneConfig& config, const EgoTrajectory& trajectory,
                  const std::vector<sim::PathPoint>& vertices);

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

}  // namespace emrm::exchange::detail
