#include "emrm/sim/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string_view>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"

namespace emrm::sim {
namespace {

// Where to point an error about a field: the field's own node if the file has it, otherwise the
// nearest enclosing mapping that it has (a default that became invalid through another field).
core::YamlNode node_at(const core::YamlNode& root, std::string_view section, std::string_view field) {
  core::YamlNode node = root;
  for (const std::string_view key : {section, field}) {
    if (key.empty() || !node.is_map()) continue;
    const auto child = node.find(key);
    if (!child || child->is_null()) break;
    node = *child;
  }
  return node;
}

// Range checks of one scene file, each failing at the offending node.
class SceneChecker {
 public:
  explicit SceneChecker(const core::YamlNode& root) : root_(root) {}

  [[noreturn]] void fail(std::string_view section, std::string_view field, const std::string& message) const {
    const std::string name = section.empty() ? std::string(field) : fmt::format("{}.{}", section, field);
    node_at(root_, section, field).fail(fmt::format("{}: {}", name, message));
  }

  void positive(std::string_view section, std::string_view field, double value) const {
    if (!(value > 0.0)) fail(section, field, fmt::format("expected a value > 0, got {}", value));
  }
  void non_negative(std::string_view section, std::string_view field, double value) const {
    if (!(value >= 0.0)) fail(section, field, fmt::format("expected a value >= 0, got {}", value));
  }
  void within(std::string_view section, std::string_view field, double value, double low, double high) const {
    if (!(value >= low && value <= high))
      fail(section, field, fmt::format("expected a value in [{}, {}], got {}", low, high, value));
  }

