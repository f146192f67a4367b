// One cell of a family other than the T-junction as an OpenSCENARIO document (openscenario.hpp,
// docs/openscenario.md, "Other families"): the ego and every actor of the cell — a vehicle, a
// pedestrian, an animal or an object by its kind, with its box and mass — each actor's open-loop
// motion as a timed trajectory of the cell's own, the road's friction and the ego's executed
// trajectory, beside the family's straight road (opendrive.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "emrm/exchange/openscenario.hpp"
#include "emrm/version.hpp"
#include "export_support.hpp"
#include "xml_writer.hpp"
#include "xosc_parts.hpp"

namespace emrm::exchange {
namespace {

using detail::axles;
using detail::bounding_box;
using detail::follow_trajectory;
using detail::maneuver_group;
using detail::maneuver_group_end;
using detail::num;
using detail::pline_interpolation;
using detail::world_position;

// How tall each kind of actor is drawn (the scene models bodies on the road plane): a car and a
// truck as the export's options say, an adult pedestrian, a deer at the shoulder, a cyclist on a
// bicycle, a low obstacle.
double height_of(sim::ActorKind kind, const ExportOptions& options) {
  switch (kind) {
    case sim::ActorKind::kCar:
      return options.ego_height_m;
    case sim::ActorKind::kTruck:
      return options.truck_height_m;
    case sim::ActorKind::kPedestrian:
      return 1.75;
    case sim::ActorKind::kCyclist:
      return 1.8;
    case sim::ActorKind::kAnimal:
      return 1.2;
    case sim::ActorKind::kStaticObject:
      return 1.0;
  }
  return 1.0;
}

// An actor's entity name: its name in the scene in CamelCase ("cutting car": "CuttingCar"),
// numbered from the second when two share it; never the ego's.
std::vector<std::string> entity_names(const sim::Scene& scene) {
  std::vector<std::string> out;
  std::map<std::string, int> seen{{kEgoEntity, 1}};
  for (const sim::Actor& actor : scene.actors()) {
    std::string name;
    bool upper = true;
    for (const char c : actor.body().name) {
      if (std::isalnum(static_cast<unsigned char>(c)) == 0) {
        upper = true;
        continue;
      }
      name += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
      upper = false;
    }
    if (name.empty()) name = "Actor";
    const int n = ++seen[name];
    out.push_back(n == 1 ? name : fmt::format("{}{}", name, n));
  }
  return out;
}

// An actor's speed at t = 0 (along its heading).
double start_speed_mps(const sim::ActorMotion& m) { return m.track ? m.track->samples.front().speed_mps : m.speed_mps; }

// The actor's ScenarioObject about its box's centre (its reference point): a Vehicle (a car, a truck,
// a bicycle), a Pedestrian (a person or an animal) or a MiscObject.
void actor_entity(XmlWriter& x, const std::string& entity, const sim::Actor& actor, const ExportOptions& options) {
  const sim::ActorBody& b = actor.body();
  const double height = height_of(b.kind, options);
  const std::string model = "emrm_" + entity;
  x.open("ScenarioObject", {{"name", entity}});
  switch (b.kind) {
    case sim::ActorKind::kPedestrian:
    case sim::ActorKind::kAnimal:
      x.open("Pedestrian", {{"name", model},
                            {"mass", num(b.mass_kg)},
                            {"pedestrianCategory", b.kind == sim::ActorKind::kAnimal ? "animal" : "pedestrian"}});
      bounding_box(x, 0.0, height, b.length_m, b.width_m);
      break;
    case sim::ActorKind::kStaticObject:
      x.open("MiscObject", {{"name", model}, {"mass", num(b.mass_kg)}, {"miscObjectCategory", "obstacle"}});
      bounding_box(x, 0.0, height, b.length_m, b.width_m);
      break;
    case sim::ActorKind::kCar:
    case sim::ActorKind::kTruck:
    case sim::ActorKind::kCyclist: {
      const bool truck = b.kind == sim::ActorKind::kTruck;
      const char* category = truck ? "truck" : b.kind == sim::ActorKind::kCyclist ? "bicycle" : "car";
      x.open("Vehicle", {{"name", model}, {"vehicleCategory", category}, {"mass", num(b.mass_kg)}});
      bounding_box(x, 0.0, height, b.length_m, b.width_m);
      const double top_speed =
          std::max(start_speed_mps(actor.motion()), truck ? options.truck_max_speed_mps : options.ego_max_speed_mps);
      x.leaf("Performance",
             {{"maxSpeed", num(top_speed)},
              {"maxAcceleration", num(truck ? options.truck_max_acceleration_mps2 : options.ego_max_acceleration_mps2)},
              {"maxDeceleration", num(std::max(actor.motion().decel_mps2, 1.0))}});
      axles(x, 0.6 * b.length_m, 0.5, std::max(b.width_m - 0.2, 0.1),
            truck ? options.truck_wheel_diameter_m : options.ego_wheel_diameter_m);
      break;
    }
  }
  x.open("Properties");
  x.leaf("Property", {{"name", "yaw_inertia_kgm2"}, {"value", num(b.yaw_inertia_kgm2)}});
  pline_interpolation(x);
  x.close();
  x.close();
  x.close();
}

// The times of an actor's polyline up to `end_s`: its start and end, the moments its motion changes
// (the end of its drift, the start of its braking, its rest), and every frame while it brakes; in
// between it moves on a straight line at one speed, which the ends of each stretch give exactly.
std::vector<double> vertex_times(const sim::ActorMotion& m, double dt_s, double end_s) {
  std::vector<double> times{0.0, end_s};
  if (m.track) {  // samples: every one of them
    for (std::size_t k = 1; static_cast<double>(k) * m.track->dt_s < end_s - 1e-9 && k < m.track->samples.size(); ++k)
      times.push_back(static_cast<double>(k) * m.track->dt_s);
    std::sort(times.begin(), times.end());
    return times;
  }
  const double rest_s = m.rest_time_s();
  for (const double change : {m.lateral_mps != 0.0 ? m.lateral_for_s : 0.0, m.brake_from_s, rest_s})
    if (change > 0.0 && change < end_s) times.push_back(change);
  if (m.decel_mps2 > 0.0 && m.speed_mps > 0.0) {
    const double from = std::max(m.brake_from_s, 0.0);
    const double to = std::min(rest_s, end_s);
    for (int k = 1; from + k * dt_s < to - 1e-9; ++k) times.push_back(from + k * dt_s);
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end(), [](double a, double b) { return b - a < 1e-9; }), times.end());
  return times;
}

// An actor that moves follows its motion in the cell as a timed trajectory of its box's centre; one
// that stands stays where Init put it, except the hazard, whose maneuver the Act always has.
void actor_maneuver(XmlWriter& x, const std::string& entity, const sim::Actor& actor, bool hazard, double dt_s,
                    double end_s) {
  const sim::ActorMotion& m = actor.motion();
  const bool stands = m.track ? m.rest_time_s() == 0.0 : !(m.speed_mps > 0.0) && m.lateral_mps == 0.0;
  if (!hazard && stands) return;
  maneuver_group(x, entity + "ManeuverGroup", entity);
  x.open("Maneuver", {{"name", entity + "Motion"}});
  x.open("Event", {{"name", entity + "Moves"}, {"priority", "override"}, {"maximumExecutionCount", "1"}});
  x.open("Action", {{"name", entity + "FollowsItsMotion"}});
  const std::vector<double> times = vertex_times(m, dt_s, end_s);
  follow_trajectory(x, "emrm_" + entity, times, [&](std::size_t k) {
    const sim::ActorState at = actor.at(times[k]);
    world_position(x, num(at.box.center.x), num(at.box.center.y), num(at.box.heading_rad));
  });
  x.close();
  maneuver_group_end(x, entity + "StartsAtHazard");
}

}  // namespace

