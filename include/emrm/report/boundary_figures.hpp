#pragma once

// The figures of `emrm boundary` (docs/boundary.md): the boundary curves of results::BoundaryReport
// over the region map they were read from, one figure per grid and combination of the other factors.

#include <cstddef>
#include <filesystem>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/results/boundary.hpp"

namespace emrm::report {

struct BoundaryFigureOptions {
  std::size_t max_figures = 24;  ///< slices beyond are listed in a note, not drawn
};

/// One figure per slice of `report` (a grid and one combination of μ, passage width and truck
/// speed), in the report's order, at most `options.max_figures`: the slice's cells of `records` as
/// a speed × TTC map in the mitigability map's colours; over them each region boundary (stop, avoid,
/// mitigate) and each strategy's as a step line, one step per speed, drawn between the highest
/// failing TTC level and t* (half a TTC step below t* when every level passes; a speed without t*
/// leaves a gap); a circle on each step whose line is not monotone; the analytic stop
/// boundary through report.actuation, dashed, on top. Stems: boundary_GRID, then _KEY_VALUE for
/// each factor after speed and TTC that varies over the grid. CSV columns: series (a
/// boundary, or analytic_stop), the ego speed's key, ttc_below_s, ttc_at_s, drawn_ttc_s, exceptions. When
/// slices are left out, one more Figure, boundary_more, has no files and a note listing them.
/// Throws as render_png_and_svg (gnuplot missing or failing).
std::vector<Figure> draw_boundary_figures(const results::BoundaryReport& report,
                                          const std::vector<campaign::CellRecord>& records,
                                          const std::filesystem::path& dir, const BoundaryFigureOptions& options = {});

}  // namespace emrm::report
