#pragma once

// The layout of a results folder (docs/results.md, "The results folder"): every path in it, named
// once, for the commands that write it (campaign::sweep, run, verify, diagnose, reproduce, report)
// and the report that reads it. The names of the files a lower module writes are that module's
// (the store and exports: campaign; a plan folder: scenario::PlanDir; the safety analysis: safety);
// the rest are named here. In `results` rather than `workflow` because `report`, below `workflow`,
// reads the folder too (docs/decisions.md, "Structure of the library").

#include <filesystem>
#include <string>

#include "emrm/scenario/plan_io.hpp"

namespace emrm::results {

/// A results folder: what `emrm sweep -o DIR` writes, and what `run`, `verify`, `diagnose`,
/// `reproduce` and `report` add to it. Paths only: nothing is checked or created. A folder built
/// from an empty root gives the paths relative to the folder (ResultsDir{}.store() is
/// "results.sqlite").
class ResultsDir {
 public:
  explicit ResultsDir(std::filesystem::path root = {});
  [[nodiscard]] const std::filesystem::path& root() const noexcept { return root_; }

  // A sweep's (campaign::sweep: every command that simulates writes these).
  [[nodiscard]] std::filesystem::path store() const;        ///< results.sqlite
  [[nodiscard]] std::filesystem::path regions_csv() const;  ///< regions.csv
  [[nodiscard]] std::filesystem::path cells_csv() const;    ///< cells.csv
  [[nodiscard]] std::filesystem::path cells_json() const;   ///< cells.json

  // A planned run's (`emrm run -o DIR`, workflow::run_scenarios; reproduce's plan_results/).
  [[nodiscard]] std::filesystem::path outcomes_csv() const;    ///< outcomes.csv, a row per scenario
  [[nodiscard]] std::filesystem::path estimates_csv() const;   ///< estimates.csv, a row per cell
  [[nodiscard]] std::filesystem::path estimates_json() const;  ///< estimates.json, Ŝ(A) and the plan's location
  /// traceability.csv (with traceability.md): the matrix with the run's scenarios, when the plan
  /// names a safety case.
  [[nodiscard]] std::filesystem::path traceability_csv() const;
  /// coverage.json of a plan written into this folder itself (`emrm plan -o DIR`, then a run there).
  [[nodiscard]] std::filesystem::path coverage_json() const;

  // `emrm verify`'s and `emrm diagnose`'s.
  [[nodiscard]] std::filesystem::path verify_json() const;       ///< verify.json
  [[nodiscard]] std::filesystem::path diagnostics_json() const;  ///< diagnostics.json
  /// fsm/: the FSM diagrams coloured by the campaign (diagnose), the FSMs' checks (reproduce).
  [[nodiscard]] std::filesystem::path fsm_dir() const;

  // `emrm reproduce`'s.
  /// analysis/: the safety case's analysis, as `emrm analyze -o` writes it (safety::write_analysis).
  [[nodiscard]] std::filesystem::path analysis_dir() const;
  [[nodiscard]] std::filesystem::path findings_json() const;              ///< analysis/findings.json
  [[nodiscard]] std::filesystem::path analysis_traceability_csv() const;  ///< analysis/traceability.csv
  /// tables/: each table as NAME.md, NAME.csv and NAME.tex (core::write_table), and kpis.csv.
  [[nodiscard]] std::filesystem::path tables_dir() const;
  [[nodiscard]] std::filesystem::path table_csv(const std::string& name) const;  ///< tables/NAME.csv
  [[nodiscard]] std::filesystem::path table_md(const std::string& name) const;   ///< tables/NAME.md
  [[nodiscard]] std::filesystem::path kpis_csv() const;                          ///< tables/kpis.csv
  /// profiles/: the headline grid under each actuation profile (workflow::sweep_profiles).
  [[nodiscard]] std::filesystem::path profiles_dir() const;
  [[nodiscard]] std::filesystem::path profile_index_json() const;  ///< profiles/index.json
  /// profiles/NAME/: a results folder of its own.
  [[nodiscard]] ResultsDir profile(const std::string& name) const;
  /// plan/: the minimum scenario set, as `emrm plan -o` writes it.
  [[nodiscard]] scenario::PlanDir plan() const;
  /// plan_results/: its run, as `emrm run -o` writes it (a results folder of its own).
  [[nodiscard]] ResultsDir plan_results() const;

  // `emrm report`'s.
  [[nodiscard]] std::filesystem::path figures_dir() const;  ///< figures/: every figure as PNG, SVG and CSV
  [[nodiscard]] std::filesystem::path report_html() const;  ///< report.html

 private:
  std::filesystem::path root_;
};

}  // namespace emrm::results
