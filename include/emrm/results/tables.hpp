#pragma once

// The results tables of a campaign, ours beside the paper's (docs/results.md): EMRM vs
// emergency stop, by parameter level, region fractions, and every KPI as CSV. The paper's numbers
// come from one YAML file (paper_reference.hpp), never from code; the tables are core::Table.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/table.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/scenario/coverage.hpp"

namespace emrm::results {

/// EMRM vs emergency stop on `grid` (rows: the four metrics of the paper plus ours only: mean
/// impact speed over collisions and mean minimum TTC; columns: per paper column, ours and the
/// paper's, plus drift_to_accident (ours only)).
[[nodiscard]] core::Table emrm_vs_baseline_table(const std::vector<campaign::CellRecord>& records,
                                                 const PaperReference& paper, std::string_view grid);
/// The paper's by-parameter table: speed, TTC and friction on `grid`; passage on `passage_grid`
/// (or all grids when it is empty); extra rows for friction on `friction_grid` when it is given.
/// Cells read "ours / ours / ours (paper p / p / p)", as collision-avoidance rates.
[[nodiscard]] core::Table by_parameter_table(const std::vector<campaign::CellRecord>& records,
                                             const PaperReference& paper, std::string_view grid,
                                             std::string_view passage_grid, std::string_view friction_grid,
                                             const LevelCuts& cuts);
/// Region fractions per grid, with the paper's beside the grid it names, and notes on why they
/// differ (the stop boundary under `actuation`, the scene's, and under instant actuation).
[[nodiscard]] core::Table regions_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                                        const sim::ActuationConfig& actuation = {});
/// The paper's qualitative claims against ours: the highest speed at which the emergency stop
/// avoids on `grid`; avoidance below the paper's μ at its TTC (every grid); coverage (the paper's
/// only: not measured from a campaign).
[[nodiscard]] core::Table claims_table(const std::vector<campaign::CellRecord>& records, const PaperReference& paper,
                                       std::string_view grid);
/// Coverage comparison (paper Fig. "coverage comparison"): per scenario set — the plan, then the
/// baselines — its size, hazard, UCA, transition, cell, t-wise and boundary coverage and C1–C4,
/// with the paper's single figure per method beside ours.
[[nodiscard]] core::Table coverage_comparison_table(const std::vector<scenario::CoverageReport>& reports,
                                                    const PaperReference& paper);
/// Every KPI per grid × strategy × factor × level, as CSV.
[[nodiscard]] std::string kpis_csv(const std::vector<campaign::CellRecord>& records, const LevelCuts& cuts);

/// Which grids the tables read.
struct TableOptions {
  std::string grid = "fine";  ///< EMRM vs baseline, speed/TTC/friction rows
  std::string passage_grid = "passage";
  std::string friction_grid = "speed_mu";
  LevelCuts cuts;                  ///< level_cuts(scene): without it every cell counts as wide
  sim::ActuationConfig actuation;  ///< the scene's, for the regions table's notes
};

/// Writes DIR/tables/{emrm_vs_baseline,by_parameter,regions,claims}.{md,csv,tex} and DIR/tables/kpis.csv,
/// all computed first, then written all or none (core::write_files).
/// A grid named in the options that has no records is reported in the tables as having no cells.
/// Returns the files written. Throws emrm::Error when a file cannot be written.
std::vector<std::filesystem::path> write_tables(const std::filesystem::path& dir,
                                                const std::vector<campaign::CellRecord>& records,
                                                const PaperReference& paper, const TableOptions& options = {});

}  // namespace emrm::results
