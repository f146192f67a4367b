#pragma once

// OpenSCENARIO XML 1.2 export of a scenario cell (docs/openscenario.md): the ego and the truck with
// their dimensions, masses and performance, the truck's crossing and braking, the road friction,
// and the ego's executed trajectory (ego_trajectory.hpp) as a timed FollowTrajectoryAction, beside
// the cell's OpenDRIVE road network (opendrive.hpp). Coordinates are emrm's road frame (x along the
// main road, y to the left, the ego's front bumper at x = 0 when the hazard appears). A plan as a
// logical scenario: plan_export.hpp.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/exchange/ego_trajectory.hpp"
#include "emrm/exchange/opendrive.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

/// Names every export uses (docs/openscenario.md, "Names").
inline constexpr const char* kEgoEntity = "Ego";
inline constexpr const char* kTruckEntity = "Truck";
inline constexpr const char* kRoadFile = "tjunction.xodr";
inline constexpr const char* kScenarioFile = "tjunction.xosc";
inline constexpr const char* kDistributionFile = "tjunction_distribution.xosc";
inline constexpr const char* kRoadsFolder = "roads";

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

/// From the ego's CG to its reference point (the rear axle's centre), backwards along its heading.
[[nodiscard]] double ego_reference_offset_m(const sim::VehicleParams& ego) noexcept;
/// From the truck's centre to its reference point (its rear axle), backwards along its heading.
[[nodiscard]] double truck_reference_offset_m(const sim::TruckConfig& truck, const ExportOptions& options) noexcept;

/// The vertices the ego's trajectory is written with: the final stop filled in
/// (sim::with_closed_form_stop), thinned to options.tolerance_m (thin_path), ended on the frame grid
/// (ended_on_frame_grid).
[[nodiscard]] std::vector<sim::PathPoint> ego_vertices(const sim::SceneConfig& config, const EgoTrajectory& trajectory,
                                                       const ExportOptions& options);

/// One cell as an OpenSCENARIO 1.2 scenario referencing `road_file`; the truck (in a family other
/// than the T-junction: every actor) follows its motion in the cell as a timed trajectory; with
/// `trajectory`, the ego follows it (ended on the frame grid, ended_on_frame_grid) and the
/// storyboard stops at its last vertex.
[[nodiscard]] std::string openscenario_xml(const sim::SceneConfig& config, const sim::CellInput& cell,
                                           const EgoTrajectory* trajectory, const ExportOptions& options,
                                           const std::string& road_file = kRoadFile);

/// The files a cell's export writes: tjunction.xodr and tjunction.xosc for the T-junction, else
/// FAMILY.xodr (its straight road, straight_road_xml) and FAMILY.xosc.
[[nodiscard]] std::string road_file_of(const sim::SceneConfig& config);
[[nodiscard]] std::string scenario_file_of(const sim::SceneConfig& config);

/// Writes the road and the scenario (road_file_of, scenario_file_of) into DIR, both or neither
/// (core::write_files); returns their paths. Throws UsageError for a cell the scene rejects or that
/// is infeasible.
std::vector<std::filesystem::path> export_cell(const std::filesystem::path& dir, const sim::SceneConfig& config,
                                               const sim::CellInput& cell, const EgoTrajectory* trajectory,
                                               const ExportOptions& options);

}  // namespace emrm::exchange