namespace detail {

std::string family_scenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                                const EgoTrajectory* trajectory, const ExportOptions& options,
                                const std::string& road_file, const std::string& scenario_id) {
  const sim::Scene scene(config, cell);
  const sim::FactorTable factors = sim::scenario_factors(config);
  const std::vector<std::string> names = entity_names(scene);
  std::vector<sim::PathPoint> vertices;
  if (trajectory != nullptr) vertices = ego_vertices(config, *trajectory, options);
  const double end_s = storyboard_end_s(config, vertices);
  XmlWriter x;
  x.open("OpenSCENARIO");
  cell_header(x,
              fmt::format("{}: {}{}", config.name, cell_text(factors, cell),
                          trajectory != nullptr ? ", strategy " + trajectory->strategy : ""),
              factors, cell, road_file, scenario_id);
  x.leaf("CatalogLocations");
  x.open("RoadNetwork");
  x.leaf("LogicFile", {{"filepath", road_file}});
  x.close();
  x.open("Entities");
  ego_entity(x, config, options);
  for (std::size_t a = 0; a < names.size(); ++a) actor_entity(x, names[a], scene.actors()[a], options);
  x.close();
  x.open("Storyboard");
  x.open("Init");
  x.open("Actions");
  road_friction(x, num(cell.friction()));
  const sim::VehicleState ego = scene.ego_initial();
  start_state(x, kEgoEntity, num(ego.x_m - ego_reference_offset_m(config.ego)), num(ego.y_m), "0", num(ego.vx_mps));
  for (std::size_t a = 0; a < names.size(); ++a) {
    const sim::Actor& actor = scene.actors()[a];
    const sim::ActorState at = actor.at(0.0);
    start_state(x, names[a], num(at.box.center.x), num(at.box.center.y), num(at.box.heading_rad),
                num(start_speed_mps(actor.motion())));
  }
  x.close();
  x.close();
  x.open("Story", {{"name", "EmrmStory"}});
  x.open("Act", {{"name", "EmrmAct"}});
  for (std::size_t a = 0; a < names.size(); ++a)
    actor_maneuver(x, names[a], scene.actors()[a], a == 0, config.simulation.dt_s, end_s);
  act_end(x, config, trajectory, vertices, end_s);
  return std::move(x).str();
}

}  // namespace detail

}  // namespace emrm::exchange
