// The layout of a results folder (results_dir.hpp, docs/results.md): every path it names, spelled
// out here as the documentation lists them, and the writers writing where it says.

#include "emrm/results/results_dir.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/sweep.hpp"
#include "emrm/results/profiles.hpp"
#include "emrm/results/verify.hpp"
#include "emrm/safety/analysis.hpp"
#include "emrm/safety/load.hpp"
#include "scratch.hpp"

namespace emrm::results {
namespace results_dir_test {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return test::scratch_dir("results-dir-test", name); }

TEST(ResultsDir, NamesEveryPathOfTheFolder) {
  const ResultsDir d("out");
  EXPECT_EQ(d.root(), fs::path("out"));
  const std::vector<std::pair<fs::path, std::string>> paths{
      {d.store(), "out/results.sqlite"},
      {d.regions_csv(), "out/regions.csv"},
      {d.cells_csv(), "out/cells.csv"},
      {d.cells_json(), "out/cells.json"},
      {d.outcomes_csv(), "out/outcomes.csv"},
      {d.estimates_csv(), "out/estimates.csv"},
      {d.estimates_json(), "out/estimates.json"},
      {d.traceability_csv(), "out/traceability.csv"},
      {d.coverage_json(), "out/coverage.json"},
      {d.verify_json(), "out/verify.json"},
      {d.diagnostics_json(), "out/diagnostics.json"},
      {d.fsm_dir(), "out/fsm"},
      {d.analysis_dir(), "out/analysis"},
      {d.findings_json(), "out/analysis/findings.json"},
      {d.analysis_traceability_csv(), "out/analysis/traceability.csv"},
      {d.tables_dir(), "out/tables"},
      {d.table_csv("claims"), "out/tables/claims.csv"},
      {d.table_md("claims"), "out/tables/claims.md"},
      {d.kpis_csv(), "out/tables/kpis.csv"},
      {d.profiles_dir(), "out/profiles"},
      {d.profile_index_json(), "out/profiles/index.json"},
      {d.profile("paper").root(), "out/profiles/paper"},
      {d.profile("paper").store(), "out/profiles/paper/results.sqlite"},
      {d.plan().root(), "out/plan"},
      {d.plan().scenarios_csv(), "out/plan/scenarios.csv"},
      {d.plan().scenarios_json(), "out/plan/scenarios.json"},
      {d.plan().coverage_json(), "out/plan/coverage.json"},
      {d.plan().coverage_csv(), "out/plan/coverage.csv"},
      {d.plan().coverage_md(), "out/plan/coverage.md"},
      {d.plan_results().root(), "out/plan_results"},
      {d.plan_results().outcomes_csv(), "out/plan_results/outcomes.csv"},
      {d.plan_results().estimates_csv(), "out/plan_results/estimates.csv"},
      {d.plan_results().estimates_json(), "out/plan_results/estimates.json"},
      {d.plan_results().traceability_csv(), "out/plan_results/traceability.csv"},
      {d.plan_results().store(), "out/plan_results/results.sqlite"},
      {d.figures_dir(), "out/figures"},
      {d.report_html(), "out/report.html"},
  };
  for (const auto& [path, expected] : paths) EXPECT_EQ(path.generic_string(), expected);
}

// From an empty root the paths are relative to the folder: what the profile index stores.
TEST(ResultsDir, AnEmptyRootGivesThePathsWithinTheFolder) {
  EXPECT_EQ(ResultsDir().store().generic_string(), "results.sqlite");
  EXPECT_EQ(ResultsDir().profile("ideal").store().generic_string(), "profiles/ideal/results.sqlite");
  EXPECT_EQ(scenario::PlanDir::of("somewhere/plan/scenarios.csv").scenarios_json().generic_string(),
            "somewhere/plan/scenarios.json");
}

// A sweep, the safety analysis, verify and the profile index write their files where the folder
// says they are (their names are their writers', results_dir.hpp).
TEST(ResultsDir, TheWritersWriteWhereItSays) {
  const ResultsDir d(scratch("writers"));
  campaign::SweepOptions options;
  options.output_dir = d.root();
  options.threads = 1;
  options.progress = false;
  (void)campaign::sweep(
      campaign::parse_campaign("grids:\n  - name: a\n    speed_kph: 30\n    ttc_s: 2.5\n", "one.yaml", "."), options);
  for (const fs::path& file : {d.store(), d.regions_csv(), d.cells_csv(), d.cells_json()})
    EXPECT_TRUE(fs::is_regular_file(file)) << file;

  const auto analysis =
      safety::analyze(safety::load_safety_case(fs::path(EMRM_SOURCE_DIR) / "examples" / "tjunction" / "safety.yaml"));
  const auto written = safety::write_analysis(d.analysis_dir(), analysis);
  EXPECT_EQ(written.size(), 4u);
  for (const fs::path& file : {d.findings_json(), d.analysis_traceability_csv()})
    EXPECT_TRUE(fs::is_regular_file(file)) << file;

  write_verify_report(d.root(), VerifyReport{});
  EXPECT_TRUE(fs::is_regular_file(d.verify_json()));
  write_profile_index(d.root(), {});
  EXPECT_TRUE(fs::is_regular_file(d.profile_index_json()));
  EXPECT_TRUE(read_profile_index(d.root()).empty());
}

}  // namespace results_dir_test
}  // namespace emrm::results
