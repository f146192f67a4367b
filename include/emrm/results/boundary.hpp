#pragma once

// Boundary curves of a results store (docs/boundary.md): for each line of a grid — one speed and one
// combination of μ, passage width and truck speed, TTC varying — the lowest TTC level from which
// every cell above is in a region (or avoided by a strategy), beside the analytic stop boundary of
// the scene's actuators. Pure functions of the stored records; no simulation.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/sim/actuation.hpp"

namespace emrm::results {

/// The bracket of one line's threshold, from its cells' (TTC, passes) pairs.
struct TtcThreshold {
  std::optional<double> below;  ///< the highest TTC level that fails; none when every level passes
  std::optional<double> at;     ///< t*: the lowest level from which every level passes; none when the top fails
  std::size_t exceptions = 0;   ///< cells below t* that pass (all passing cells when there is no t*)
  std::size_t cells = 0;        ///< cells given
};

/// The threshold of `cells` (TTC, passes): a level passes when every cell at it passes; t* is the
/// lowest level with every level at or above it passing. Cells share a level only when their TTCs
/// are equal (a grid's values are rounded to 1e-9 when it is loaded, so equal values are equal).
[[nodiscard]] TtcThreshold ttc_threshold(std::vector<std::pair<double, bool>> cells);

/// The rank of a region: G 0, Y 1, O 2, R 3. Throws emrm::Error for kInfeasible.
[[nodiscard]] int region_rank(sim::Region region);

/// The region boundaries and their highest rank: stop (G, 0), avoid (G or Y, 1), mitigate (G, Y or
/// O, 2). A strategy's boundary is named "strategy:NAME".
struct RegionBoundary {
  std::string_view name;
  int max_rank;
};
inline constexpr RegionBoundary kRegionBoundaries[] = {{"stop", 0}, {"avoid", 1}, {"mitigate", 2}};

/// One row of boundary.csv: the threshold of one boundary on one line of a grid.
struct BoundaryRow {
  std::string grid;
  std::vector<double> held;  ///< the slice's held factors (BoundarySlice::held)
  std::string boundary;      ///< stop, avoid, mitigate or strategy:NAME
  double speed_kph = 0.0;
  TtcThreshold threshold;  ///< threshold.cells: the cells of the line that contributed (cells_used)
};

/// One row of analytic_stop.csv: the TTC at which full braking through the actuators stops exactly
/// at the truck.
struct AnalyticStopRow {
  std::string grid;
  double mu = 0.0, speed_kph = 0.0;
  double stopping_distance_m = 0.0;  ///< sim::ActuationConfig::stopping_distance_m, perception included
  double ttc_s = 0.0;                ///< stopping_distance_m / v
};

/// A grid left out: fewer than two TTC levels, so no threshold can be bracketed.
struct SkippedGrid {
  std::string grid;
  std::size_t ttc_levels = 0;
};

/// The cells of a grid that share every factor but the ego's speed and the TTC (μ first, then the
/// scenario's own: the held factors): one figure.
struct BoundarySlice {
  std::string grid;
  std::vector<double> held;  ///< in the factor table's order, from μ on
  [[nodiscard]] bool holds(const campaign::CellRecord& cell) const noexcept;
};

/// Every boundary of a store.
struct BoundaryReport {
  /// The actuators of the analytic stop boundary; none for a family where it does not hold
  /// (sim::stop_boundary_applies): then there are no analytic rows and no line.
  std::optional<sim::ActuationConfig> actuation;
  sim::FactorTable factors;               ///< the scenario's: the columns' keys
  std::vector<std::string> grids;         ///< grids with boundaries, in store order
  std::vector<SkippedGrid> skipped;       ///< grids with fewer than two TTC levels
  std::vector<std::string> boundaries;    ///< stop, avoid, mitigate, then strategy:NAME per stored strategy
  std::vector<BoundarySlice> slices;      ///< per grid, held factors ascending
  std::size_t lines = 0;                  ///< (grid, held factors, speed) with a cell
  std::vector<BoundaryRow> rows;          ///< per slice, boundary (in `boundaries` order), speed ascending
  std::vector<AnalyticStopRow> analytic;  ///< per grid, μ, speed ascending

  /// Rows whose line is not monotone (exceptions > 0).
  [[nodiscard]] std::size_t non_monotone() const noexcept;
};

/// The boundaries of every grid of `records` with at least two TTC levels, from its feasible cells
/// (a strategy's from the feasible cells with an outcome of that strategy: a cell stored without
/// outcomes counts only for the region boundaries). Throws emrm::Error naming the cell when a
/// feasible cell's region is not G, Y, O or R (a damaged store).
[[nodiscard]] BoundaryReport compute_boundaries(const std::vector<campaign::CellRecord>& records,
                                                const sim::FactorTable& factors,
                                                const std::optional<sim::ActuationConfig>& actuation);

/// boundary.csv: grid, the held factors' keys (μ on), boundary, the ego speed's key, ttc_below_s,
/// ttc_at_s, exceptions, cells_used (an absent TTC is an empty field).
[[nodiscard]] std::string boundary_csv(const BoundaryReport& report);
/// analytic_stop.csv: grid, the friction's key, the ego speed's key, stopping_distance_m, the TTC's key.
[[nodiscard]] std::string analytic_stop_csv(const BoundaryReport& report);

/// Writes OUT_DIR/boundary.csv and OUT_DIR/analytic_stop.csv together (core::write_files) and
/// returns their paths. Throws emrm::Error when a file cannot be written (then neither is).
std::vector<std::filesystem::path> write_boundary_files(const std::filesystem::path& out_dir,
                                                        const BoundaryReport& report);

/// A few lines for a terminal: the grids (and those skipped, with why), the lines, the boundaries
/// written and the non-monotone ones.
[[nodiscard]] std::string summary(const BoundaryReport& report);

}  // namespace emrm::results
