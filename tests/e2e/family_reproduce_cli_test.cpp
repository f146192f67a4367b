// `emrm reproduce` on another family's example folder: a small copy of examples/highway_obstacle
// (its own safety case, FSMs and scene, a campaign of a few cells and a coarse ODD over the family's
// factors, categorical ones by their levels' names) runs every step, with no paper numbers beside
// ours; an ODD that names a class the family lacks, or numbers one as another level, is refused at
// its place.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace family_reproduce_cli_test {

using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

// Two speeds x two TTCs for each obstacle: the deer's braked hit beside the truck's evasion.
constexpr const char* kCampaign = R"(scene: scene.yaml
seed: 1
strategies: [emergency_stop, dodge, drift_to_avoid, drift_to_accident, emrm, best_strategy]
grids:
  - name: speed_ttc
    speed_kph: [80, 120]
    ttc_s: [0.8, 1.6]
    obstacle: [truck, deer]
)";

// The family's categorical obstacle as classes, blocked_m and roadside held, so that the plan stays
// small; every UCA's region is met (UCA2 on dry road at 60 km/h, UCA4 beyond the right lane).
constexpr const char* kOddHead = R"(name: small highway ODD
safety: safety.yaml
scene: scene.yaml
seed: 1
factors:
  - {name: speed_kph, bins: [60, 100, 150]}
  - {name: ttc_s, bins: [0.5, 1.2, 2.0]}
  - {name: mu, bins: [0.3, 0.6, 1.0]}
)";
constexpr const char* kOddTail = R"(  - {name: blocked_m, type: constant, value: 8.0}
relevance: "speed_kph / 3.6 * ttc_s <= 70"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, delta: 0.05, budget: 40}
acceptance: {strategy: emrm, outcome: mitigated}
baselines:
  manual: {speed_kph: [60, 150], ttc_s: [0.5, 2.0]}
)";

fs::path small_highway_example(const std::string& name, const std::string& obstacle_factor) {
  const auto dir = scratch_dir(name) / "example";
  fs::create_directories(dir);
  const fs::path shipped = fs::path(EMRM_SOURCE_DIR) / "examples" / "highway_obstacle";
  for (const char* file : {"safety.yaml", "emrm_fsm.yaml", "loss_evaluation_fsm.yaml", "scene.yaml"})
    fs::copy_file(shipped / file, dir / file);
  write_text(dir / "campaign.yaml", kCampaign);
  write_text(dir / "odd.yaml", std::string(kOddHead) + obstacle_factor + kOddTail);
  return dir;
}

