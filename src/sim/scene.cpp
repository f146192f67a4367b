#include "emrm/sim/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "emrm/core/error.hpp"
#include "emrm/core/trig.hpp"
#include "emrm/core/yaml.hpp"

namespace emrm::sim {
namespace {

// The scene readers of other formats, by extension (SceneReaderRegistration).
struct SceneReaders {
  std::mutex mutex;
  std::map<std::string, std::function<SceneConfig(const std::filesystem::path&)>, std::less<>> by_extension;
};
SceneReaders& scene_readers() {
  static SceneReaders readers;
  return readers;
}

// An imported scenario's file, relative to the scene file's folder as written: made absolute, and
// it must exist.
void resolve_scenario_file(const core::YamlNode& root, SceneConfig& config, const std::filesystem::path& scene_file) {
  if (config.family != "openscenario") return;
  std::filesystem::path file = config.openscenario.file;
  if (file.is_relative()) file = scene_file.parent_path() / file;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    core::node_at(root, core::FieldPath{{std::string("openscenario"), std::string("file")}})
        .fail(fmt::format("expected an OpenSCENARIO file (.xosc), but '{}' is not a file", file.string()));
  config.openscenario.file = std::filesystem::absolute(file).lexically_normal().string();
}

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

SceneReaderRegistration::SceneReaderRegistration(std::string extension,
                                                 std::function<SceneConfig(const std::filesystem::path&)> read)
    : extension_(std::move(extension)) {
  SceneReaders& readers = scene_readers();
  const std::scoped_lock lock(readers.mutex);
  if (!readers.by_extension.emplace(extension_, std::move(read)).second)
    throw UsageError(fmt::format("a scene reader for '{}' files is registered already", extension_));
}

SceneReaderRegistration::~SceneReaderRegistration() {
  SceneReaders& readers = scene_readers();
  const std::scoped_lock lock(readers.mutex);
  readers.by_extension.erase(extension_);
}

SceneConfig load_scene_config(const std::filesystem::path& path) {
  std::function<SceneConfig(const std::filesystem::path&)> reader;
  {
    SceneReaders& readers = scene_readers();
    const std::scoped_lock lock(readers.mutex);
    if (const auto it = readers.by_extension.find(path.extension().string()); it != readers.by_extension.end())
      reader = it->second;
  }
  if (reader) return reader(path);
  const core::YamlNode root = core::YamlNode::load_file(path);
  SceneConfig config = read_scene(root);
  resolve_scenario_file(root, config, path);
  if (const auto family = find_family(config.family); family->check_scene) try {
      family->check_scene(config);
    } catch (const core::ConfigError& e) {
      core::fail_at(root, e, /*with_path=*/true);
    }
  return config;
}

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

FactorTable scenario_factors(const SceneConfig& config) { return find_family(config.family)->factors(config); }

void validate_cell(const SceneConfig& config, const CellInput& cell) {
  const auto family = find_family(config.family);
  if (family->validate_cell)
    family->validate_cell(config, cell);
  else
    family->factors(config).validate(cell);
}

Scene::Scene(const SceneConfig& config, const CellInput& cell)
    : config_(&config),
      cell_(cell),
      speed_kph_(cell.ego_speed_kph()),
      ttc_s_(cell.time_to_collision_s()),
      mu_(cell.friction()),
      layout_(find_family(config.family)->layout(config, cell)) {
  if (layout_.actors.empty())
    throw std::logic_error(fmt::format("scenario family '{}' laid out a cell without a hazard", config.family));
  if (layout_.ego_speed_mps) speed_kph_ = *layout_.ego_speed_mps * 3.6;
}

bool Scene::feasible() const noexcept {
  // The tolerance keeps cells whose v·TTC lands exactly on the limit (up to rounding of the
  // grid's steps) feasible.
  return layout_.infeasible.empty() && layout_.initial_distance_m <= config_->max_initial_distance_m + 1e-9;
}

std::string Scene::infeasible_reason() const {
  if (!layout_.infeasible.empty()) return layout_.infeasible;
  if (feasible()) return {};
  const bool v_ttc = find_family(config_->family)->stop_boundary;
  return fmt::format(
      "the {} would appear {:.2f} m ahead ({}), beyond the scene's max_initial_distance_m = {:g} m (the speed is in "
      "km/h, the TTC in seconds)",
      hazard().body().name, layout_.initial_distance_m, v_ttc ? "v·TTC" : "its gap", config_->max_initial_distance_m);
}

VehicleState Scene::ego_initial() const noexcept {
  VehicleState s;
  s.x_m = -config_->ego.cg_to_front_m();
  s.y_m = layout_.ego_y_m;
  s.yaw_rad = 0.0;
  s.vx_mps = initial_speed_mps();
  return s;
}

core::OrientedBox Scene::ego_box(const VehicleState& s) const noexcept {
  const VehicleParams& ego = config_->ego;
  const auto [c, sn] = core::cos_sin(s.yaw_rad);
  const core::Vec2 heading{c, sn};
  // The CG is not at the middle of the car: shift by half the difference of its two ends.
  const double offset_m = (ego.cg_to_front_m() - ego.cg_to_rear_m()) / 2.0;
  return {core::Vec2{s.x_m, s.y_m} + heading * offset_m, s.yaw_rad, ego.length_m, ego.width_m};
}

double Scene::passed_x_of_track(double t_s) const noexcept {
  double far = -std::numeric_limits<double>::infinity();
  for (const core::Vec2& corner : hazard_at(t_s).box.corners()) far = std::max(far, corner.x);
  return far;
}

FreeBands Scene::free_bands(double t_s) const noexcept {
  FreeBands out;
  std::tie(out.hazard_low_m, out.hazard_high_m) = hazard().y_extent_at(t_s);
  for (const FreeBand band : {FreeBand{layout_.road.min_y_m, std::min(out.hazard_low_m, layout_.road.max_y_m), true},
                              FreeBand{std::max(out.hazard_high_m, layout_.road.min_y_m), layout_.road.max_y_m, false}})
    if (band.high_m > band.low_m) out.band[out.count++] = band;
  return out;
}

bool Scene::on_drivable_area(const core::OrientedBox& ego) const noexcept { return edge_gap_m(ego) >= 0.0; }

double Scene::edge_gap_m(const core::OrientedBox& box) const noexcept {
  // The lowest and highest corner: the box's half-extent across the road.
  const auto [cos_h, sin_h] = core::cos_sin(box.heading_rad);
  const double half_extent_y = 0.5 * (box.length_m * std::abs(sin_h) + box.width_m * std::abs(cos_h));
  return std::min(box.center.y - half_extent_y - layout_.road.min_y_m,
                  layout_.road.max_y_m - box.center.y - half_extent_y);
}

}  // namespace emrm::sim
