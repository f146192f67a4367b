// The layout of a results folder (results_dir.hpp): the names of the files and folders that no
// lower module writes, and the others' names taken from their writers.

#include "emrm/results/results_dir.hpp"

#include <utility>

#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/safety/analysis.hpp"
#include "emrm/safety/traceability.hpp"

namespace emrm::results {

namespace fs = std::filesystem;

ResultsDir::ResultsDir(fs::path root) : root_(std::move(root)) {}

fs::path ResultsDir::store() const { return root_ / campaign::kStoreFile; }
fs::path ResultsDir::regions_csv() const { return root_ / campaign::kRegionsCsv; }
fs::path ResultsDir::cells_csv() const { return root_ / campaign::kCellsCsv; }
fs::path ResultsDir::cells_json() const { return root_ / campaign::kCellsJson; }

fs::path ResultsDir::outcomes_csv() const { return root_ / "outcomes.csv"; }
fs::path ResultsDir::estimates_csv() const { return root_ / "estimates.csv"; }
fs::path ResultsDir::estimates_json() const { return root_ / "estimates.json"; }
fs::path ResultsDir::traceability_csv() const { return root_ / safety::kTraceabilityCsv; }
fs::path ResultsDir::coverage_json() const { return scenario::PlanDir(root_).coverage_json(); }

fs::path ResultsDir::verify_json() const { return root_ / "verify.json"; }
fs::path ResultsDir::diagnostics_json() const { return root_ / "diagnostics.json"; }
fs::path ResultsDir::fsm_dir() const { return root_ / "fsm"; }

fs::path ResultsDir::analysis_dir() const { return root_ / "analysis"; }
fs::path ResultsDir::findings_json() const { return analysis_dir() / safety::kFindingsJson; }
fs::path ResultsDir::analysis_traceability_csv() const { return analysis_dir() / safety::kTraceabilityCsv; }
fs::path ResultsDir::tables_dir() const { return root_ / "tables"; }
fs::path ResultsDir::table_csv(const std::string& name) const { return tables_dir() / (name + ".csv"); }
fs::path ResultsDir::table_md(const std::string& name) const { return tables_dir() / (name + ".md"); }
fs::path ResultsDir::kpis_csv() const { return table_csv("kpis"); }
fs::path ResultsDir::profiles_dir() const { return root_ / "profiles"; }
fs::path ResultsDir::profile_index_json() const { return profiles_dir() / "index.json"; }
ResultsDir ResultsDir::profile(const std::string& name) const { return ResultsDir(profiles_dir() / name); }
scenario::PlanDir ResultsDir::plan() const { return scenario::PlanDir(root_ / "plan"); }
ResultsDir ResultsDir::plan_results() const { return ResultsDir(root_ / "plan_results"); }

fs::path ResultsDir::figures_dir() const { return root_ / "figures"; }
fs::path ResultsDir::report_html() const { return root_ / "report.html"; }

}  // namespace emrm::results
