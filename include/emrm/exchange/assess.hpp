#pragma once

// `emrm assess`: a trajectory recorded by another simulator, judged by emrm's own models
// (docs/openscenario.md, "Judging a recorded trajectory"): contact with the truck and leaving the
// drivable area, between samples too, assessed by the same functions a rollout's checks call
// (sim::truck_impact, sim::roadside_impact: the impact model, Δv, injury risks, loss level), and
// the safe state at the end (stopped, or past the truck and sim::stable_with_room_to_stop). No
// vehicle dynamics run: the recorded motion is what is judged.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "emrm/core/geometry.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::exchange {

/// emrm: columns t, x, y, psi, v (the ego's CG), optional truck_x, truck_y, truck_psi (the truck's
/// centre) and steer (road-wheel angle). esmini: the CSV esmini's dat2csv writes, entities named
/// as the export names them, reference points (rear axles) converted back to the CG and centre;
/// the CG's speed from its positions (esmini's `speed` is the rear axle's, a frame late), and no
/// wheel angle (esmini's `wheel_angle` is its own kinematic estimate, not the road-wheel angle).
enum class TrajectoryFormat { kEmrm, kEsmini };
[[nodiscard]] std::string_view format_name(TrajectoryFormat format) noexcept;

/// One sample: the ego's CG (m, rad, m/s) and, when recorded, the truck's centre.
struct TrajectorySample {
  double t_s = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;  ///< unwrapped: continuous from sample to sample
  double speed_mps = 0.0;
  double steer_rad = 0.0;  ///< 0 when not recorded
  double truck_x_m = 0.0;
  double truck_y_m = 0.0;
  double truck_yaw_rad = 0.0;
};

struct RecordedTrajectory {
  std::string file;
  std::vector<TrajectorySample> samples;  ///< at least two, strictly increasing in time
  bool has_truck = false;  ///< the truck's motion is recorded (else the scene's nominal motion)
  bool has_steer = false;  ///< the wheel angle is recorded (else the safe state does not test it)
};

/// Parses a recorded trajectory. Throws InputError at `file_name`:line:column for malformed CSV, a
/// missing column, a row of the wrong length, a value that is not a finite number, a time not
/// after the previous one (esmini: repeated frames of one time are skipped), a negative speed, or
/// fewer than two samples. `config` and `options` convert esmini's reference points.
[[nodiscard]] RecordedTrajectory parse_trajectory_csv(std::string_view text, const std::string& file_name,
                                                      TrajectoryFormat format, const sim::SceneConfig& config,
                                                      const ExportOptions& options = {});
/// Reads and parses a file (core::read_input_file, then parse_trajectory_csv).
[[nodiscard]] RecordedTrajectory read_trajectory_csv(const std::filesystem::path& path, TrajectoryFormat format,
                                                     const sim::SceneConfig& config,
                                                     const ExportOptions& options = {});

enum class SafeState { kNone, kStopped, kStabilised };
[[nodiscard]] std::string_view safe_state_name(SafeState s) noexcept;

/// A recorded trajectory's outcome, in the terms of sim::StrategyOutcome.
struct Assessment {
  bool avoided = false;
  bool contact = false;
  bool road_departure = false;
  std::optional<double> event_time_s;  ///< when the contact or the departure began
  core::Vec2 event_point_m;           ///< where: the contact's point, or the corner across the edge
  sim::ImpactAssessment impact;       ///< zeros when avoided
  sim::ImpactAssessment unmitigated;  ///< the cell's no-action reference (simulated)
  int delta_loss = 0;                 ///< unmitigated level − this level
  std::optional<double> min_ttc_s;    ///< with the scene's truck only (sim::min_ttc_along)
  SafeState safe_state = SafeState::kNone;
  double end_time_s = 0.0;          ///< the event's time, or the last sample's
  std::size_t samples_judged = 0;   ///< samples up to the event (all without one)
};

/// Judges `trajectory` in the cell. Throws UsageError for a cell the scene rejects or that is
/// infeasible (v·TTC beyond max_initial_distance_m).
[[nodiscard]] Assessment assess(const sim::SceneConfig& config, const sim::CellInput& cell,
                                const RecordedTrajectory& trajectory);

/// {"file", "format", "input", "truck", "samples", "strategy"?, "unmitigated", "outcome"}; "outcome" has the
/// keys of a strategy in `emrm simulate --json` (impact, avoided, contact, road_departure,
/// departure_speed_kph, delta_loss, min_ttc_s) plus event_time_s, event_point, safe_state, end_time_s.
[[nodiscard]] nlohmann::ordered_json to_json(const Assessment& a, const RecordedTrajectory& trajectory,
                                             TrajectoryFormat format, const sim::CellInput& cell,
                                             const std::string& strategy);
/// The same as a few lines of text.
[[nodiscard]] std::string to_text(const Assessment& a, const RecordedTrajectory& trajectory,
                                  const std::string& strategy);

}  // namespace emrm::exchange
