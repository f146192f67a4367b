// End-to-end: `emrm diagnose` on a store of a user's own campaign (a grid of any name, a wet road):
// the diagnostics of `emrm reproduce` are written beside the store and shown by the report; a region
// that contradicts the stop boundary is found (exit 1); a folder that is not a store is bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace diagnose_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr const char* kCampaign =
    "seed: 3\n"
    "grids:\n"
    "  - name: wet\n"
    "    speed_kph: [20, 30]\n"
    "    ttc_s: [0.5, 1.5, 2.5]\n"
    "    mu: 0.5\n";

class DiagnoseCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(scratch_dir("diagnose"));
    write_text(*dir_ / "campaign.yaml", kCampaign);
    const auto r = run_emrm("sweep " + quoted(*dir_ / "campaign.yaml") + " -o " + quoted(*dir_ / "out"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path* dir_;
};
fs::path* DiagnoseCli::dir_ = nullptr;

TEST_F(DiagnoseCli, WritesTheDiagnosticsOfAnyStoreAndTheReportShowsThem) {
  const auto r = run_emrm("diagnose " + quoted(*dir_ / "out") + " --sample 2 --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("0 analytically stoppable cells classified R"));
  EXPECT_THAT(r.out, HasSubstr("reference planner on 2 cells"));
  const auto d = nlohmann::json::parse(read_text(*dir_ / "out" / "diagnostics.json"));
  EXPECT_EQ(d["stop_boundary"]["feasible"].get<int>(), 6);
  EXPECT_EQ(d["stop_boundary"]["stoppable"].get<int>(), 4);  // TTC >= v/(2 mu g): 1.5 s and 2.5 s
  EXPECT_EQ(d["rrt_vs_reference"]["sampled"].get<int>(), 2);
  EXPECT_TRUE(fs::exists(*dir_ / "out" / "fsm" / "emrm_fsm.dot"));

  const auto report = run_emrm("report " + quoted(*dir_ / "out"));
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string html = read_text(*dir_ / "out" / "report.html");
  EXPECT_THAT(html, HasSubstr("feasible cells can stop analytically"));
  EXPECT_THAT(html, HasSubstr("RRT against the reference planner (2 cells"));
}

TEST_F(DiagnoseCli, ARegionAgainstTheStopBoundaryIsExitOne) {
  if (std::system("command -v sqlite3 >/dev/null 2>&1") != 0) GTEST_SKIP() << "the sqlite3 shell is needed";
  const fs::path dir = *dir_ / "tampered";
  fs::create_directories(dir);
  fs::copy_file(*dir_ / "out" / "results.sqlite", dir / "results.sqlite", fs::copy_options::overwrite_existing);
  const std::string sql =
      "sqlite3 " + quoted(dir / "results.sqlite") + " \"UPDATE cells SET region = 'R' WHERE region = 'G'\"";
  ASSERT_EQ(std::system(sql.c_str()), 0);
  const auto r = run_emrm("diagnose " + quoted(dir) + " --sample 0");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("classified R (WARNING"));
  EXPECT_THAT(r.out, HasSubstr("contradict the analytic stop boundary"));
}

TEST_F(DiagnoseCli, AFolderWithoutAStoreIsBadInput) {
  const auto r = run_emrm("diagnose " + quoted(*dir_));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("holds no results.sqlite"));
  const auto missing = run_emrm("diagnose " + quoted(*dir_ / "nosuch"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.err, HasSubstr("does not exist"));
}

}  // namespace diagnose_cli_test
}  // namespace emrm::e2e
