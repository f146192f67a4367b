#include "emrm/sim/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

#include "emrm/core/error.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/core/yaml.hpp"

namespace emrm::sim {
namespace {

using tjunction::kMu;
using tjunction::kPassage;
using tjunction::kSpeed;
using tjunction::kTruckSpeed;
using tjunction::kTtc;

SceneConfig read_scene(const core::YamlNode& root) {
  SceneConfig config;
  core::read_yaml(root, config);
  try {
    validate(config);
  } catch (const core::ConfigError& e) {
    core::fail_at(root, e, /*with_path=*/true);
  }
  return config;
}

}  // namespace

void validate(const SceneConfig& config) { core::validate_fields("scene", config); }
void validate(const RoadConfig& road) { core::validate_fields("road", road); }
void validate(const TruckConfig& truck) { core::validate_fields("truck", truck); }
void validate(const SimulationConfig& simulation) { core::validate_fields("simulation", simulation); }
void validate(const SeverityConfig& severity) { core::validate_fields("severity", severity); }
void validate(const PlannerConfig& planner) { core::validate_fields("planner", planner); }
void validate(const RoadsideConfig& roadside) { core::validate_fields("roadside", roadside); }
void validate(const SafeStateConfig& safe_state) { core::validate_fields("safe_state", safe_state); }
void validate(const ActuationConfig& actuation) { core::validate_fields("actuation", actuation); }

SceneConfig load_scene_config(const std::filesystem::path& path) { return read_scene(core::YamlNode::load_file(path)); }

SceneConfig parse_scene_config(const std::string& text, const std::string& file_name) {
  return read_scene(core::YamlNode::parse(text, file_name));
}

SceneConfig parse_stored_scene_config(const std::string& text, const std::string& file_name) {
  const core::YamlNode node = core::YamlNode::parse(text, file_name);
  YAML::Node root = node.raw();  // shares the parsed tree
  if (root.IsMap() && root["simulation"].IsMap() && root["simulation"]["latency_s"]) {
    root["actuation"]["perception_latency_s"] = root["simulation"]["latency_s"];
    root["simulation"].remove("latency_s");
    return parse_scene_config(core::to_yaml_text(root), file_name);
  }
  return read_scene(node);
}

std::string to_yaml(const SceneConfig& config) { return core::to_yaml_text(core::write_yaml(config)); }

std::filesystem::path profile_path(const std::string& profile, const std::filesystem::path& scene_dir) {
  if (profile.find('/') != std::string::npos || profile.ends_with(".yaml")) {
    if (!std::filesystem::is_regular_file(profile))
      throw UsageError(fmt::format("--profile: profile file '{}' does not exist", profile));
    return profile;
  }
  const std::filesystem::path folder = scene_dir / "profiles";
  std::filesystem::path file = folder / (profile + ".yaml");
  if (std::filesystem::is_regular_file(file)) return file;
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  throw UsageError(fmt::format("--profile: no profile '{}' in {} (known: {})", profile, folder.string(),
                               names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
}

std::string apply_profile(SceneConfig& config, const std::string& profile, const std::filesystem::path& scene_dir) {
  const std::filesystem::path file = profile_path(profile, scene_dir);
  const core::YamlNode root = core::YamlNode::load_file(file);
  ActuationProfile overlay;
  overlay.actuation = config.actuation;  // keys the profile leaves out keep the scene's values
  core::read_yaml(root, overlay);
  try {
    validate(overlay.actuation);
  } catch (const core::ConfigError& e) {
    core::fail_at(*root.find("actuation"), e, /*with_path=*/true);
  }
  config.actuation = overlay.actuation;
  return overlay.description;
}

namespace {

constexpr double kMaxSpeed_kph = 400.0;  // above every road vehicle: a value beyond is another unit

double drivable_width_m(const SceneConfig& config) noexcept {
  return config.road.drivable_max_y_m() - config.road.drivable_min_y_m();
}

// The values each factor accepts, in cell order: the one owner of scenario_factors' limits, which
// validate_cell reads without building the table's texts (it runs for every cell simulated).
std::array<FactorLimits, tjunction::kFactors> factor_limits(const SceneConfig& config) noexcept {
  std::array<FactorLimits, tjunction::kFactors> limits{};
  limits[kSpeed].high = kMaxSpeed_kph;
  limits[kMu].high = 2.0;
  limits[kPassage].high = drivable_width_m(config);
  limits[kTruckSpeed] = {.low = 0.0, .low_inclusive = true, .high = kMaxSpeed_kph};
  return limits;
}

}  // namespace

FactorTable scenario_factors(const SceneConfig& config) {
  constexpr std::string_view kWhySpeed = "faster than any road vehicle drives; the speed is in km/h";
  const double width_m = drivable_width_m(config);
  const auto limits = factor_limits(config);
  const TJunctionCell defaults;
  std::vector<Factor> factors(tjunction::kFactors);
  factors[kSpeed] = {.key = "speed_kph",
                     .unit = "km/h",
                     .what = "ego speed",
                     .axis = "ego speed (km/h)",
                     .plural = "speeds",
                     .held = "v = {} km/h",
                     .brief = "{:g} km/h",
                     .role = FactorRole::kEgoSpeed,
                     .default_value = defaults.speed_kph,
                     .limits = limits[kSpeed],
                     .why_high = std::string(kWhySpeed),
                     .band = 1.0,
                     .name = "speed"};
  factors[kTtc] = {.key = "ttc_s",
                   .unit = "s",
                   .what = "time to collision",
                   .axis = "time to collision TTC (s)",
                   .plural = "TTCs",
                   .held = "TTC = {} s",
                   .brief = "TTC {:g} s",
                   .role = FactorRole::kTtc,
                   .default_value = defaults.ttc_s,
                   .limits = limits[kTtc],
                   .why_high = "",
                   .name = "TTC"};
  factors[kMu] = {.key = "mu",
                  .unit = "1",
                  .what = "friction coefficient",
                  .axis = "road friction μ (–)",
                  .plural = "μ",
                  .held = "μ = {}",
                  .brief = "mu {:g}",
                  .role = FactorRole::kFriction,
                  .default_value = defaults.mu,
                  .limits = limits[kMu],
                  .why_high = "",
                  .name = "μ"};
  factors[kPassage] = {
      .key = "passage_m",
      .unit = "m",
      .what = "passage width",
      .axis = "passage width (m)",
      .plural = "passage widths",
      .held = "passage {} m",
      .brief = "passage {:g} m",
      .role = FactorRole::kPassage,
      .default_value = defaults.passage_m,
      .limits = limits[kPassage],
      .why_high = fmt::format("the drivable area is {:g} m wide: a wider passage is wider than the road", width_m),
      .name = "passage"};
  factors[kTruckSpeed] = {.key = "truck_speed_kph",
                          .unit = "km/h",
                          .what = "truck speed",
                          .axis = "truck speed (km/h)",
                          .plural = "truck speeds",
                          .held = "truck {} km/h",
                          .brief = "truck {:g} km/h",
                          .role = FactorRole::kOther,
                          .default_value = config.truck.speed_kph,
                          .limits = limits[kTruckSpeed],
                          .why_high = std::string(kWhySpeed),
                          .band = 1.0,
                          .name = "truck speed"};
  return FactorTable(std::move(factors));
}

TJunctionCell TJunctionCell::of(const CellInput& cell) noexcept {
  return {cell[kSpeed], cell[kTtc], cell[kMu], cell[kPassage], cell[kTruckSpeed]};
}

void validate_cell(const SceneConfig& config, const CellInput& cell) {
  const auto limits = factor_limits(config);
  bool accepted = cell.size() == limits.size();
  for (std::size_t i = 0; accepted && i < limits.size(); ++i) accepted = limits[i].accepts(cell[i]);
  if (!accepted) scenario_factors(config).validate(cell);  // throws, naming the factor and its limits
}

Scene::Scene(const SceneConfig& config, const CellInput& cell)
    : config_(&config),
      cell_(cell),
      speed_kph_(cell.ego_speed_kph()),
      ttc_s_(cell.time_to_collision_s()),
      mu_(cell.friction()),
      initial_distance_m_(speed_kph_ / 3.6 * ttc_s_),
      truck_speed_mps_(cell[kTruckSpeed] / 3.6) {
  // passage_m is the gap once the truck stands (or, never stopping, at t = TTC): the truck
  // starts that far plus its travel until then above the right edge of the drivable area.
  const double a = config.truck.decel_mps2;
  const double travel_m = a > 0.0 ? truck_speed_mps_ * truck_speed_mps_ / (2.0 * a) : truck_speed_mps_ * ttc_s_;
  truck_front_y0_m_ = config.road.drivable_min_y_m() + cell[kPassage] + travel_m;
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
  const auto [c, sn] = core::cos_sin(s.yaw_rad);
  const core::Vec2 heading{c, sn};
  // The CG is not at the middle of the car: shift by half the difference of its two ends.
  const double offset_m = (ego.cg_to_front_m() - ego.cg_to_rear_m()) / 2.0;
  return {core::Vec2{s.x_m, s.y_m} + heading * offset_m, s.yaw_rad, ego.length_m, ego.width_m};
}

bool Scene::on_drivable_area(const core::OrientedBox& ego) const noexcept { return edge_gap_m(ego) >= 0.0; }

double Scene::edge_gap_m(const core::OrientedBox& box) const noexcept {
  // The lowest and highest corner: the box's half-extent across the road.
  const auto [cos_h, sin_h] = core::cos_sin(box.heading_rad);
  const double half_extent_y = 0.5 * (box.length_m * std::abs(sin_h) + box.width_m * std::abs(cos_h));
  return std::min(box.center.y - half_extent_y - config_->road.drivable_min_y_m(),
                  config_->road.drivable_max_y_m() - box.center.y - half_extent_y);
}

double Scene::truck_far_x_m() const noexcept { return initial_distance_m_ + config_->truck.width_m; }

}  // namespace emrm::sim
