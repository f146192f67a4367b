#pragma once

// The T-junction "EMRM Scene 1" (docs/scene-yaml.md): configuration with every default, and the
// geometry and truck motion of one scenario cell. Road frame: x along the main road (ego drives
// +x), y to the left; the ego's front bumper is at x = 0 when the hazard appears (t = 0).

#include <filesystem>
#include <string>

#include "emrm/core/geometry.hpp"
#include "emrm/core/yaml.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

struct RoadConfig {
  double lane_width_m = 3.5;
  int lanes = 2;               ///< the main road spans y ∈ [-lanes/2·w, lanes/2·w]
  double shoulder_m = 1.5;     ///< paved shoulder on the right: drivable down to -(lanes/2·w + shoulder)
  double ego_lane_center_m = -1.75;

  [[nodiscard]] double drivable_min_y_m() const { return -(lanes * lane_width_m / 2.0) - shoulder_m; }
  [[nodiscard]] double drivable_max_y_m() const { return lanes * lane_width_m / 2.0; }

  template <class A>
  void serialize(A& a) {
    a.optional("lane_width_m", lane_width_m);
    a.optional("lanes", lanes);
    a.optional("shoulder_m", shoulder_m);
    a.optional("ego_lane_center_m", ego_lane_center_m);
  }
};

/// A rigid truck crossing the main road from the side road on the left, heading -y.
struct TruckConfig {
  double length_m = 10.0;
  double width_m = 2.5;
  double mass_kg = 12000.0;
  double yaw_inertia_kgm2 = 130000.0;  ///< ≈ m (L² + W²) / 12
  double speed_kph = 10.0;             ///< default crossing speed when the hazard appears
  double decel_mps2 = 4.0;             ///< its driver brakes to a standstill; 0: it keeps going

  template <class A>
  void serialize(A& a) {
    a.optional("length_m", length_m);
    a.optional("width_m", width_m);
    a.optional("mass_kg", mass_kg);
    a.optional("yaw_inertia_kgm2", yaw_inertia_kgm2);
    a.optional("speed_kph", speed_kph);
    a.optional("decel_mps2", decel_mps2);
  }
};

struct SimulationConfig {
  std::string vehicle_model = "single_track_fiala";
  double dt_s = 0.01;
  double horizon_s = 4.0;   ///< longest simulated time after t = 0
  double latency_s = 0.0;   ///< before any actuation
  template <class A>
  void serialize(A& a) {
    a.optional("vehicle_model", vehicle_model);
    a.optional("dt_s", dt_s);
    a.optional("horizon_s", horizon_s);
    a.optional("latency_s", latency_s);
  }
};

/// Energy-based loss model (docs/physics.md, "Impacts and losses").
struct SeverityConfig {
  double restitution = 0.0;
  double contact_friction = 0.3;   ///< limits the tangential impulse of a glancing impact
  double mais3_intercept = 4.591;  ///< P(MAIS3+) = 1 / (1 + exp(intercept - slope · Δv[m/s]))
  double mais3_slope_per_mps = 0.185;
  double fatal_reference_mps = 31.74;  ///< Joksch: P(fatal) = min(1, (Δv / ref)^exponent)
  double fatal_exponent = 4.0;
  double l6_p_mais3 = 0.10;  ///< L6 when P(MAIS3+) reaches this
  double l7_p_fatal = 0.10;  ///< L7 when P(fatal) reaches this
  template <class A>
  void serialize(A& a) {
    a.optional("restitution", restitution);
    a.optional("contact_friction", contact_friction);
    a.optional("mais3_intercept", mais3_intercept);
    a.optional("mais3_slope_per_mps", mais3_slope_per_mps);
    a.optional("fatal_reference_mps", fatal_reference_mps);
    a.optional("fatal_exponent", fatal_exponent);
    a.optional("l6_p_mais3", l6_p_mais3);
    a.optional("l7_p_fatal", l7_p_fatal);
  }
};

/// Search budget of the RRT strategies (docs/planner.md).
struct PlannerConfig {
  int max_nodes = 2000;
  double max_time_ms = 5000.0;  ///< wall-clock guard; the node budget is what makes runs repeatable
  double min_duration_s = 0.1;  ///< control intervals are sampled in [min, max]
  double max_duration_s = 0.4;
  double goal_bias = 0.3;       ///< probability of extending towards the passage
  template <class A>
  void serialize(A& a) {
    a.optional("max_nodes", max_nodes);
    a.optional("max_time_ms", max_time_ms);
    a.optional("min_duration_s", min_duration_s);
    a.optional("max_duration_s", max_duration_s);
    a.optional("goal_bias", goal_bias);
  }
};

