// A plan's shortfalls travel: `emrm plan` says why a mode's region is empty inside the ODD and
// records it in scenarios.json and coverage.json; `emrm run` repeats it as a warning (exit 1), keeps
// the mode in estimates.json and records where the plan lives; `emrm report` shows it first and
// finds the plan's coverage beside the scenarios.csv the run read.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace shortfall_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// A UCA of the safety case whose region (ice) is empty in the small ODD (mu is 1 throughout).
constexpr const char* kIceUca = R"(  - id: UCA5
    control_action: CA1
    type: provided
    context: EMRM evades as on ice although the road is dry.
    hazards: [H2]
    fsm_transitions:
      - {from: S2, event: high_risk, to: S3}
    region: "mu < 0.35"
)";

class ShortfallCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto example_dir = small_example("shortfall");
    std::string safety = read_text(example_dir / "safety.yaml");
    safety.insert(safety.find("\n# SMIL lookup") + 1, kIceUca);
    write_text(example_dir / "safety.yaml", safety);
    root_ = new fs::path(example_dir.parent_path());
    plan_ = new RunResult(run_emrm("plan " + quoted(example_dir / "odd.yaml") + " -o " + quoted(*root_ / "plan")));
    run_ = new RunResult(run_emrm("run " + quoted(*root_ / "plan" / "scenarios.csv") + " -o " +
                                  quoted(*root_ / "results") + " --threads 2"));
  }
  static void TearDownTestSuite() {
    delete root_;
    delete plan_;
    delete run_;
  }
  static fs::path* root_;
  static RunResult* plan_;
  static RunResult* run_;
};
fs::path* ShortfallCli::root_ = nullptr;
RunResult* ShortfallCli::plan_ = nullptr;
RunResult* ShortfallCli::run_ = nullptr;

constexpr const char* kEmpty =
    "malfunction UCA5: its region is empty inside the ODD: 'mu < 0.35' holds nowhere in the factors' domains "
    "(mu = 1)";

TEST_F(ShortfallCli, PlanSaysTheRegionIsEmptyAndWhy) {
  EXPECT_EQ(plan_->exit_code, 1) << plan_->out << plan_->err;  // C4 fails for UCA5
  EXPECT_THAT(plan_->out, HasSubstr(std::string("shortfall: ") + kEmpty));
  EXPECT_THAT(plan_->out, ::testing::Not(HasSubstr("only 0 of")));
}

TEST_F(ShortfallCli, PlanRecordsTheShortfallInItsFiles) {
  const auto scenarios = nlohmann::json::parse(read_text(*root_ / "plan" / "scenarios.json"));
  const auto& shortfalls = scenarios.at("stop").at("shortfalls");
  ASSERT_EQ(shortfalls.size(), 1u) << shortfalls.dump(2);
  EXPECT_EQ(shortfalls[0].at("kind"), "empty_region");
  EXPECT_EQ(shortfalls[0].at("subject"), "UCA5");
  EXPECT_EQ(shortfalls[0].at("found"), 0);
  EXPECT_EQ(shortfalls[0].at("needed"), 1);
  EXPECT_THAT(shortfalls[0].at("message").get<std::string>(), HasSubstr(kEmpty));
  // Every mode is listed with its planned tests, UCA5 with none.
  std::map<std::string, int> tests;
  for (const auto& m : scenarios.at("malfunctions")) tests[m.at("id")] = m.at("tests");
  EXPECT_EQ(tests.size(), 5u);
  EXPECT_EQ(tests.at("UCA5"), 0);
  EXPECT_GT(tests.at("UCA1"), 0);
  const auto coverage = nlohmann::json::parse(read_text(*root_ / "plan" / "coverage.json"));
  EXPECT_EQ(coverage.at("shortfalls"), shortfalls);
}

TEST_F(ShortfallCli, RunRepeatsTheShortfallAndKeepsTheMode) {
  EXPECT_EQ(run_->exit_code, 1) << run_->out << run_->err;
  EXPECT_THAT(run_->out, HasSubstr(std::string("warning: the plan fell short: ") + kEmpty));
  EXPECT_THAT(run_->out, HasSubstr("S(UCA5): no tests (a plan shortfall, above)"));
  EXPECT_THAT(run_->out, HasSubstr("run       1 shortfall of the plan"));
  const auto estimates = nlohmann::json::parse(read_text(*root_ / "results" / "estimates.json"));
  const auto& uca5 = estimates.at("weighted_success").at("UCA5");
  EXPECT_EQ(uca5.at("n"), 0);
  EXPECT_TRUE(uca5.at("estimate").is_null());
  EXPECT_THAT(uca5.at("shortfall").get<std::string>(), HasSubstr(kEmpty));
  EXPECT_EQ(estimates.at("shortfalls").size(), 1u);
  EXPECT_EQ(estimates.at("shortfalls")[0].at("kind"), "empty_region");
  // Where the plan lives, relative to the run's folder.
  EXPECT_EQ(estimates.at("plan").at("scenarios"), "../plan/scenarios.csv");
  EXPECT_EQ(estimates.at("plan").at("coverage"), "../plan/coverage.json");
}

TEST_F(ShortfallCli, ReportShowsTheShortfallFirstAndFindsThePlansCoverage) {
  const auto r = run_emrm("report " + quoted(*root_ / "results"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr("no coverage.json")));
  EXPECT_TRUE(fs::is_regular_file(*root_ / "results" / "figures" / "coverage_comparison.png"));
  const std::string html = read_text(*root_ / "results" / "report.html");
  const auto shortfall = html.find("malfunction UCA5: its region is empty inside the ODD");
  ASSERT_NE(shortfall, std::string::npos);
  EXPECT_LT(shortfall, html.find("Actuation:"));  // at the top, before the figures and tables
}

}  // namespace shortfall_cli_test
}  // namespace emrm::e2e
