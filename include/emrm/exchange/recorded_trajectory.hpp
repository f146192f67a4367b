#pragma once

// A trajectory recorded by another simulator, as `emrm assess` reads it (docs/openscenario.md,
// "Judging a recorded trajectory"): emrm's CSV or esmini's dat2csv output, the ego's CG and, when
// recorded, the truck's centre at each sample.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/exchange/openscenario.hpp"
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
  bool has_truck = false;                 ///< the truck's motion is recorded (else the scene's nominal motion)
  bool has_steer = false;                 ///< the wheel angle is recorded (else the safe state does not test it)
};

/// Parses a recorded trajectory. Throws InputError at `file_name`:line:column for malformed CSV, a
/// missing column, a row of the wrong length, a value that is not a finite number, a time not
/// after the previous one (esmini: repeated frames of one time are skipped), a speed below the
/// dither of a car at rest (core/measured.hpp: down to -0.05 m/s is read as 0), or
/// fewer than two samples. `config` and `options` convert esmini's reference points.
[[nodiscard]] RecordedTrajectory parse_trajectory_csv(std::string_view text, const std::string& file_name,
                                                      TrajectoryFormat format, const sim::SceneConfig& config,
                                                      const ExportOptions& options = {});
/// Reads and parses a file (core::read_input_file, then parse_trajectory_csv).
[[nodiscard]] RecordedTrajectory read_trajectory_csv(const std::filesystem::path& path, TrajectoryFormat format,
                                                     const sim::SceneConfig& config, const ExportOptions& options = {});

}  // namespace emrm::exchange
