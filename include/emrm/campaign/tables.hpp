#pragma once

// The results tables of a campaign, ours beside the paper's (DESIGN.md §11, §12): EMRM vs
// emergency stop, by parameter level, region fractions, and every KPI as CSV. The paper's numbers
// come from one YAML file (examples/tjunction/paper_reference.yaml), never from code.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/aggregate.hpp"
#include "emrm/campaign/records.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/scenario/coverage.hpp"

namespace emrm::campaign {

// ---- the paper's numbers -------------------------------------------------------------------

struct PaperRegions {
  double g = 0.0, y = 0.0, o = 0.0, r = 0.0;  ///< percent of the feasible cells
  template <class A>
  void serialize(A& a) {
    a.required("G", g);
    a.required("Y", y);
    a.required("O", o);
    a.required("R", r);
  }
};

struct PaperFineGrid {
  std::string grid = "fine";
  int feasible_cells = 0;
  PaperRegions regions_pct;
  template <class A>
  void serialize(A& a) {
    a.required("grid", grid);
    a.required("feasible_cells", feasible_cells);
    a.required("regions_pct", regions_pct);
  }
};

/// One column of the paper's EMRM-vs-baseline table and the strategy of ours it is compared with.
struct PaperBaselineColumn {
  std::string label;
  std::string strategy;
  double collision_avoidance_rate_pct = 0.0;
  double mean_residual_impact_speed_kph = 0.0;
  double mitigability_success_pct = 0.0;
  double delta_loss = 0.0;
  SourceLocation where;
  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("label", label);
    a.required("strategy", strategy);
    a.required("collision_avoidance_rate_pct", collision_avoidance_rate_pct);
    a.required("mean_residual_impact_speed_kph", mean_residual_impact_speed_kph);
    a.required("mitigability_success_pct", mitigability_success_pct);
    a.required("delta_loss", delta_loss);
  }
};

struct PaperBaseline {
  std::string grid = "fine";
  int cells = 0;
  std::vector<PaperBaselineColumn> columns;
  template <class A>
  void serialize(A& a) {
    a.required("grid", grid);
    a.required("cells", cells);
    a.required("columns", columns);
  }
};

/// Per-level values of one row of the by-parameter table, one list per strategy column.
struct PaperLevelValues {
  std::vector<double> dodge, drift_to_avoid, drift_to_accident, emergency_stop;
  template <class A>
  void serialize(A& a) {
    a.required("dodge", dodge);
    a.required("drift_to_avoid", drift_to_avoid);
    a.required("drift_to_accident", drift_to_accident);
    a.required("emergency_stop", emergency_stop);
  }
  /// The list of a strategy column, or nullptr for another name.
  [[nodiscard]] const std::vector<double>* of(std::string_view strategy) const;
};

struct PaperByParameterRow {
  std::string factor;  ///< speed, ttc, friction or passage
  std::string label;
  std::vector<std::string> levels;  ///< level names of that factor (aggregate.hpp level_names)
  PaperLevelValues values;
  std::vector<int> tests;  ///< one per level, or one total
  SourceLocation where;
  template <class A>
  void serialize(A& a) {
    a.location(where);
    a.required("factor", factor);
    a.required("label", label);
    a.required("levels", levels);
    a.required("values", values);
    a.required("tests", tests);
  }
};

struct PaperByParameter {
  std::vector<std::string> strategies;
  std::vector<PaperByParameterRow> rows;
  template <class A>
  void serialize(A& a) {
    a.required("strategies", strategies);
    a.required("rows", rows);
  }
};

struct PaperCoverage {
  double framework = 0.0, hara_only = 0.0, stpa_only = 0.0, manual = 0.0;
  template <class A>
  void serialize(A& a) {
    a.required("framework", framework);
    a.required("hara_only", hara_only);
    a.required("stpa_only", stpa_only);
    a.required("manual", manual);
  }
};

struct PaperClaims {
  double emergency_stop_never_avoids_above_kph = 0.0;
  double no_avoidance_below_mu = 0.0;
  double no_avoidance_below_mu_at_ttc_s = 0.0;
  PaperCoverage coverage_pct;
  template <class A>
  void serialize(A& a) {
    a.required("emergency_stop_never_avoids_above_kph", emergency_stop_never_avoids_above_kph);
    a.required("no_avoidance_below_mu", no_avoidance_below_mu);
    a.required("no_avoidance_below_mu_at_ttc_s", no_avoidance_below_mu_at_ttc_s);
    a.required("coverage_pct", coverage_pct);
  }
};

