// One cell as an OpenSCENARIO document (openscenario.hpp): the vehicles, the initial state, the
// truck's motion and the ego's trajectory as timed polylines, and the storyboard's end.

#include "emrm/exchange/openscenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/termination.hpp"
#include "emrm/version.hpp"
#include "export_support.hpp"
#include "xml_writer.hpp"
#include "xosc_parts.hpp"

namespace emrm::exchange {
namespace {

namespace fs = std::filesystem;
using detail::num;
using detail::require_feasible;
using detail::scenario_xml;
using detail::truck_rest_s;
// The parts of a scenario document (xosc_parts.hpp).
using detail::axles;
using detail::bounding_box;
using detail::ego_entity;
using detail::follow_trajectory;
using detail::maneuver_group;
using detail::maneuver_group_end;
using detail::pline_interpolation;
using detail::road_friction;
using detail::start_state;
using detail::world_position;

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

// "$KEY": the logical scenario's parameter of each T-junction factor (its key in the factor table).
struct Parameters {
  std::string speed, ttc, mu, passage, truck_speed;
  Parameters() = default;
  explicit Parameters(const sim::SceneConfig& config) {
    const sim::FactorTable factors = sim::scenario_factors(config);
    const auto ref = [&](sim::tjunction::Position i) { return "$" + factors[i].key; };
    speed = ref(sim::tjunction::kSpeed);
    ttc = ref(sim::tjunction::kTtc);
    mu = ref(sim::tjunction::kMu);
    passage = ref(sim::tjunction::kPassage);
    truck_speed = ref(sim::tjunction::kTruckSpeed);
  }
};

struct Initial {
  Quantity ego_x, ego_y, ego_speed, truck_x, truck_y, truck_speed, mu;
  Parameters parameters;
};

Initial initial_of(const sim::SceneConfig& config, const sim::CellInput& cell, const ExportOptions& options) {
  const sim::Scene scene(config, cell);
  const sim::VehicleState ego = scene.ego_initial();
  const sim::ActorState truck = scene.hazard_at(0.0);
  const double ego_back = ego_reference_offset_m(config.ego);
  const double truck_back = truck_reference_offset_m(config.truck, options);
  Initial i;
  i.parameters = Parameters(config);
  i.ego_x = {ego.x_m - ego_back, ""};
  i.ego_y = {ego.y_m, ""};
  const Parameters& p = i.parameters;
  i.ego_speed = {ego.vx_mps, "${" + p.speed + " / 3.6}"};
  // The truck heads -y: its rear axle is above its centre.
  i.truck_x = {truck.box.center.x, "${" + p.speed + " / 3.6 * " + p.ttc + plus(config.truck.width_m / 2.0) + "}"};
  const double y_constant = config.road.drivable_min_y_m() + config.truck.length_m / 2.0 + truck_back;
  const std::string travel = config.truck.decel_mps2 > 0.0 ? p.truck_speed + " / 3.6 * " + p.truck_speed + " / 3.6 / " +
                                                                 num(2.0 * config.truck.decel_mps2)
                                                           : p.truck_speed + " / 3.6 * " + p.ttc;
  i.truck_y = {truck.box.center.y + truck_back, "${" + p.passage + " + " + travel + plus(y_constant) + "}"};
  i.truck_speed = {scene.hazard_speed_mps(), "${" + p.truck_speed + " / 3.6}"};
  i.mu = {cell.friction(), p.mu};
  return i;
}
void entities(XmlWriter& x, const sim::SceneConfig& config, const ExportOptions& options) {
  const sim::TruckConfig& truck = config.truck;
  x.open("Entities");
  ego_entity(x, config, options);

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

void init(XmlWriter& x, const Initial& i, bool parametric) {
  x.open("Init");
  x.open("Actions");
  road_friction(x, i.mu.text(parametric));
  start_state(x, kEgoEntity, i.ego_x.text(parametric), i.ego_y.text(parametric), "0", i.ego_speed.text(parametric));
  start_state(x, kTruckEntity, i.truck_x.text(parametric), i.truck_y.text(parametric), num(-std::numbers::pi / 2.0),
              i.truck_speed.text(parametric));
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

// The y of the truck's rear axle at time t: where the scene's truck is (Scene::hazard_at), or for
// the logical scenario the expression of the parameters that gives it: the passage plus the travel
// still ahead of the truck, max(v − a·t, 0)² / 2a, its max written with the standard's operators as
// (w + sqrt(w·w)) / 2.
std::string truck_y_at(const sim::Scene& scene, const Parameters& p, const ExportOptions& options, double t_s,
                       bool parametric) {
  const sim::SceneConfig& config = scene.config();
  const double back = truck_reference_offset_m(config.truck, options);
  if (!parametric) return num(scene.hazard_at(t_s).box.center.y + back);
  const double y_constant = config.road.drivable_min_y_m() + config.truck.length_m / 2.0 + back;
  const double a = config.truck.decel_mps2;
  std::string ahead;
  if (a > 0.0) {
    const std::string w = "(" + p.truck_speed + " / 3.6" + plus(-a * t_s) + ")";
    const std::string moving = "((" + w + " + sqrt(" + w + " * " + w + ")) / 2)";
    ahead = moving + " * " + moving + " / " + num(2.0 * a);
  } else {
    ahead = p.truck_speed + " / 3.6 * (" + p.ttc + plus(-t_s) + ")";
  }
  return "${" + p.passage + " + " + ahead + plus(y_constant) + "}";
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
    world_position(x, truck_x, truck_y_at(scene, i.parameters, options, times[k], parametric), heading);
  });
  x.close();
  maneuver_group_end(x, "TruckBrakesAtHazard");
}

}  // namespace

namespace detail {

void file_header(XmlWriter& x, const std::string& description,
                 const std::vector<std::pair<std::string, std::string>>& properties) {
  const XmlWriter::Attributes attributes{{"revMajor", "1"},
                                         {"revMinor", "2"},
                                         {"date", kDate},
                                         {"description", description},
                                         {"author", fmt::format("emrm {}", kVersion)}};
  if (properties.empty()) {
    x.leaf("FileHeader", attributes);
    return;
  }
  x.open("FileHeader", attributes);
  x.open("Properties");
  for (const auto& [name, value] : properties) x.leaf("Property", {{"name", name}, {"value", value}});
  x.close();
  x.close();
}

void cell_header(XmlWriter& x, const std::string& description, const sim::FactorTable& factors,
                 const sim::CellInput& cell, const std::string& road_file, const std::string& scenario_id) {
  std::vector<std::pair<std::string, std::string>> properties;
  for (auto& f : scenario_fields(factors, cell, road_file, scenario_id))
    properties.emplace_back(std::move(f.name), std::move(f.value));
  file_header(x, description, properties);
}

// `truck_rest_s`: when the truck comes to rest (the latest over the scenarios a logical scenario
// stands for), infinite when it does not brake.
std::string scenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell, const EgoTrajectory* trajectory,
                         const ExportOptions& options, const std::string& road_file, bool parametric,
                         const std::string& scenario_id, double truck_rest_s) {
  const Initial i = initial_of(config, cell, options);
  const sim::FactorTable factors = sim::scenario_factors(config);
  std::vector<sim::PathPoint> vertices;
  if (trajectory != nullptr) vertices = ego_vertices(config, *trajectory, options);
  const double end_s = storyboard_end_s(config, vertices);
  XmlWriter x;
  x.open("OpenSCENARIO");
  if (parametric) {
    file_header(x, fmt::format("{}: logical scenario of an emrm plan", config.name));
    parameter_declarations(x, scenario_fields(factors, cell, road_file, scenario_id));
  } else {
    cell_header(x,
                fmt::format("{}: {}{}", config.name, cell_text(factors, cell),
                            trajectory != nullptr ? ", strategy " + trajectory->strategy : ""),
                factors, cell, road_file, scenario_id);
  }
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
  act_end(x, config, trajectory, vertices, end_s);
  return std::move(x).str();
}

// When the cell's truck comes to rest (infinite when it does not brake).
double truck_rest_s(const sim::SceneConfig& config, const sim::CellInput& cell) {
  return config.truck.decel_mps2 > 0.0 ? sim::Scene(config, cell).hazard_speed_mps() / config.truck.decel_mps2
                                       : std::numeric_limits<double>::infinity();
}

void require_feasible(const sim::SceneConfig& config, const sim::CellInput& cell) {
  sim::validate_cell(config, cell);
  if (const sim::Scene scene(config, cell); !scene.feasible())
    throw UsageError("the cell is infeasible: " + scene.infeasible_reason());
}

}  // namespace detail

