#pragma once

// The T-junction "EMRM Scene 1" (docs/scene-yaml.md): configuration with every default, and the
// geometry and truck motion of one scenario cell. Road frame: x along the main road (ego drives
// +x), y to the left; the ego's front bumper is at x = 0 when the hazard appears (t = 0).

#include <array>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/config.hpp"
#include "emrm/core/geometry.hpp"
#include "emrm/sim/actor.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/crossing.hpp"
#include "emrm/sim/cut_in.hpp"
#include "emrm/sim/factors.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/highway.hpp"
#include "emrm/sim/openscenario_config.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

struct RoadConfig {
  double lane_width_m = 3.5;
  int lanes = 2;                     ///< the main road spans y ∈ [-lanes/2·w, lanes/2·w]
  double shoulder_m = 1.5;           ///< paved shoulder on the right: drivable down to -(lanes/2·w + shoulder)
  double ego_lane_center_m = -1.75;  ///< checked against the ego's width by SceneConfig

  [[nodiscard]] double drivable_min_y_m() const { return -(lanes * lane_width_m / 2.0) - shoulder_m; }
  [[nodiscard]] double drivable_max_y_m() const { return lanes * lane_width_m / 2.0; }

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, lane_width_m, core::positive);
    EMRM_FIELD(a, lanes, core::at_least(1, "lane"));
    EMRM_FIELD(a, shoulder_m, core::non_negative);
    EMRM_FIELD(a, ego_lane_center_m);
  }
};

/// The T-junction's rigid truck, crossing the main road from the side road on the left, heading -y.
using TruckConfig = ObstacleConfig;

struct SimulationConfig {
  static constexpr double kMinStep_s = 1e-4, kMaxStep_s = 0.1, kMaxHorizon_s = 60.0;
  std::string vehicle_model = "single_track_fiala";
  double dt_s = 0.01;
  double horizon_s = 4.0;  ///< longest simulated time after t = 0
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, vehicle_model, core::one_of(vehicle_model_names, "vehicle model"));
    // A finer step than 0.1 ms or a horizon beyond a minute adds no accuracy to a maneuver of a
    // few seconds, only time: the bounds keep a small file from running for hours.
    EMRM_FIELD(a, dt_s, core::within(kMinStep_s, kMaxStep_s));
    EMRM_FIELD(a, horizon_s, core::within(kMinStep_s, kMaxHorizon_s));
    if constexpr (requires { a.moved("", ""); }) a.moved("latency_s", "actuation.perception_latency_s");
    a.ensure(!(dt_s > horizon_s), "dt_s", "expected a time step no longer than the horizon ({} s), got {} s", horizon_s,
             dt_s);
  }
};

/// What lies beyond the edges of the drivable area (docs/physics.md, "Road departure").
struct RoadsideConfig {
  /// "barrier": a rigid wall or guardrail along both edges; a departure is an impact against an
  /// immovable body, assessed by the same impact model as a contact with the truck.
  /// "open": clear, traversable ground; a departure hits nothing (Δv 0) and scores L4.
  /// "embankment": a slope down from both edges, `embankment_slope_h` of run per unit of drop;
  /// steeper than the critical 1V:3H the car rolls over (SeverityConfig::rollover_p_fatal).
  std::string type = "barrier";
  double embankment_slope_h = 2.0;

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, type, core::one_of(roadside_types, "roadside type"));
    // Written for an embankment only: stores and configuration hashes written before it stay valid.
    if (!core::writes_file<A> || type == "embankment") EMRM_FIELD(a, embankment_slope_h, core::positive);
  }
  [[nodiscard]] static std::vector<std::string> roadside_types() { return core::enum_names<Roadside>(); }
  [[nodiscard]] bool barrier() const noexcept { return type == "barrier"; }
};

