#pragma once

// The trajectory-tree figure of one cell (the paper's "RRT validation scenarios"): the road, the
// truck at t = 0 and when the ego's path ends, the green goal tree, the orange fail-safe branches,
// and the executed path coloured by speed, one panel per strategy.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::report {

/// Draws `result` (simulated with trees kept) to `output` (.png or .svg) with gnuplot. Throws
/// UsageError for an unsupported extension and emrm::Error if gnuplot fails.
void draw_cell_figure(const sim::CellResult& result, const sim::SceneConfig& config,
                      const std::filesystem::path& output);

/// (2) The trajectory-tree grid of the paper's twelve RRT validation scenarios, from the stored
/// paths and trees of `grid` (a grid swept with `keep_trees: true`): four panels a row, in the
/// grid's order (rows of the shipped example: passage width, friction, speed). Each panel shows
/// the road, the truck at t = 0 (dashed) and when the path ends, the green goal tree and orange
/// fail-safe tree of the RRT strategy emrm chose (of dodge when it chose the emergency stop), and
/// emrm's executed path coloured by speed with one colour bar. CSV: panel, cell_index, the keys of
/// the ego speed, TTC, friction and passage (scenario_factors), region, outcome, kind (path, goal, failsafe), edge,
/// t_s, x_m, y_m, speed_mps. A grid without stored trajectories gives no files and a note.
Figure draw_trajectory_grid(const std::vector<campaign::CellRecord>& records, const sim::SceneConfig& config,
                            const std::string& grid, const std::filesystem::path& dir);

}  // namespace emrm::report