/// Every number of the paper's evaluation that we show beside ours.
struct PaperReference {
  std::string file;
  int version = 1;
  std::string source;
  PaperFineGrid fine_grid;
  PaperBaseline emrm_vs_baseline;
  PaperByParameter by_parameter;
  PaperClaims claims;
  template <class A>
  void serialize(A& a) {
    a.required("version", version);
    a.optional("source", source);
    a.required("fine_grid", fine_grid);
    a.required("emrm_vs_baseline", emrm_vs_baseline);
    a.required("by_parameter", by_parameter);
    a.required("claims", claims);
  }
  /// The by-parameter row of a factor, if the paper has one.
  [[nodiscard]] const PaperByParameterRow* by_parameter_row(std::string_view factor) const;
};

/// Loads the paper's reference numbers. Throws InputError (file:line:column) for an unreadable or
/// malformed file, a version other than 1, a missing or unknown field, a percentage outside
/// [0, 100], a negative count, an unknown factor or level, or a value list whose length is not
/// the number of levels (`tests` may also be a single total).
[[nodiscard]] PaperReference load_paper_reference(const std::filesystem::path& path);
[[nodiscard]] PaperReference parse_paper_reference(const std::string& text, const std::string& file_name);

// ---- tables --------------------------------------------------------------------------------

/// A table with its title and a closing paragraph (why ours and the paper's differ).
struct Table {
  std::string title;
  core::Row header;
  std::vector<core::Row> rows;
  std::vector<std::string> notes;  ///< paragraphs after the table
};

/// "# title", the Markdown table, then the notes as paragraphs.
[[nodiscard]] std::string to_markdown(const Table& table);
/// Header and rows only (RFC 4180).
[[nodiscard]] std::string to_csv(const Table& table);
/// A plain `tabular` (one l column then c columns, \hline rules) with every cell escaped, preceded
/// by the title as a comment; notes are not included.
[[nodiscard]] std::string to_latex(const Table& table);
/// Escapes LaTeX's special characters (\ { } $ & # ^ _ % ~) so the text prints as written.
[[nodiscard]] std::string latex_escape(std::string_view text);

/// A number for a table: `decimals` places, "—" for NaN.
[[nodiscard]] std::string format_number(double value, int decimals);

/// EMRM vs emergency stop on `grid` (rows: the four metrics of the paper plus ours only: mean
/// impact speed over collisions and mean minimum TTC; columns: per paper column, ours and the
/// paper's, plus drift_to_accident (ours only)).
[[nodiscard]] Table emrm_vs_baseline_table(const std::vector<CellRecord>& records,
                                           const PaperReference& paper, std::string_view grid);
/// The paper's by-parameter table: speed, TTC and friction on `grid`; passage on `passage_grid`
/// (or all grids when it is empty); extra rows for friction on `friction_grid` when it is given.
/// Cells read "ours / ours / ours (paper p / p / p)", as collision-avoidance rates.
[[nodiscard]] Table by_parameter_table(const std::vector<CellRecord>& records, const PaperReference& paper,
                                       std::string_view grid, std::string_view passage_grid,
                                       std::string_view friction_grid, const LevelCuts& cuts = {});
/// Region fractions per grid, with the paper's beside the grid it names.
[[nodiscard]] Table regions_table(const std::vector<CellRecord>& records, const PaperReference& paper);
/// The paper's qualitative claims against ours: the highest speed at which the emergency stop
/// avoids on `grid`; avoidance below the paper's μ at its TTC (every grid); coverage (the paper's
/// only: not measured from a campaign).
[[nodiscard]] Table claims_table(const std::vector<CellRecord>& records, const PaperReference& paper,
                                 std::string_view grid);
/// Coverage comparison (paper Fig. "coverage comparison"): per scenario set — the plan, then the
/// baselines — its size, hazard, UCA, transition, cell, t-wise and boundary coverage and C1–C4,
/// with the paper's single figure per method beside ours.
[[nodiscard]] Table coverage_comparison_table(const std::vector<scenario::CoverageReport>& reports,
                                              const PaperReference& paper);
/// Every KPI per grid × strategy × factor × level, as CSV.
[[nodiscard]] std::string kpis_csv(const std::vector<CellRecord>& records, const LevelCuts& cuts = {});

/// Which grids the tables read.
struct TableOptions {
  std::string grid = "fine";  ///< EMRM vs baseline, speed/TTC/friction rows
  std::string passage_grid = "passage";
  std::string friction_grid = "speed_mu";
  LevelCuts cuts;
};

/// Writes TABLES_DIR/STEM.md, .csv and .tex; returns the files written.
std::vector<std::filesystem::path> write_table(const std::filesystem::path& tables_dir, const std::string& stem,
                                               const Table& table);

/// Writes DIR/tables/{emrm_vs_baseline,by_parameter,regions,claims}.{md,csv,tex} and DIR/tables/kpis.csv.
/// A grid named in the options that has no records is reported in the tables as having no cells.
/// Returns the files written. Throws emrm::Error when a file cannot be written.
std::vector<std::filesystem::path> write_tables(const std::filesystem::path& dir,
                                                const std::vector<CellRecord>& records,
                                                const PaperReference& paper,
                                                const TableOptions& options = {});

}  // namespace emrm::campaign