/// When an avoidance counts: the car passes (or stops short of) the truck without contact and then
/// reaches a safe state on the drivable area: stopped, or stable with room to stop
/// (docs/physics.md, "Safe state").
struct SafeStateConfig {
  double horizon_s = 8.0;              ///< longest recovery after passing the truck
  double max_yaw_rate_radps = 0.05;    ///< stable: |r| at most this
  double max_slip_angle_rad = 0.02;    ///< stable: |β| at most this
  double max_heading_error_rad = 0.1;  ///< stable: |ψ| (against the road's direction) at most this
  double max_steer_rad = 0.02;         ///< stable: the wheels (nearly) straight

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, horizon_s, core::positive);
    EMRM_FIELD(a, max_yaw_rate_radps, core::positive);
    EMRM_FIELD(a, max_slip_angle_rad, core::positive);
    EMRM_FIELD(a, max_heading_error_rad, core::positive);
    EMRM_FIELD(a, max_steer_rad, core::positive);
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
  /// A departure down an embankment steeper than `critical_slope_h` (run per unit of drop) rolls the
  /// car over (AASHTO's critical slopes, steeper than 1V:3H); a rollover kills this share of the
  /// occupants (NHTSA, Strashny 2007), and injures at least as many seriously (docs/physics.md).
  double critical_slope_h = 3.0;
  double rollover_p_fatal = 0.027;
  /// A pedestrian struck by the car's front, by the impact (closing) speed in km/h: P = 1 / (1 +
  /// exp(intercept − slope · v)). Death: Hussain et al. 2019 (meta-analysis; odds ratio 1.11 per
  /// km/h, 50 % at 59 km/h); serious injury (AIS 4+): fitted to Tefft 2013's five published points
  /// (docs/physics.md, "Pedestrians").
  double pedestrian_fatal_intercept = 6.157;
  double pedestrian_fatal_slope_per_kph = 0.10436;
  double pedestrian_serious_intercept = 4.621;
  double pedestrian_serious_slope_per_kph = 0.08759;
  /// A cyclist struck by the car's front, by the closing speed in km/h: P(MAIS3+) = 1 / (1 +
  /// exp(intercept − slope · v)), Lubbe, Wu & Jeppsson 2022's cyclist model (logit −7.467 + 0.079 v
  /// + 0.047 age) for a 40-year-old rider (docs/physics.md, "Cyclists"). A cyclist's risk of death
  /// is the pedestrian's (no published cyclist curve is carried; the pedestrian's is the higher).
  double cyclist_serious_intercept = 5.587;
  double cyclist_serious_slope_per_kph = 0.079;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, restitution, core::within(0.0, 1.0));
    EMRM_FIELD(a, contact_friction, core::non_negative);
    EMRM_FIELD(a, mais3_intercept);
    EMRM_FIELD(a, mais3_slope_per_mps, core::positive);
    EMRM_FIELD(a, fatal_reference_mps, core::positive);
    EMRM_FIELD(a, fatal_exponent, core::positive);
    EMRM_FIELD(a, l6_p_mais3, core::probability);
    EMRM_FIELD(a, l7_p_fatal, core::probability);
    // The rollover's, the pedestrians' and the cyclists' fields came later: written only when changed, so that
    // stores written before them stay valid.
    const SeverityConfig defaults;
    EMRM_FIELD_UNLESS_DEFAULT(a, critical_slope_h, defaults.critical_slope_h, core::positive);
    EMRM_FIELD_UNLESS_DEFAULT(a, rollover_p_fatal, defaults.rollover_p_fatal, core::probability);
    EMRM_FIELD_UNLESS_DEFAULT(a, pedestrian_fatal_intercept, defaults.pedestrian_fatal_intercept);
    EMRM_FIELD_UNLESS_DEFAULT(a, pedestrian_fatal_slope_per_kph, defaults.pedestrian_fatal_slope_per_kph,
                              core::positive);
    EMRM_FIELD_UNLESS_DEFAULT(a, pedestrian_serious_intercept, defaults.pedestrian_serious_intercept);
    EMRM_FIELD_UNLESS_DEFAULT(a, pedestrian_serious_slope_per_kph, defaults.pedestrian_serious_slope_per_kph,
                              core::positive);
    EMRM_FIELD_UNLESS_DEFAULT(a, cyclist_serious_intercept, defaults.cyclist_serious_intercept);
    EMRM_FIELD_UNLESS_DEFAULT(a, cyclist_serious_slope_per_kph, defaults.cyclist_serious_slope_per_kph, core::positive);
  }
};