 private:
  const core::YamlNode& root_;
};

void validate(const SceneConfig& c, const core::YamlNode& root) {
  const SceneChecker check(root);

  const RoadConfig& road = c.road;
  check.positive("road", "lane_width_m", road.lane_width_m);
  if (road.lanes < 1)
    check.fail("road", "lanes", fmt::format("expected at least 1 lane, got {}", road.lanes));
  check.non_negative("road", "shoulder_m", road.shoulder_m);

  const TruckConfig& truck = c.truck;
  check.positive("truck", "length_m", truck.length_m);
  check.positive("truck", "width_m", truck.width_m);
  check.positive("truck", "mass_kg", truck.mass_kg);
  check.positive("truck", "yaw_inertia_kgm2", truck.yaw_inertia_kgm2);
  check.non_negative("truck", "speed_kph", truck.speed_kph);
  check.non_negative("truck", "decel_mps2", truck.decel_mps2);

  const VehicleParams& ego = c.ego;
  check.positive("ego", "length_m", ego.length_m);
  check.positive("ego", "width_m", ego.width_m);
  check.positive("ego", "mass_kg", ego.mass_kg);
  check.positive("ego", "yaw_inertia_kgm2", ego.yaw_inertia_kgm2);
  check.positive("ego", "cg_to_front_axle_m", ego.cg_to_front_axle_m);
  check.positive("ego", "cg_to_rear_axle_m", ego.cg_to_rear_axle_m);
  check.positive("ego", "cg_height_m", ego.cg_height_m);
  if (!(ego.max_steer_rad > 0.0 && ego.max_steer_rad < std::numbers::pi / 2))
    check.fail("ego", "max_steer_rad",
               fmt::format("expected a value in (0, pi/2), got {}", ego.max_steer_rad));
  check.positive("ego", "max_steer_rate_radps", ego.max_steer_rate_radps);
  check.positive("ego", "front_cornering_stiffness_n_per_rad", ego.front_cornering_stiffness_n_per_rad);
  check.positive("ego", "rear_cornering_stiffness_n_per_rad", ego.rear_cornering_stiffness_n_per_rad);
  check.non_negative("ego", "kinematic_blend_speed_mps", ego.kinematic_blend_speed_mps);
  // Overhangs are (length − wheelbase)/2 each; a negative one would put the bumper behind the axle.
  if (ego.wheelbase_m() > ego.length_m)
    check.fail("ego", "length_m",
               fmt::format("expected the car to be at least as long as its wheelbase ({} m), got {} m",
                           ego.wheelbase_m(), ego.length_m));

  const SimulationConfig& sim = c.simulation;
  const auto models = vehicle_model_names();
  if (std::find(models.begin(), models.end(), sim.vehicle_model) == models.end())
    check.fail("simulation", "vehicle_model",
               fmt::format("unknown vehicle model '{}'; expected one of: {}", sim.vehicle_model,
                           core::join(models, ", ")));
  check.positive("simulation", "dt_s", sim.dt_s);
  check.positive("simulation", "horizon_s", sim.horizon_s);
  check.non_negative("simulation", "latency_s", sim.latency_s);
  if (sim.dt_s > sim.horizon_s)
    check.fail("simulation", "dt_s",
               fmt::format("expected a time step no longer than the horizon ({} s), got {} s", sim.horizon_s,
                           sim.dt_s));

  const SeverityConfig& sev = c.severity;
  check.within("severity", "restitution", sev.restitution, 0.0, 1.0);
  check.non_negative("severity", "contact_friction", sev.contact_friction);
  check.positive("severity", "mais3_slope_per_mps", sev.mais3_slope_per_mps);
  check.positive("severity", "fatal_reference_mps", sev.fatal_reference_mps);
  check.positive("severity", "fatal_exponent", sev.fatal_exponent);
  if (!(sev.l6_p_mais3 > 0.0 && sev.l6_p_mais3 <= 1.0))
    check.fail("severity", "l6_p_mais3",
               fmt::format("expected a probability in (0, 1], got {}", sev.l6_p_mais3));
  if (!(sev.l7_p_fatal > 0.0 && sev.l7_p_fatal <= 1.0))
    check.fail("severity", "l7_p_fatal",
               fmt::format("expected a probability in (0, 1], got {}", sev.l7_p_fatal));

  const PlannerConfig& planner = c.planner;
  if (planner.max_nodes < 1)
    check.fail("planner", "max_nodes", fmt::format("expected at least 1 node, got {}", planner.max_nodes));
  check.positive("planner", "max_time_ms", planner.max_time_ms);
  check.positive("planner", "min_duration_s", planner.min_duration_s);
  check.positive("planner", "max_duration_s", planner.max_duration_s);
  if (planner.min_duration_s > planner.max_duration_s)
    check.fail("planner", "min_duration_s",
               fmt::format("expected min_duration_s <= max_duration_s ({} s), got {} s",
                           planner.max_duration_s, planner.min_duration_s));
  check.within("planner", "goal_bias", planner.goal_bias, 0.0, 1.0);

  check.positive("", "max_initial_distance_m", c.max_initial_distance_m);

  // Checked last: it depends on the road and on the ego's width, which must be sane first. The
  // whole car must start on the drivable area, or every run would begin with a road departure.
  const double low = road.drivable_min_y_m();
  const double high = road.drivable_max_y_m();
  const double half_width = ego.width_m / 2.0;
  if (!(road.ego_lane_center_m - half_width >= low && road.ego_lane_center_m + half_width <= high))
    check.fail("road", "ego_lane_center_m",
               fmt::format("the ego ({} m wide) centred at y = {} m does not fit on the drivable area "
                           "y in [{}, {}] m",
                           ego.width_m, road.ego_lane_center_m, low, high));
}

SceneConfig read_scene(const core::YamlNode& root) {
  SceneConfig config;
  core::read_yaml(root, config);
  validate(config, root);
  return config;
}

}  // namespace

SceneConfig load_scene_config(const std::filesystem::path& path) {
  return read_scene(core::YamlNode::load_file(path));
}

SceneConfig parse_scene_config(const std::string& text, const std::string& file_name) {
  return read_scene(core::YamlNode::parse(text, file_name));
}

std::string to_yaml(const SceneConfig& config) { return core::to_yaml_text(core::write_yaml(config)); }

void validate_cell(const SceneConfig& config, const CellInput& cell) {
  const auto finite_positive = [](double value, std::string_view factor, std::string_view unit) {
    if (!std::isfinite(value) || !(value > 0.0))
      throw UsageError(fmt::format("{} must be a finite number > 0 {}, got {}", factor, unit, value));
  };
  finite_positive(cell.speed_kph, "speed_kph", "km/h");
  finite_positive(cell.ttc_s, "ttc_s", "s");
  if (!std::isfinite(cell.mu) || !(cell.mu > 0.0 && cell.mu <= 2.0))
    throw UsageError(
        fmt::format("mu must be a finite friction coefficient with 0 < mu <= 2, got {}", cell.mu));
  if (!std::isfinite(cell.truck_speed_kph) || !(cell.truck_speed_kph >= 0.0))
    throw UsageError(
        fmt::format("truck_speed_kph must be a finite number >= 0 km/h, got {}", cell.truck_speed_kph));
  finite_positive(cell.passage_m, "passage_m", "m");
  const double drivable_width_m = config.road.drivable_max_y_m() - config.road.drivable_min_y_m();
  if (cell.passage_m > drivable_width_m)
    throw UsageError(fmt::format(
        "passage_m must be in (0, {}] m (the width of the drivable area), got {} m: a scene whose passage is "
        "wider than the road",
        drivable_width_m, cell.passage_m));
}

Scene::Scene(const SceneConfig& config, const CellInput& cell)
    : config_(&config),
      cell_(cell),
      initial_distance_m_(cell.speed_kph / 3.6 * cell.ttc_s),
      truck_speed_mps_(cell.truck_speed_kph / 3.6) {
  // passage_m is the gap once the truck stands (or, never stopping, at t = TTC): the truck
  // starts that far plus its travel until then above the right edge of the drivable area.
  const double a = config.truck.decel_mps2;
  const double travel_m =
      a > 0.0 ? truck_speed_mps_ * truck_speed_mps_ / (2.0 * a) : truck_speed_mps_ * cell.ttc_s;
  truck_front_y0_m_ = config.road.drivable_min_y_m() + cell.passage_m + travel_m;
}

bool Scene::feasible() const noexcept {
  // The tolerance keeps cells whose v·TTC lands exactly on the limit (up to rounding of the
  // grid's steps) feasible.
  return initial_distance_m_ <= config_->max_initial_distance_m + 1e-9;
}

VehicleState Scene::ego_initial() const noexcept {
  VehicleState s;
  s.x_m = -config_->ego.cg_to_front_m();
  s.y_m = config_->road.ego_lane_center_m;
  s.yaw_rad = 0.0;
  s.vx_mps = initial_speed_mps();
  return s;
}

double Scene::truck_front_y_at(double t_s) const noexcept {
  const double t = std::max(t_s, 0.0);
  const double a = config_->truck.decel_mps2;
  if (a <= 0.0) return truck_front_y0_m_ - truck_speed_mps_ * t;
  const double moving_s = std::min(t, truck_speed_mps_ / a);  // it stops at v/a and stays
  return truck_front_y0_m_ - (truck_speed_mps_ * moving_s - 0.5 * a * moving_s * moving_s);
}

TruckState Scene::truck_at(double t_s) const noexcept {
  const TruckConfig& truck = config_->truck;
  const double t = std::max(t_s, 0.0);
  const double speed =
      truck.decel_mps2 > 0.0 ? std::max(truck_speed_mps_ - truck.decel_mps2 * t, 0.0) : truck_speed_mps_;
  TruckState out;
  out.box.center = {initial_distance_m_ + truck.width_m / 2.0, truck_front_y_at(t) + truck.length_m / 2.0};
  out.box.heading_rad = -std::numbers::pi / 2.0;
  out.box.length_m = truck.length_m;
  out.box.width_m = truck.width_m;
  out.velocity_mps = {0.0, -speed};
  return out;
}

core::OrientedBox Scene::ego_box(const VehicleState& s) const noexcept {
  const VehicleParams& ego = config_->ego;
  const core::Vec2 heading = core::Vec2::unit(s.yaw_rad);
  // The CG is not at the middle of the car: shift by half the difference of its two ends.
  const double offset_m = (ego.cg_to_front_m() - ego.cg_to_rear_m()) / 2.0;
  return {core::Vec2{s.x_m, s.y_m} + heading * offset_m, s.yaw_rad, ego.length_m, ego.width_m};
}

bool Scene::on_drivable_area(const core::OrientedBox& ego) const noexcept {
  // The lowest and highest corner: the box's half-extent across the road.
  const double c = std::abs(std::cos(ego.heading_rad));
  const double s = std::abs(std::sin(ego.heading_rad));
  const double half_extent_y = 0.5 * (ego.length_m * s + ego.width_m * c);
  return ego.center.y - half_extent_y >= config_->road.drivable_min_y_m() &&
         ego.center.y + half_extent_y <= config_->road.drivable_max_y_m();
}

double Scene::truck_far_x_m() const noexcept { return initial_distance_m_ + config_->truck.width_m; }

}  // namespace emrm::sim
