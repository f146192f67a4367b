#pragma once

// The trajectory-tree figure of one cell (the paper's "RRT validation scenarios"): the road, the
// truck at t = 0 and when the ego's path ends, the green goal tree, the orange fail-safe branches,
// and the executed path coloured by speed, one panel per strategy.

#include <filesystem>

#include "emrm/sim/simulate.hpp"

namespace emrm::report {

/// Draws `result` (simulated with trees kept) to `output` (.png or .svg) with gnuplot. Throws
/// UsageError for an unsupported extension and emrm::Error if gnuplot fails.
void draw_cell_figure(const sim::CellResult& result, const sim::SceneConfig& config,
                      const std::filesystem::path& output);

}  // namespace emrm::report