/// Search budget of the RRT strategies (docs/planner.md).
struct PlannerConfig {
  int max_nodes = 2000;
  double max_time_ms = 5000.0;  ///< wall-clock guard; the node budget is what makes runs repeatable
  double min_duration_s = 0.1;  ///< control intervals are sampled in [min, max]
  double max_duration_s = 0.4;
  double goal_bias = 0.3;  ///< probability of extending towards the passage
  /// Rollouts of each local optimisation of the falsifier, which runs first in the strengthened
  /// search, wherever no strategy avoided and no certificate proves that none can (docs/planner.md,
  /// "The falsifier"); 0 leaves it its grid alone.
  int falsifier_evaluations = 150;
  /// Restarts of the strengthened search after the falsifier, each with the full budget and a seed
  /// from the cell alone (docs/planner.md, "A region that does not depend on the seed") ...
  int restarts = 6;
  /// ... where avoidance is plausible: the falsifier came within this of one (across the hazard's
  /// edge, or short of stopping: its closest miss).
  double plausible_miss_m = 0.4;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, max_nodes, core::at_least(1, "node"));
    EMRM_FIELD(a, max_time_ms, core::positive);
    EMRM_FIELD(a, min_duration_s, core::positive);
    EMRM_FIELD(a, max_duration_s, core::positive);
    a.ensure(!(min_duration_s > max_duration_s), "min_duration_s",
             "expected min_duration_s <= max_duration_s ({} s), got {} s", max_duration_s, min_duration_s);
    EMRM_FIELD(a, goal_bias, core::within(0.0, 1.0));
    EMRM_FIELD(a, falsifier_evaluations, core::non_negative);
    EMRM_FIELD(a, restarts, core::non_negative);
    EMRM_FIELD(a, plausible_miss_m, core::non_negative);
  }
};

/// The EMRM controller's on-board computer (docs/simulate.md, "emrm"; docs/decisions.md): the
/// search it affords for each evasive strategy before it must commit, on the scene it perceives.
struct ControllerConfig {
  /// Extension attempts of one on-board search (the full search's are planner.max_nodes).
  int max_nodes = 300;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, max_nodes, core::at_least(1, "node"));
  }
};

