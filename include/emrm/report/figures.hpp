#pragma once

// The paper's figures from a results store (docs/report.md): each figure is drawn
// by gnuplot as PNG and SVG, with the data it plots written beside it as CSV
// (DIR/NAME.png, DIR/NAME.svg, DIR/NAME.csv). Figures never recompute physics: they read records.

#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/results/profiles.hpp"
#include "emrm/safety/traceability.hpp"
#include "emrm/scenario/coverage.hpp"
#include "emrm/sim/actuation.hpp"
#include "emrm/sim/factors.hpp"

namespace emrm::report {

/// A figure as written: its files and what it shows.
struct Figure {
  std::string name;   ///< file stem, e.g. "mitigability_map"
  std::string title;  ///< a caption for the report
  std::string note;   ///< empty, or why something is missing (e.g. "no grid 'ttc_mu' in the store")
  std::filesystem::path png, svg, csv;
};

/// The grids of the four panels of the mitigability map, in panel order (a) to (d).
struct MapPanels {
  std::string coarse = "coarse";      ///< speed × TTC
  std::string fine = "fine";          ///< speed × TTC
  std::string speed_mu = "speed_mu";  ///< speed × μ
  std::string ttc_mu = "ttc_mu";      ///< TTC × μ
};

/// (1) The four-panel mitigability map: each cell a rectangle in its region's colour (G green,
/// Y yellow, O orange, R red, infeasible grey), the analytic stop boundary TTC = v/(2μg) dashed
/// (with the latency added when it is not 0). An undecided O/R cell (no avoidance found, none
/// proven impossible) carries a black cross and the key an entry for it; certified cells are
/// unmarked, and a map without undecided cells looks as if no cell had evidence. Panels whose grid
/// is missing are left out (and said in `note`); with no panel at all, no files are written and
/// `note` says why. CSV columns: panel, grid, the factors' keys (sim::scenario_factors), region,
/// evidence (witness, certificate, undecided; empty for an infeasible cell).
Figure draw_mitigability_map(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                             const std::filesystem::path& dir, const MapPanels& panels = {}, double latency_s = 0.0);

/// (1b) The harm-reduction map: the mitigability map's panels and axes, each feasible cell
/// coloured by its p_mais3_reduction (the unmitigated reference's P(MAIS3+) minus the best
/// strategy's: mitigation inside one loss level; an avoided G or Y cell counts its whole
/// unmitigated risk) on a sequential scale from 0 to the largest value, with a colour bar;
/// infeasible cells grey, the stop boundary dashed. Panels and `note` as draw_mitigability_map.
/// CSV columns: panel, grid, the factors' keys (in the table's order), region, unmitigated_p_mais3,
/// p_mais3_reduction, unmitigated_p_fatal, p_fatal_reduction (the last four empty for an
/// infeasible cell).
Figure draw_harm_reduction_map(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                               const std::filesystem::path& dir, const MapPanels& panels = {}, double latency_s = 0.0);

/// What draw_grid_maps draws.
struct GridMapOptions {
  std::vector<std::string> skip;         ///< grids drawn elsewhere (the paper map's panels)
  std::size_t max_slices_per_grid = 12;  ///< further slices are listed in a note, not drawn
  double latency_s = 0.0;                ///< of the dashed stop boundary, as draw_mitigability_map
};

/// (1d) A map of every grid of `records` but those in `options.skip`, whatever its name: the
/// mitigability map's colours, crosses and stop boundary in one panel per figure. The axes are the
/// first two factors that vary over the grid, in the order of the factor table (a grid varying one
/// factor or none gets a strip: a constant factor is its second axis);
/// a grid varying more is cut into slices, one per combination of the values of the other
/// varying factors, one figure each, in ascending order of those values. Stems: map_GRID, then
/// _FACTOR_VALUE per factor the slice is cut along (e.g. map_wet3_mu_0.5; characters other than
/// letters, digits, '.', '-' and '_' become '_'). At most `max_slices_per_grid` slices a grid are
/// drawn; then one more Figure, map_GRID_more, has no files and a note listing the slices left out.
/// Each caption names the grid, the slice and the region shares. CSV columns: slice, grid, the
/// factors' keys, region, evidence. After each slice's map comes its harm-reduction map, harm_STEM,
/// drawn as draw_harm_reduction_map draws the paper's grids.
std::vector<Figure> draw_grid_maps(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                                   const std::filesystem::path& dir, const GridMapOptions& options = {});

/// (3) Loss comparison on `grid`: collision-avoidance rate (%) and mean residual impact speed (km/h)
/// per strategy, as two bar panels. CSV: strategy, cells, collision_avoidance_rate_pct,
/// mean_impact_speed_kph.
Figure draw_loss_comparison(const std::vector<campaign::CellRecord>& records, const std::string& grid,
                            const std::filesystem::path& dir);

/// (4) Parameter sweep on `grid`: collision-avoidance rate and mitigability success (%) against
/// ego speed, one line per strategy, two panels. CSV: the ego speed's key (the scenario's
/// `factors`), strategy, cells, collision_avoidance_rate_pct, mitigability_success_pct.
Figure draw_sweep_curves(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                         const std::string& grid, const std::filesystem::path& dir);

/// A factor of a plan's ODD as the figures of a planned run group by it (estimates.json "factors"):
/// its name, unit and the label of each level (a bin "[44, 58)", a class or a constant), in level order.
struct PlanFactor {
  std::string name, unit;
  std::vector<std::string> levels;
};

/// "speed_kph (km/h)", or the name alone when the unit is empty or "1": the factor on an axis.
[[nodiscard]] std::string plan_factor_label(const PlanFactor& factor);

/// (4b) The parameter sweep of a planned run: draw_sweep_curves's panels with one point per level of
/// `factor` (levels[i] is the level of cells[i]) over the feasible scenarios in it, the bins' labels
/// as x tics. CSV: level, bin, strategy, cells, collision_avoidance_rate_pct,
/// mitigability_success_pct, one row per (bin, strategy) with a feasible scenario, bins ascending.
/// `name` is the figure's stem.
Figure draw_binned_sweep_curves(const std::vector<campaign::CellRecord>& cells, const std::vector<int>& levels,
                                const PlanFactor& factor, const std::filesystem::path& dir,
                                const std::string& name = "sweep_curves");

/// (5) Coverage comparison of `reports`, the plan's then the baselines' (as coverage.json holds
/// them: scenario::read_coverage_json): hazard, UCA and cell coverage (%) per method as grouped
/// bars. CSV: method, scenarios, hazard_pct, uca_pct, transition_pct, cell_pct, twise_pct. With no
/// report, no files are written and `note` says why.
Figure draw_coverage_comparison(const std::vector<scenario::CoverageReport>& reports, const std::filesystem::path& dir);

/// (7) The traceability matrix as a chart: UCAs (rows) × hazards (columns), each entry the number
/// of scenarios that trace to it (or a mark when the link exists and no scenario is known).
/// CSV: uca, hazard, losses, scenarios.
Figure draw_traceability(const std::vector<safety::TraceRow>& rows, const std::filesystem::path& dir);

/// (1c) The headline grid under each actuation profile side by side (docs/actuation.md, "Profiles
/// side by side"): the mitigability map's colours and crosses, one speed × TTC panel per profile
/// (records[i] are runs[i]'s; at most four, in the 2×2 layout), each with its own dashed stop
/// boundary. CSV columns: panel, profile, grid, the factors' keys, region, evidence.
Figure draw_profile_maps(const std::vector<results::ProfileRun>& runs,
                         const std::vector<std::vector<campaign::CellRecord>>& records, const sim::FactorTable& factors,
                         const std::string& grid, const std::filesystem::path& dir);

/// The brakes' sensitivity (docs/actuation.md, "Sensitivity"): G of `grid` against the brake dead
/// time (0–0.6 s) and the peak deceleration (10–4 m/s²), one changed at a time from `actuation`,
/// from the stop's closed form. A note instead when the grid has no feasible cell.
Figure draw_brake_sensitivity(const std::vector<campaign::CellRecord>& records, const std::string& grid,
                              const sim::ActuationConfig& actuation, const std::filesystem::path& dir);

}  // namespace emrm::report
