#pragma once

// OpenSCENARIO XML 1.2 and OpenDRIVE 1.6 export of a scenario cell or a plan (docs/openscenario.md):
// the T-junction as a road network, the ego and the truck with their dimensions, masses and
// performance, the truck's crossing and braking, the road friction, and the ego's executed
// trajectory as a timed FollowTrajectoryAction. Coordinates are emrm's road frame (x along the
// main road, y to the left, the ego's front bumper at x = 0 when the hazard appears).

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

/// Names every export uses (docs/openscenario.md, "Names").
inline constexpr const char* kEgoEntity = "Ego";
inline constexpr const char* kTruckEntity = "Truck";
inline constexpr const char* kRoadFile = "tjunction.xodr";
inline constexpr const char* kScenarioFile = "tjunction.xosc";
inline constexpr const char* kDistributionFile = "tjunction_distribution.xosc";
inline constexpr const char* kRoadsFolder = "roads";

/// Below this speed a car is at rest (sim's stopped test).
inline constexpr double kStoppedSpeed_mps = 0.05;

/// What the export assumes beyond the scene, which models the vehicles as boxes on the road plane.
struct ExportOptions {
  double ego_height_m = 1.4;
  double truck_height_m = 3.5;
  double ego_wheel_diameter_m = 0.6;
  double truck_wheel_diameter_m = 1.0;
  double ego_max_speed_mps = 250.0 / 3.6;  ///< Performance: what the scene does not limit
  double ego_max_acceleration_mps2 = 3.0;
  double truck_max_speed_mps = 25.0;
  double truck_max_acceleration_mps2 = 1.0;
  /// The truck's rear axle (its reference point) lies this share of its length ahead of its rear.
  double truck_rear_axle_share = 0.25;
  /// Thinning of the ego's trajectory: a vertex is dropped when the polyline without it stays within
  /// this distance (m) of it at its time; 0 keeps every integration step.
  double tolerance_m = 0.0;
};

/// The road network of one cell; everything in metres in the road frame. The side road joins from
/// the left (y > 0) with its centre line at `side_road_x_m`; the truck drives down its left lane.
struct JunctionLayout {
  double main_start_x_m = 0.0;   ///< start of road 1 (incoming main road)
  double junction_min_x_m = 0.0; ///< road 1 ends, the junction begins
  double junction_max_x_m = 0.0; ///< the junction ends, road 2 begins
  double main_end_x_m = 0.0;     ///< end of road 2
  double side_road_x_m = 0.0;    ///< the side road's reference line
  double side_road_start_y_m = 0.0;
  double side_road_length_m = 0.0;
  double reference_line_y_m = 0.0;  ///< the main road's reference line (the centre lane)
  int left_lanes = 0;               ///< driving lanes left of the reference line (ids 1…)
  int right_lanes = 0;              ///< driving lanes right of it (ids −1…), then the shoulder
};
[[nodiscard]] JunctionLayout junction_layout(const sim::SceneConfig& config, const sim::CellInput& cell);

/// From the ego's CG to its reference point (the rear axle's centre), backwards along its heading.
[[nodiscard]] double ego_reference_offset_m(const sim::VehicleParams& ego) noexcept;
/// From the truck's centre to its reference point (its rear axle), backwards along its heading.
[[nodiscard]] double truck_reference_offset_m(const sim::TruckConfig& truck, const ExportOptions& options) noexcept;

/// The T-junction of a cell as an OpenDRIVE 1.6 document.
[[nodiscard]] std::string opendrive_xml(const sim::SceneConfig& config, const sim::CellInput& cell);

/// The ego's executed trajectory (sim::StrategyOutcome::path) under a strategy.
struct EgoTrajectory {
  std::string strategy;
  std::vector<sim::PathPoint> path;
};

/// The path with its closed-form final stop filled in: a rollout braking straight short of the truck
/// ends in one step to where it comes to rest (sim's "stops short" test); the braking in between
/// is added at steps of `dt_s` at the constant deceleration that step implies, so that a simulator
/// interpolating the vertices brakes instead of coasting. Other paths are returned unchanged.
[[nodiscard]] std::vector<sim::PathPoint> with_final_stop(const std::vector<sim::PathPoint>& path, double dt_s);

/// The path's points that a polyline within `tolerance_m` of every dropped point (at its time)
/// needs; the first and last always. tolerance 0: all of them.
[[nodiscard]] std::vector<sim::PathPoint> thin_path(const std::vector<sim::PathPoint>& path, double tolerance_m);

/// A path ended on the frames of a simulator that steps at `dt_s` from t = 0 (esmini with
/// `--fixed_timestep`), which records the first frame at or after a trajectory's end with the speed
/// of the step before: a path that ends at rest (below kStoppedSpeed_mps) holds its last pose to one
/// frame after that one, a frame that does not move; a path that ends moving (at a contact or a
/// departure) goes on at its final velocity and yaw rate to that frame. A path that ends moving on
/// a frame is returned unchanged.
[[nodiscard]] std::vector<sim::PathPoint> ended_on_frame_grid(const std::vector<sim::PathPoint>& path, double dt_s);

/// One cell as an OpenSCENARIO 1.2 scenario referencing `road_file`; the truck follows its motion in
/// the cell as a timed trajectory; with `trajectory`, the ego follows it (ended on the frame grid,
/// ended_on_frame_grid) and the storyboard stops at its last vertex.
[[nodiscard]] std::string openscenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                                           const EgoTrajectory* trajectory, const ExportOptions& options,
                                           const std::string& road_file = kRoadFile);

/// Writes DIR/tjunction.xodr and DIR/tjunction.xosc, both or neither (core::write_files); returns
/// their paths. Throws UsageError for a cell the scene rejects or that is infeasible.
std::vector<std::filesystem::path> export_cell(const std::filesystem::path& dir, const sim::SceneConfig& config,
                                               const sim::CellInput& cell, const EgoTrajectory* trajectory,
                                               const ExportOptions& options);

/// A plan as a logical scenario: DIR/tjunction.xosc (ParameterDeclarations, positions and speeds as
/// expressions of them), DIR/tjunction_distribution.xosc (a deterministic ValueSetDistribution, one
/// ParameterValueSet per scenario) and one road network per distinct junction position in
/// DIR/roads/. Written all or none.
struct PlanExport {
  std::vector<std::filesystem::path> files;
  std::size_t scenarios = 0;
  std::size_t road_networks = 0;
};
/// Throws InputError at the scenario's row for a scenario the scene rejects or that is infeasible.
PlanExport export_plan(const std::filesystem::path& dir, const sim::SceneConfig& config,
                       const scenario::ScenarioFile& scenarios, const ExportOptions& options);

/// Names of the logical scenario's parameters, in declaration order: the cell's factors, then
/// road_network (the .xodr file) and scenario_id.
[[nodiscard]] std::vector<std::string> plan_parameter_names();

}  // namespace emrm::exchange
