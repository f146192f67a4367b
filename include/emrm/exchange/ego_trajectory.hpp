#pragma once

// The ego's executed trajectory as the vertices another simulator follows (docs/openscenario.md):
// its closed-form final stop filled in (sim::with_closed_form_stop, for a store written before
// outcomes held it), thinned to a tolerance, and ended on the simulator's frame grid.

#include <string>
#include <vector>

#include "emrm/sim/step.hpp"

namespace emrm::exchange {

/// The ego's executed trajectory (sim::StrategyOutcome::path) under a strategy.
struct EgoTrajectory {
  std::string strategy;
  std::vector<sim::PathPoint> path;
};

/// The path's points that a polyline within `tolerance_m` of every dropped point (at its time)
/// needs; the first and last always. tolerance 0: all of them.
[[nodiscard]] std::vector<sim::PathPoint> thin_path(const std::vector<sim::PathPoint>& path, double tolerance_m);

/// A path ended on the frames of a simulator that steps at `dt_s` from t = 0 (esmini with
/// `--fixed_timestep`), which records the first frame at or after a trajectory's end with the speed
/// of the step before: a path that ends at rest (below sim::kStoppedSpeed_mps) holds its last pose to one
/// frame after that one, a frame that does not move; a path that ends moving (at a contact or a
/// departure) goes on at its final velocity and yaw rate to that frame. A path that ends moving on
/// a frame is returned unchanged.
[[nodiscard]] std::vector<sim::PathPoint> ended_on_frame_grid(const std::vector<sim::PathPoint>& path, double dt_s);

}  // namespace emrm::exchange
