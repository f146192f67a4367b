#pragma once

// `emrm calibrate` (docs/actuation.md, "Calibration"): fits actuation parameters to measured brake
// tests with NLopt, states a 95 % profile-likelihood interval for each, and says when the data
// cannot tell the parameters apart.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/core/error.hpp"
#include "emrm/sim/actuation.hpp"

namespace emrm::calibration {

/// One straight-line stop: from the brake command at `speed_kph` on friction `mu` to standstill.
struct StopRecord {
  double speed_kph = 0.0;
  double mu = 1.0;
  double stop_distance_m = 0.0;
  double time_to_stop_s = -1.0;  ///< < 0: not measured
};

/// One speed sample of a brake application; t = 0 is the brake command.
struct TraceSample {
  std::string run;
  double t_s = 0.0;
  double speed_mps = 0.0;
};

/// Reads `speed_kph, mu, stop_distance_m[, time_to_stop_s]` (any column order, a header row).
/// Throws InputError at file:line:column for a missing column, a field that is not a finite
/// number, a speed or distance <= 0, mu outside (0, 2], or no rows.
[[nodiscard]] std::vector<StopRecord> read_stops(const std::filesystem::path& file);
/// Reads `run, t_s, speed_mps`; the same errors, and a run whose times do not increase.
[[nodiscard]] std::vector<TraceSample> read_decel_trace(const std::filesystem::path& file);

/// The actuation parameters a brake test can identify, by name.
[[nodiscard]] std::vector<std::string> calibratable_parameters();

struct FitBounds {
  double low = 0.0;
  double high = 0.0;
};

struct FittedValue {
  double value = 0.0;
  double ci_low = 0.0;  ///< 95 % profile-likelihood interval
  double ci_high = 0.0;
  bool identifiable = true;  ///< false: the interval reaches both bounds (a flat profile)
};

struct CalibrationResult {
  std::map<std::string, FittedValue> fitted;
  sim::ActuationConfig actuation;  ///< the starting actuation with the fitted values
  double residual_rms = 0.0;       ///< in the data's unit (m for stops, m/s for a trace, points for regions)
  std::size_t observations = 0;
  bool converged = false;
  std::vector<std::string> warnings;  ///< not identifiable parameters, strong correlations, bounds hit
};

struct CalibrationRequest {
  std::vector<std::string> fit;             ///< parameter names
  std::map<std::string, FitBounds> bounds;  ///< overrides of the defaults
  sim::ActuationConfig start;               ///< the scene's (or profile's) actuation
};

/// The default search bounds of a parameter.
[[nodiscard]] FitBounds default_bounds(const std::string& name);

/// Fits to stops (the closed-form stopping distance of sim::ActuationConfig, and the stopping time
/// where given). Throws UsageError for an unknown or unidentifiable-by-stops parameter name, or
/// bounds that are empty or outside the parameter's domain.
[[nodiscard]] CalibrationResult calibrate_stops(const std::vector<StopRecord>& stops,
                                                const CalibrationRequest& request);
/// Fits to speed traces (dead time, then the ramp, then the full deceleration; each run's initial
/// speed a nuisance parameter).
[[nodiscard]] CalibrationResult calibrate_trace(const std::vector<TraceSample>& trace,
                                                const CalibrationRequest& request);

/// Target region fractions of one campaign grid (`--regions`): paper_reference.yaml's `fine_grid`
/// mapping, or the same keys at a file's top level (`grid`, `regions_pct`, optional `feasible_cells`).
struct RegionTarget {
  std::string file;
  std::string grid;
  SourceLocation grid_at;
  std::map<std::string, double> pct;  ///< G, Y, O, R (any of them), percent of the feasible cells
};
/// Reads a target. Throws InputError at file:line:column for malformed YAML, an unknown key or
/// region, a percentage outside [0, 100], all four not summing to 100 ± 1, or a missing field.
[[nodiscard]] RegionTarget read_region_target(const std::filesystem::path& file);

struct RegionCalibration {
  CalibrationResult calibration;  ///< residual_rms in percentage points
  std::string grid;
  std::size_t feasible_cells = 0;
  std::size_t sweeps = 0;                    ///< simulations of the grid (0 for a fit to G alone)
  std::map<std::string, double> target_pct;  ///< the matched fractions
  std::map<std::string, double> fitted_pct;  ///< at the fitted values: G, and Y/O/R when simulated
};

/// Fits to a grid's region fractions: χ² over the `match`ed fractions (all the target gives when
/// empty), each with the binomial variance of a fraction of the grid's feasible cells; G from the
/// stop's closed form, Y/O/R by simulating the cells the stop cannot save (cached per parameter
/// vector). A global search (DIRECT-L), since fractions are counts. `threads` 0 = all cores.
/// Throws InputError at the target's grid when the campaign has no such grid, UsageError for a
/// `match` the target does not give.
[[nodiscard]] RegionCalibration calibrate_regions(const campaign::Campaign& campaign, const RegionTarget& target,
                                                  const std::vector<std::string>& match,
                                                  const CalibrationRequest& request, int threads = 0);

/// The speed `t_s` after a brake command from `v0` (closed form; 0 once stopped).
[[nodiscard]] double braked_speed_mps(const sim::ActuationConfig& a, double mu, double v0, double t_s);

/// The profile YAML (`description:` and an `actuation:` overlay) with `command` in its header.
[[nodiscard]] std::string profile_yaml(const CalibrationResult& result, const std::string& command,
                                       const std::string& description = "calibrated actuation");

/// What `emrm calibrate --json` prints: {fitted: {NAME: {value, ci_low, ci_high, identifiable}},
/// residual_rms, observations, converged, warnings}, and with `regions` (a fit to a map) the grid,
/// its feasible cells, the sweeps and the fitted beside the target fractions.
[[nodiscard]] nlohmann::ordered_json to_json(const CalibrationResult& result, const RegionCalibration* regions);

/// What `emrm calibrate` prints: the fit's source and residual (in `unit`), each parameter with its
/// 95 % interval, the fractions against their targets (with `regions`), the warnings, and where the
/// profile went (`output`) or that the fit did not converge.
[[nodiscard]] std::string to_text(const CalibrationResult& result, const RegionCalibration* regions,
                                  const std::string& source, std::string_view unit, const std::string& output);

}  // namespace emrm::calibration