/// Everything about the scene; one YAML file (examples/tjunction/scene.yaml, docs/scene-yaml.md).
struct SceneConfig {
  std::string name = "EMRM Scene 1";
  static constexpr std::string_view kDefaultFamily = "tjunction";
  std::string family{kDefaultFamily};  ///< the scenario family (family.hpp) that lays out its cells
  RoadConfig road;
  TruckConfig truck;
  VehicleParams ego;
  SimulationConfig simulation;
  ActuationConfig actuation;
  SeverityConfig severity;
  PlannerConfig planner;
  ControllerConfig controller;
  RoadsideConfig roadside;
  SafeStateConfig safe_state;
  HighwayConfig highway;            ///< the family highway_obstacle's road and obstacles
  CrossingConfig crossing;          ///< the family pedestrian_crossing's street and its actors
  CutInConfig cut_in;               ///< the family cut_in's highway and its cars
  OpenScenarioConfig openscenario;  ///< the family openscenario's scenario file and its factors
  /// Cells whose hazard appears farther ahead (v·TTC; a cut-in's gap) are infeasible (grey).
  double max_initial_distance_m = 24.5;

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, name);
    // The T-junction was the only scene before families: a scene of it is written without the key, so
    // that stores and configuration hashes written before families existed stay valid
    // (docs/decisions.md, "A scene names its family").
    if (!core::writes_file<A> || family != kDefaultFamily)
      EMRM_FIELD(a, family, core::one_of(family_names, "scenario family"));
    EMRM_FIELD(a, road);
    EMRM_FIELD(a, truck);
    EMRM_FIELD(a, ego);
    EMRM_FIELD(a, simulation);
    EMRM_FIELD(a, actuation);
    EMRM_FIELD(a, severity);
    EMRM_FIELD(a, planner);
    EMRM_FIELD(a, controller);
    EMRM_FIELD(a, roadside);
    EMRM_FIELD(a, safe_state);
    // A family's own block is written for a scene of that family only.
    if (!core::writes_file<A> || family == "highway_obstacle") EMRM_FIELD(a, highway);
    if (!core::writes_file<A> || family == "pedestrian_crossing") EMRM_FIELD(a, crossing);
    if (!core::writes_file<A> || family == "cut_in") EMRM_FIELD(a, cut_in);
    if (family == "openscenario")
      EMRM_REQUIRED_FIELD(a, openscenario);
    else if (!core::writes_file<A>)  // every field for Python's attributes and the checks
      EMRM_FIELD(a, openscenario);
    EMRM_FIELD(a, max_initial_distance_m, core::positive);
    // Checked last: it depends on the road and on the ego's width, which must be sane first. The
    // whole car must start on the drivable area, or every run would begin with a road departure.
    // An imported scenario's ego starts where its storyboard puts it (checked when a cell is laid out).
    const EgoStart start = ego_start();
    const double half_width = ego.width_m / 2.0;
    a.ensure(family == "openscenario" ||
                 (start.y_m - half_width >= start.min_y_m && start.y_m + half_width <= start.max_y_m),
             start.field, "the ego ({} m wide) centred at y = {} m does not fit on the drivable area y in [{}, {}] m",
             ego.width_m, start.y_m, start.min_y_m, start.max_y_m);
  }

  /// Where the ego starts across the road and the drivable area it must fit on, from the block of
  /// the scene's family that sets them (`field`, for messages).
  struct EgoStart {
    double y_m, min_y_m, max_y_m;
    std::string_view field;
  };
  [[nodiscard]] EgoStart ego_start() const noexcept {
    if (family == "highway_obstacle")
      return {highway.ego_y_m(), highway.min_y_m(), highway.max_y_m(), "highway.ego_lane"};
    if (family == "pedestrian_crossing")
      return {crossing.ego_y_m(), crossing.min_y_m(), crossing.max_y_m(), "crossing.lane_width_m"};
    if (family == "cut_in") return {cut_in.ego_y_m(), cut_in.min_y_m(), cut_in.max_y_m(), "cut_in.lane_width_m"};
    return {road.ego_lane_center_m, road.drivable_min_y_m(), road.drivable_max_y_m(), "road.ego_lane_center_m"};
  }
};

/// Checks every field of a scene against its constraints and the rules across fields (all sizes,
/// masses and time steps > 0, a known vehicle model, a step no longer than the horizon, the ego's
/// lane on the drivable area, ...: docs/scene-yaml.md). Throws core::ConfigError (an InputError)
/// naming the field path: "scene: road.lane_width_m: expected a value > 0, got -1".
void validate(const SceneConfig& config);
/// The same for one part of a scene; the message names the part ("road: lanes: ...").
void validate(const RoadConfig& road);
void validate(const TruckConfig& truck);
void validate(const SimulationConfig& simulation);
void validate(const SeverityConfig& severity);
void validate(const PlannerConfig& planner);
void validate(const RoadsideConfig& roadside);
void validate(const SafeStateConfig& safe_state);
void validate(const ActuationConfig& actuation);

/// Loads a scene file and validates it (validate(const SceneConfig&)). Throws InputError
/// (file:line:column) for malformed YAML, wrong types, unknown fields, and for a value validate()
/// rejects: at the field's own node, or at the nearest enclosing mapping the file has when the
/// field kept its default.
///
/// A file whose extension a SceneReaderRegistration names (".xosc") is read by that reader instead.
/// A scene of the family openscenario has its `openscenario.file` made absolute (relative to the
/// scene file's folder) and must name an existing file (InputError at the field).
[[nodiscard]] SceneConfig load_scene_config(const std::filesystem::path& path);

/// Reads scene files of another format into a scene — an OpenSCENARIO scenario (docs/import.md) —
/// for load_scene_config, by the file's extension (".xosc"), for as long as the object lives.
/// Throws UsageError for an extension with a reader already.
class SceneReaderRegistration {
 public:
  SceneReaderRegistration(std::string extension, std::function<SceneConfig(const std::filesystem::path&)> read);
  ~SceneReaderRegistration();
  SceneReaderRegistration(const SceneReaderRegistration&) = delete;
  SceneReaderRegistration& operator=(const SceneReaderRegistration&) = delete;