TEST(FamilyReproduceCli, RunsEveryStepOnTheHighwayWithOursAlone) {
  const auto example_dir =
      small_highway_example("reproduce_highway", "  - {name: obstacle, type: categorical, classes: [truck, deer]}\n");
  const auto out = example_dir.parent_path() / "out";
  const auto r =
      run_emrm("reproduce -o " + quoted(out) + " --examples " + quoted(example_dir) + " --sample 2 --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("sweep"));
  EXPECT_THAT(r.out, HasSubstr("all claims hold"));
  EXPECT_THAT(r.out, HasSubstr("C1 holds, C2 holds, C3 holds, C4 holds"));
  EXPECT_THAT(r.out, HasSubstr("no published numbers beside them"));
  EXPECT_THAT(r.out, Not(HasSubstr("(paper")));
  EXPECT_THAT(r.out, Not(HasSubstr("vs paper")));
  for (const char* f :
       {"tables/emrm_vs_baseline.md", "tables/by_parameter.md", "tables/regions.md", "tables/coverage.md",
        "tables/brake_sensitivity.md", "tables/kpis.csv", "diagnostics.json", "analysis/traceability.csv",
        "plan/scenarios.csv", "plan_results/estimates.json", "report.html"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // Without the paper's numbers there are no claims to hold ours against, and no paper column.
  EXPECT_FALSE(fs::exists(out / "tables/claims.md"));
  EXPECT_THAT(read_text(out / "tables/emrm_vs_baseline.md"), Not(HasSubstr("(paper")));
  const auto by_parameter = read_text(out / "tables/by_parameter.md");
  EXPECT_THAT(by_parameter, HasSubstr("Ego speed: low (<= 93 km/h)"));  // thirds of 80-120 km/h
  EXPECT_THAT(by_parameter, Not(HasSubstr("Passage")));
  // The planned scenarios name the obstacle by its level's index, as a cell holds it.
  const auto scenarios = read_text(out / "plan/scenarios.csv");
  EXPECT_THAT(scenarios, HasSubstr("obstacle"));
  const auto diagnostics = nlohmann::json::parse(read_text(out / "diagnostics.json"));
  EXPECT_EQ(diagnostics["stop_boundary"]["stoppable_red_count"].get<int>(), 0);
}

TEST(FamilyReproduceCli, AnOddClassTheFamilyLacksIsRefusedAtItsPlace) {
  const auto example_dir = small_highway_example("reproduce_highway_moose",
                                                 "  - {name: obstacle, type: categorical, classes: [truck, moose]}\n");
  const auto r =
      run_emrm("reproduce -o " + quoted(example_dir.parent_path() / "out") + " --examples " + quoted(example_dir));
  expect_bad_input(r, "odd.yaml:9:58: error: obstacle: class 'moose': expected one of the levels truck, deer");
  EXPECT_FALSE(fs::exists(example_dir.parent_path() / "out" / "results.sqlite"));
}

TEST(FamilyReproduceCli, AnOddClassNumberedAsAnotherLevelIsRefused) {
  const auto example_dir = small_highway_example("reproduce_highway_swapped",
                                                 "  - {name: obstacle, type: categorical, classes: [deer, truck]}\n");
  const auto r =
      run_emrm("reproduce -o " + quoted(example_dir.parent_path() / "out") + " --examples " + quoted(example_dir));
  expect_bad_input(r,
                   "odd.yaml:9:51: error: obstacle: class 'deer' has the number 0, but the simulator reads 0 as "
                   "'truck'");
}

// A constant ODD factor may name one of the family's levels (`value: deer`): its index is the value
// every planned scenario gets; a name the family lacks is refused at its place.
TEST(FamilyReproduceCli, AConstantOddFactorNamesALevel) {
  const auto deer = small_highway_example("plan_highway_constant_deer",
                                          "  - {name: obstacle, type: constant, value: deer}\n  - {name: roadside, "
                                          "type: constant, value: embankment}\n");
  const auto plan = run_emrm("plan " + quoted(deer / "odd.yaml") + " -o " + quoted(deer.parent_path() / "plan"));
  ASSERT_EQ(plan.exit_code, 0) << plan.out << plan.err;
  const auto j = nlohmann::json::parse(read_text(deer.parent_path() / "plan" / "scenarios.json"));
  ASSERT_FALSE(j["scenarios"].empty());
  for (const auto& scenario : j["scenarios"]) {
    EXPECT_EQ(scenario["values"]["obstacle"].get<double>(), 1.0);
    EXPECT_EQ(scenario["values"]["roadside"].get<double>(), 1.0);
  }
  const auto moose =
      small_highway_example("plan_highway_constant_moose", "  - {name: obstacle, type: constant, value: moose}\n");
  expect_bad_input(run_emrm("plan " + quoted(moose / "odd.yaml") + " -o " + quoted(moose.parent_path() / "plan")),
                   "odd.yaml:9:45: error: value 'moose': expected one of the levels truck, deer of the scene's family");
}

// Every shipped family's example folder (beside the T-junction's, which ReproduceCli runs): its
// safety case analyses without an error, both FSMs pass their checks, and its ODD plans a scenario
// set meeting C1-C4 against its own scene; the whole reproduce is the README's (docs/families.md).
TEST(FamilyReproduceCli, EveryShippedExampleFolderAnalysesChecksAndPlans) {
  for (const char* family : {"highway_obstacle", "pedestrian_crossing", "cut_in"}) {
    const fs::path folder = fs::path(EMRM_SOURCE_DIR) / "examples" / family;
    const auto analysis = run_emrm("analyze " + quoted(folder / "safety.yaml"));
    EXPECT_EQ(analysis.exit_code, 0) << family << analysis.out << analysis.err;
    for (const char* fsm : {"emrm_fsm.yaml", "loss_evaluation_fsm.yaml"}) {
      const auto check = run_emrm("fsm " + quoted(folder / fsm) + " --check");
      EXPECT_EQ(check.exit_code, 0) << family << " " << fsm << check.out << check.err;
    }
    const auto plan = run_emrm("plan " + quoted(folder / "odd.yaml") + " -o " + quoted(scratch_dir(family) / "plan"));
    EXPECT_EQ(plan.exit_code, 0) << family << plan.out << plan.err;
    EXPECT_THAT(plan.out, HasSubstr("C1 holds, C2 holds, C3 holds, C4 holds")) << family;
  }
}

}  // namespace family_reproduce_cli_test
}  // namespace emrm::e2e
