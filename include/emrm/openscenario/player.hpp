#pragma once

// Plays a scenario's storyboard open loop at a fixed step, as esmini does with
// `--fixed_timestep` (docs/import.md, "The player's step"), and returns every entity's trajectory
// in the OpenDRIVE world frame.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "emrm/openscenario/parameters.hpp"
#include "emrm/openscenario/scenario.hpp"

namespace emrm::openscenario {

/// An entity's reference point at one time: world position (m), heading (rad, in (-pi, pi]) and
/// speed (m/s, negative when reversing).
struct Sample {
  double t_s = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
  double speed_mps = 0.0;
};

/// Each entity's samples, by name, at t = 0, dt, 2 dt, ... (the same times for every entity).
using Trajectories = std::map<std::string, std::vector<Sample>>;

/// The entities' samples at one step, by name.
using StepStates = std::map<std::string, Sample>;

struct PlayOptions {
  double dt_s = 0.01;        ///< esmini's --fixed_timestep
  double duration_s = 10.0;  ///< the last sample is at the last step not after it
  /// Parameter values from outside: non-empty, the scenario is read again from its file with them
  /// (load_openscenario), so that every value derived from a parameter follows.
  ParameterOverrides overrides{};
  /// Called after each step with its states; true ends the play after that step.
  std::function<bool(double t_s, const StepStates& states)> stop_at{};
  /// Called when a storyboard element starts running, with the time of the step it starts in (the
  /// time before the step: the sample at that time is the last one without it).
  std::function<void(double t_s, const std::string& element)> element_started{};
};

/// Plays `scenario` from t = 0 until `duration_s`, the storyboard's StopTrigger or `stop_at`.
/// Throws InputError for what only the play finds wrong (a lane change to a lane that does not
/// exist where it starts, a position off every road), at the element that asked for it.
[[nodiscard]] Trajectories play(const Scenario& scenario, const PlayOptions& options = {});

}  // namespace emrm::openscenario