/// Everything about the scene; one YAML file (examples/tjunction/scene.yaml, docs/scene-yaml.md).
struct SceneConfig {
  std::string name = "EMRM Scene 1";
  RoadConfig road;
  TruckConfig truck;
  VehicleParams ego;
  SimulationConfig simulation;
  SeverityConfig severity;
  PlannerConfig planner;
  double max_initial_distance_m = 24.5;  ///< cells with v·TTC beyond this are infeasible (grey)

  template <class A>
  void serialize(A& a) {
    a.optional("name", name);
    a.optional("road", road);
    a.optional("truck", truck);
    a.optional("ego", ego);
    a.optional("simulation", simulation);
    a.optional("severity", severity);
    a.optional("planner", planner);
    a.optional("max_initial_distance_m", max_initial_distance_m);
  }
};

/// Loads and validates a scene file. Throws InputError (file:line:column) for malformed YAML,
/// wrong types, unknown fields, non-positive sizes/masses/time steps, an unknown vehicle model,
/// a horizon shorter than a step, or an ego lane outside the drivable area.
[[nodiscard]] SceneConfig load_scene_config(const std::filesystem::path& path);
[[nodiscard]] SceneConfig parse_scene_config(const std::string& text, const std::string& file_name);
/// The effective scene as YAML.
[[nodiscard]] std::string to_yaml(const SceneConfig& config);

/// The factors of one scenario cell.
struct CellInput {
  double speed_kph = 50.0;
  double ttc_s = 1.0;
  double mu = 1.0;
  double passage_m = 3.0;
  double truck_speed_kph = 10.0;
};

/// Checks a cell against the scene: speed > 0, TTC > 0, 0 < mu <= 2, truck speed >= 0, passage
/// > 0 and not wider than the drivable area, all finite. Throws UsageError naming the factor.
void validate_cell(const SceneConfig& config, const CellInput& cell);

/// Where the truck is at a time, and how fast it moves.
struct TruckState {
  core::OrientedBox box;
  core::Vec2 velocity_mps;
};

/// One cell's scene: the ego's start, the truck's motion, the drivable area. Cheap to copy.
class Scene {
 public:
  Scene(const SceneConfig& config, const CellInput& cell);

  [[nodiscard]] const SceneConfig& config() const noexcept { return *config_; }
  [[nodiscard]] const CellInput& cell() const noexcept { return cell_; }
  /// v·TTC ≤ max_initial_distance_m.
  [[nodiscard]] bool feasible() const noexcept;
  /// Distance from the ego's front bumper to the truck's near side at t = 0: v·TTC.
  [[nodiscard]] double initial_distance_m() const noexcept { return initial_distance_m_; }
  [[nodiscard]] double initial_speed_mps() const noexcept { return cell_.speed_kph / 3.6; }
  /// Ego CG in its lane, front bumper at x = 0, heading +x at the cell's speed.
  [[nodiscard]] VehicleState ego_initial() const noexcept;
  /// The truck at time t ≥ 0 (closed-form braking to a standstill).
  [[nodiscard]] TruckState truck_at(double t_s) const noexcept;
  /// y of the truck's front (its lowest y) at time t.
  [[nodiscard]] double truck_front_y_at(double t_s) const noexcept;
  /// The ego's footprint at a state.
  [[nodiscard]] core::OrientedBox ego_box(const VehicleState& s) const noexcept;
  /// All four corners within the drivable band y ∈ [min, max].
  [[nodiscard]] bool on_drivable_area(const core::OrientedBox& ego) const noexcept;
  /// x of the truck's far side: an ego whose rear is beyond it has passed the truck.
  [[nodiscard]] double truck_far_x_m() const noexcept;

 private:
  const SceneConfig* config_;  // borrowed: the config outlives every Scene made from it
  CellInput cell_;
  double initial_distance_m_ = 0.0;
  double truck_front_y0_m_ = 0.0;
  double truck_speed_mps_ = 0.0;
};

}  // namespace emrm::sim