double ego_reference_offset_m(const sim::VehicleParams& ego) noexcept { return ego.cg_to_rear_axle_m; }

std::vector<sim::PathPoint> ego_vertices(const sim::SceneConfig& config, const EgoTrajectory& trajectory,
                                         const ExportOptions& options) {
  return ended_on_frame_grid(
      thin_path(sim::with_closed_form_stop(trajectory.path, config.simulation.dt_s), options.tolerance_m),
      config.simulation.dt_s);
}

double truck_reference_offset_m(const sim::TruckConfig& truck, const ExportOptions& options) noexcept {
  return truck.length_m / 2.0 - options.truck_rear_axle_share * truck.length_m;
}

// The T-junction's geometry has its own road and scenario (sim::has_tjunction_analytics); every other
// family exports its straight road and its actors.
std::string openscenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                             const EgoTrajectory* trajectory, const ExportOptions& options,
                             const std::string& road_file) {
  if (!sim::has_tjunction_analytics(config))
    return detail::family_scenario_xml(config, cell, trajectory, options, road_file, "cell");
  return scenario_xml(config, cell, trajectory, options, road_file, false, "cell", truck_rest_s(config, cell));
}

std::string road_file_of(const sim::SceneConfig& config) {
  return sim::has_tjunction_analytics(config) ? kRoadFile : config.family + ".xodr";
}

std::string scenario_file_of(const sim::SceneConfig& config) {
  return sim::has_tjunction_analytics(config) ? kScenarioFile : config.family + ".xosc";
}

std::vector<fs::path> export_cell(const fs::path& dir, const sim::SceneConfig& config, const sim::CellInput& cell,
                                  const EgoTrajectory* trajectory, const ExportOptions& options) {
  require_feasible(config, cell);
  const bool tjunction = sim::has_tjunction_analytics(config);
  const std::string road = road_file_of(config);
  const std::vector<core::FileContent> files{
      {dir / road, tjunction ? opendrive_xml(config, cell) : straight_road_xml(config, cell)},
      {dir / scenario_file_of(config), openscenario_xml(config, cell, trajectory, options, road)}};
  core::write_files(files);
  return {files[0].path, files[1].path};
}

}  // namespace emrm::exchange