 private:
  std::string extension_;
};
[[nodiscard]] SceneConfig parse_scene_config(const std::string& text, const std::string& file_name);
/// A scene as a results store keeps it: the same, except that a store written before the actuators
/// existed has `simulation.latency_s`, read as `actuation.perception_latency_s` (its meaning).
[[nodiscard]] SceneConfig parse_stored_scene_config(const std::string& text, const std::string& file_name);
/// The effective scene as YAML.
[[nodiscard]] std::string to_yaml(const SceneConfig& config);

/// An actuation profile (docs/actuation.md, "Profiles"): a YAML file with an optional
/// `description:` and an `actuation:` mapping whose keys overlay the scene's.
struct ActuationProfile {
  std::string description;
  ActuationConfig actuation;
  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, description);
    EMRM_REQUIRED_FIELD(a, actuation);
  }
};

/// Where a profile's file is: `profile` itself when it names a file (it contains a '/' or ends in
/// .yaml), else `scene_dir`/profiles/`profile`.yaml (an empty `scene_dir` is the current folder). Throws UsageError for
/// a NAME with no such file (listing the names in that folder).
[[nodiscard]] std::filesystem::path profile_path(const std::string& profile, const std::filesystem::path& scene_dir);
/// Overlays the profile on `config`'s actuation (keys it does not give keep the scene's values) and
/// validates the result; returns the profile's `description:`. Throws InputError (file:line:column)
/// for a malformed profile.
std::string apply_profile(SceneConfig& config, const std::string& profile, const std::filesystem::path& scene_dir);

/// The T-junction's factors in cell order (docs/scene-yaml.md, "Factors"): the ego's speed
/// (speed_kph), the time to collision (ttc_s), the road's friction (mu), the passage left beside the
/// truck (passage_m; at most the drivable area's width) and the truck's speed (truck_speed_kph; the
/// scene's truck.speed_kph by default).
[[nodiscard]] FactorTable scenario_factors(const SceneConfig& config);

namespace tjunction {
/// The positions of the T-junction's factors in its cells (scenario_factors' order): for code of
/// the T-junction's own that reads a factor's key from the table (its OpenSCENARIO expressions).
enum Position : std::size_t { kSpeed, kTtc, kMu, kPassage, kTruckSpeed, kFactors };
}  // namespace tjunction

/// A T-junction cell by its factors' names, for code and tests that build one by hand.
struct TJunctionCell {
  double speed_kph = 50.0;
  double ttc_s = 1.0;
  double mu = 1.0;
  double passage_m = 3.0;
  double truck_speed_kph = TruckConfig{}.speed_kph;

  // NOLINTNEXTLINE(google-explicit-constructor): a named cell is a cell
  operator CellInput() const { return {speed_kph, ttc_s, mu, passage_m, truck_speed_kph}; }
  /// The named form of a T-junction cell (one of scenario_factors' cells).
  [[nodiscard]] static TJunctionCell of(const CellInput& cell) noexcept;
};

/// Checks a cell against scenario_factors(config): every factor finite and within its limits.
/// Throws UsageError naming the factor and its accepted range.
void validate_cell(const SceneConfig& config, const CellInput& cell);

/// A band of the road, y ∈ [low_m, high_m], free of the hazard (Scene::free_bands).
struct FreeBand {
  double low_m = 0.0;
  double high_m = 0.0;
  bool right = false;  ///< right of the hazard (below its lowest y), else left of it
};

/// The free bands beside the hazard, the right one first, and the hazard's extent across the road
/// they were cut from.
struct FreeBands {
  std::array<FreeBand, 2> band{};
  std::size_t count = 0;
  double hazard_low_m = 0.0;   ///< the hazard's lowest y
  double hazard_high_m = 0.0;  ///< and its highest
};

/// One cell's scene as its family lays it out (family.hpp): the ego's start, the road, the other
/// road users and their motion.
class Scene {
 public:
  /// Lays out the cell by the scene's family (SceneConfig::family).
  Scene(const SceneConfig& config, const CellInput& cell);

