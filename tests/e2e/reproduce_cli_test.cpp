// `emrm reproduce` end to end on a small copy of the shipped example: every step runs, the tables
// show ours beside the paper's, and the fine grid's G cells are exactly the analytically stoppable ones.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace reproduce_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

TEST(ReproduceCli, RunsEveryStepAndShowsOursBesideThePapers) {
  const auto example_dir = small_example("reproduce");
  const auto out = example_dir.parent_path() / "out";
  const auto r =
      run_emrm("reproduce -o " + quoted(out) + " --examples " + quoted(example_dir) + " --sample 3 --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("G "));
  EXPECT_THAT(r.out, HasSubstr("vs 44.5"));
  EXPECT_THAT(r.out, HasSubstr("(paper 45)"));

  for (const char* f : {"tables/emrm_vs_baseline.md",
                        "tables/emrm_vs_baseline.csv",
                        "tables/emrm_vs_baseline.tex",
                        "tables/by_parameter.md",
                        "tables/regions.md",
                        "tables/kpis.csv",
                        "diagnostics.json",
                        "analysis/traceability.csv",
                        "fsm/emrm_fsm_check.json",
                        "fsm/emrm_fsm.dot",
                        "fsm/loss_evaluation_fsm.dot",
                        "results.sqlite",
                        "tables/coverage.md",
                        "tables/coverage.tex",
                        "plan/scenarios.csv",
                        "plan/scenarios.json",
                        "plan/coverage.json",
                        "plan_results/estimates.json",
                        "plan_results/outcomes.csv",
                        "plan_results/traceability.csv"})
    EXPECT_TRUE(fs::exists(out / f)) << f;

  // The minimum scenario set: C1–C4 hold, baselines measured, the paper's figures beside ours.
  EXPECT_THAT(r.out, HasSubstr("C1 holds, C2 holds, C3 holds, C4 holds"));
  const auto coverage = read_text(out / "tables/coverage.md");
  EXPECT_THAT(coverage, HasSubstr("| emrm plan |"));
  EXPECT_THAT(coverage, HasSubstr("| HARA only |"));
  EXPECT_THAT(coverage, HasSubstr("≤75"));
  EXPECT_THAT(coverage, HasSubstr("≤1 |"));
  const auto estimates = nlohmann::json::parse(read_text(out / "plan_results/estimates.json"));
  EXPECT_GT(estimates["scenarios"].get<int>(), 0);
  EXPECT_TRUE(estimates["weighted_success"].contains("all"));

  const auto baseline = read_text(out / "tables/emrm_vs_baseline.md");
  EXPECT_THAT(baseline, HasSubstr("(paper 81)"));
  EXPECT_THAT(baseline, HasSubstr("(paper 18.9)"));
  EXPECT_THAT(read_text(out / "tables/by_parameter.md"), HasSubstr("(paper 96 / 83 / 46)"));
  const auto regions = read_text(out / "tables/regions.md");
  EXPECT_THAT(regions, HasSubstr("| fine (paper) |"));
  EXPECT_THAT(regions, HasSubstr("44.5"));

  const auto diagnostics = nlohmann::json::parse(read_text(out / "diagnostics.json"));
  EXPECT_EQ(diagnostics["stop_boundary"]["stoppable_red_count"].get<int>(), 0);
  EXPECT_EQ(diagnostics["rrt_vs_reference"]["sampled"].get<int>(), 3);
  EXPECT_GT(diagnostics["fsm_coverage"]["emrm_fsm"]["covered"].get<int>(), 0);

  // G exactly where the analytic stop boundary says: TTC >= v / (2 mu g).
  std::istringstream csv(read_text(out / "regions.csv"));
  std::string header;
  std::getline(csv, header);
  std::vector<std::string> columns;
  for (std::stringstream h(header); h.good();) {
    std::string c;
    std::getline(h, c, ',');
    columns.push_back(c);
  }
  const auto column = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name << " in " << header;
    return static_cast<std::size_t>(it - columns.begin());
  };
  const auto grid_at = column("grid");
  const auto speed_at = column("speed_kph"), ttc_at = column("ttc_s"), mu_at = column("mu"),
             feasible_at = column("feasible"), region_at = column("region");
  int feasible = 0, green = 0;
  for (std::string line; std::getline(csv, line);) {
    std::vector<std::string> f;
    for (std::stringstream l(line); l.good();) {
      std::string c;
      std::getline(l, c, ',');
      f.push_back(c);
    }
    ASSERT_GT(f.size(), region_at) << line;
    if (f[grid_at] != "fine" || f[feasible_at] != "1") continue;
    ++feasible;
    const double v = std::stod(f[speed_at]) / 3.6, ttc = std::stod(f[ttc_at]), mu = std::stod(f[mu_at]);
    // The stop's closed form under the shipped scene's actuation (the production car: perception
    // 0.25 s and brake dead time 0.1 s, then a 0.25 s ramp to mu g; docs/actuation.md).
    const double a = mu * 9.81, delay = 0.25 + 0.1, ramp = 0.25;
    const bool stoppable = v * ttc >= v * delay + v * ramp / 2.0 + v * v / (2.0 * a) - a * ramp * ramp / 24.0;
    EXPECT_EQ(f[region_at] == "G", stoppable) << line;
    green += f[region_at] == "G";
  }
  EXPECT_EQ(feasible, 7);
  EXPECT_EQ(green, 2);  // (30, 1.0), (30, 2.0); (50, 1.0) needs 16.4 m and has 13.9

  // The fine grid under every profile of the example's profiles/ folder: production is the scene
  // (its store reused), ideal and paper are swept; under ideal, G is the instant stop's.
  const auto index = nlohmann::json::parse(read_text(out / "profiles/index.json"));
  ASSERT_EQ(index.size(), 3u);
  std::map<std::string, bool> reused;
  for (const auto& e : index) reused[e["name"].get<std::string>()] = e["reused"].get<bool>();
  EXPECT_EQ(reused, (std::map<std::string, bool>{{"ideal", false}, {"paper", false}, {"production", true}}));
  int ideal_green = 0;
  for (const auto& row : csv_rows(out / "profiles/ideal/regions.csv")) ideal_green += row.size() > 7 && row[7] == "G";
  EXPECT_EQ(ideal_green, 3);  // (30, 1.0), (30, 2.0), (50, 1.0): TTC >= v/(2 mu g)
  EXPECT_EQ(csv_rows(out / "tables/regions_by_profile.csv").size(), 5u);  // header, 3 profiles, the paper
  EXPECT_THAT(r.out, HasSubstr("profiles  grid 'fine' per profile"));

  // A rerun resumes: nothing is simulated again, and the plan is the same.
  const std::string planned = read_text(out / "plan/scenarios.csv");
  const auto again = run_emrm("reproduce -o " + quoted(out) + " --examples " + quoted(example_dir) + " --sample 1");
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_THAT(again.out, HasSubstr("11 already stored, 0 simulated"));
  EXPECT_EQ(read_text(out / "plan/scenarios.csv"), planned);
}

TEST(ReproduceCli, MissingExamplesFolderIsBadInput) {
  const auto out = scratch_dir("reproduce-missing");
  const auto r = run_emrm("reproduce -o " + quoted(out / "out") + " --examples " + quoted(out / "nowhere"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("nowhere"));
}

TEST(ReproduceCli, BadPaperReferenceIsBadInputWithLocation) {
  const auto example_dir = small_example("reproduce-bad-reference");
  write_text(example_dir / "paper_reference.yaml", "version: 7\n");
  const auto r =
      run_emrm("reproduce -o " + quoted(example_dir.parent_path() / "out") + " --examples " + quoted(example_dir));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("paper_reference.yaml:1:10"));
}

}  // namespace reproduce_cli_test
}  // namespace emrm::e2e