  [[nodiscard]] const SceneConfig& config() const noexcept { return *config_; }
  [[nodiscard]] const CellInput& cell() const noexcept { return cell_; }
  /// The cell as its family laid it out.
  [[nodiscard]] const SceneLayout& layout() const noexcept { return layout_; }
  /// The family laid the cell out (SceneLayout::infeasible) and the hazard appears within
  /// max_initial_distance_m.
  [[nodiscard]] bool feasible() const noexcept;
  /// Why the cell is infeasible, for messages ("the hazard would appear 30 m ahead (v·TTC), beyond
  /// ..."); empty for a feasible cell.
  [[nodiscard]] std::string infeasible_reason() const;
  /// Distance from the ego's front bumper to the hazard's near side at t = 0.
  [[nodiscard]] double initial_distance_m() const noexcept { return layout_.initial_distance_m; }
  [[nodiscard]] double initial_speed_mps() const noexcept {
    return layout_.ego_speed_mps ? *layout_.ego_speed_mps : speed_kph_ / 3.6;
  }
  /// The cell's factors the physics reads: the ego's speed (km/h), the TTC (s), the road's friction.
  [[nodiscard]] double speed_kph() const noexcept { return speed_kph_; }
  [[nodiscard]] double ttc_s() const noexcept { return ttc_s_; }
  [[nodiscard]] double friction() const noexcept { return mu_; }
  /// The drivable area and its roadsides.
  [[nodiscard]] const Road& road() const noexcept { return layout_.road; }
  /// The other road users; the first is the hazard.
  [[nodiscard]] std::span<const Actor> actors() const noexcept { return layout_.actors; }
  /// The actor the TTC is measured against (the T-junction's truck).
  [[nodiscard]] const Actor& hazard() const noexcept { return layout_.actors.front(); }
  /// The hazard's speed when it appears (m/s).
  [[nodiscard]] double hazard_speed_mps() const noexcept {
    const ActorMotion& m = hazard().motion();
    return m.track ? m.track->samples.front().speed_mps : m.speed_mps;
  }
  /// Ego CG in its lane, front bumper at x = 0, heading +x at the cell's speed.
  [[nodiscard]] VehicleState ego_initial() const noexcept;
  /// The hazard at time t ≥ 0.
  [[nodiscard]] ActorState hazard_at(double t_s) const noexcept { return hazard().at(t_s); }
  /// y of the hazard's leading edge at time t: the T-junction's truck's front, its lowest y.
  [[nodiscard]] double truck_front_y_at(double t_s) const noexcept { return hazard().motion().front_at(t_s).y; }
  /// The ego's footprint at a state.
  [[nodiscard]] core::OrientedBox ego_box(const VehicleState& s) const noexcept;
  /// All four corners within the drivable band y ∈ [min, max].
  [[nodiscard]] bool on_drivable_area(const core::OrientedBox& ego) const noexcept;
  /// How far the box is from the nearer edge of the drivable band (m): its lowest corner above
  /// y_min or its highest below y_max; negative once a corner is across.
  [[nodiscard]] double edge_gap_m(const core::OrientedBox& box) const noexcept;
  /// The parts of the drivable band beside the hazard at time t (by its extent across the road; the
  /// T-junction's passage is the right one): where a path past it may lie. Bands of no width are left out.
  [[nodiscard]] FreeBands free_bands(double t_s) const noexcept;
  /// The hazard's far side at time t: an ego whose rear is beyond it has got past the hazard. It
  /// moves with a hazard that drives along the road (a cut-in's car; a Track's: its box's farthest
  /// corner along x); t < 0 counts as 0.
  [[nodiscard]] double passed_x_m(double t_s = 0.0) const noexcept {
    const ActorMotion& m = hazard().motion();
    if (m.track) return passed_x_of_track(t_s);
    return m.direction.x == 0.0 ? layout_.passed_x_m : layout_.passed_x_m + m.direction.x * m.travelled_m(t_s);
  }

 private:
  [[nodiscard]] double passed_x_of_track(double t_s) const noexcept;

  const SceneConfig* config_;  // borrowed: the config outlives every Scene made from it
  CellInput cell_;
  double speed_kph_ = 0.0;
  double ttc_s_ = 0.0;
  double mu_ = 0.0;
  SceneLayout layout_;
};

}  // namespace emrm::sim
