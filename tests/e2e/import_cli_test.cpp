// End-to-end: an OpenSCENARIO scenario as a user imports it (docs/import.md) — `emrm import` writing
// the scene and the trace, every command taking the scene or the .xosc itself, and bad scenario
// files refused with exit 2 and nothing written.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace import_cli_test {

using ::testing::HasSubstr;

const std::string kExample = std::string(EMRM_SOURCE_DIR) + "/examples/openscenario/";

TEST(ImportCli, WritesASceneEveryCommandTakesAndTheTrace) {
  const auto dir = scratch_dir("import");
  const RunResult r = run_emrm("import " + quoted(kExample + "cut_in.xosc") + " -o " + quoted(dir / "scene.yaml") +
                               " --trace " + quoted(dir / "trace.csv") + " --trace-s 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("family openscenario, ego Ego, 4 factors"));
  const std::string scene = read_text(dir / "scene.yaml");
  EXPECT_THAT(scene, HasSubstr("family: openscenario"));
  // The scenario named relative to the scene file, so that the two move together.
  EXPECT_THAT(scene, HasSubstr("file: "));
  EXPECT_THAT(scene, ::testing::Not(HasSubstr("file: /")));
  // The trace: both cars every 10 ms for 2 s, from t = 0.
  const auto rows = csv_rows(dir / "trace.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], (std::vector<std::string>{"t", "actor", "x", "y", "heading", "speed"}));
  EXPECT_EQ(rows.size(), 1U + 2U * 201U);
  // The written scene simulates, and so does the scenario itself.
  for (const std::string& scene_arg : {quoted(dir / "scene.yaml"), quoted(kExample + "cut_in.xosc")}) {
    const RunResult sim = run_emrm("simulate --scene " + scene_arg + " --speed-kph 100 --ttc-s 1 --json");
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto j = nlohmann::json::parse(sim.out);
    EXPECT_EQ(j["family"], "openscenario");
    EXPECT_EQ(j["actors"][0]["name"], "CutIn");
  }
}

TEST(ImportCli, TheExampleSweepsAndVerifies) {
  const auto dir = scratch_dir("import_sweep");
  // A corner of the example's campaign, over both declared parameters that are factors.
  write_text(dir / "campaign.yaml", "scene: " + kExample +
                                        "scene.yaml\nseed: 1\ngrids:\n  - name: corner\n"
                                        "    speed_kph: [80, 100]\n    ttc_s: [0.5, 1.0]\n    RelativeSpeed: [11.11]\n"
                                        "    LaneChangeTime: [1.5, 3.0]\n");
  const RunResult sweep = run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "store"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_THAT(sweep.out, HasSubstr("Swept 8 cells"));
  const RunResult verify = run_emrm("verify " + quoted(dir / "store"));
  EXPECT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  EXPECT_THAT(verify.out, HasSubstr("All claims hold."));
}

TEST(ImportCli, PlansAndRunsAMinimumScenarioSetOverTheDeclaredParameters) {
  const auto dir = scratch_dir("import_plan");
  // An ODD of its own over the two declared parameters the example's scene makes factors: four
  // cells, each tested.
  write_text(dir / "odd.yaml", "name: imported\nscene: " + kExample +
                                   "scene.yaml\nseed: 3\nfactors:\n"
                                   "  - {name: speed_kph, unit: km/h, bins: [90, 110]}\n"
                                   "  - {name: ttc_s, unit: s, bins: [0.4, 0.8]}\n"
                                   "  - {name: RelativeSpeed, unit: m/s, bins: [5, 8, 11]}\n"
                                   "  - {name: LaneChangeTime, unit: s, bins: [1.5, 2.5, 3.5]}\n"
                                   "coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, delta: 0.1, budget: 12}\n"
                                   "acceptance: {strategy: emrm, outcome: mitigated}\n");
  const RunResult plan = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "plan"));
  ASSERT_EQ(plan.exit_code, 0) << plan.out << plan.err;
  EXPECT_THAT(plan.out, HasSubstr("cells 100.0 % (4/4)"));
  const auto scenarios = csv_rows(dir / "plan" / "scenarios.csv");
  ASSERT_GE(scenarios.size(), 5U);
  EXPECT_THAT(scenarios[0], ::testing::Contains("RelativeSpeed"));
  EXPECT_THAT(scenarios[0], ::testing::Contains("LaneChangeTime"));
  const RunResult run = run_emrm("run " + quoted(dir / "plan" / "scenarios.csv") + " -o " + quoted(dir / "run"));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_THAT(run.out, HasSubstr("4 cells"));
  // Every planned scenario has its outcome, with the cell's declared parameters as planned.
  const auto outcomes = csv_rows(dir / "run" / "outcomes.csv");
  ASSERT_EQ(outcomes.size(), scenarios.size());
  EXPECT_THAT(outcomes[0], ::testing::Contains("RelativeSpeed"));
}

TEST(ImportCli, ADistributionFileAndFactorRangesMakeACampaignThatSweeps) {
  const auto dir = scratch_dir("import_distribution");
  write_text(dir / "motorway.xodr", read_text(kExample + "motorway.xodr"));
  write_text(dir / "cut_in.xosc", read_text(kExample + "cut_in.xosc"));
  // The distribution varies the ego's speed (m/s) and the gap; the command line narrows the speed
  // and sets the TTC.
  write_text(dir / "distribution.xosc", R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="2" date="2026-01-01T00:00:00" description="d" author="emrm"/>
  <ParameterValueDistribution>
    <ScenarioFile filepath="cut_in.xosc"/>
    <Deterministic>
      <DeterministicSingleParameterDistribution parameterName="EgoSpeed">
        <DistributionRange stepWidth="5"><Range lowerLimit="20" upperLimit="30"/></DistributionRange>
      </DeterministicSingleParameterDistribution>
      <DeterministicSingleParameterDistribution parameterName="CutInGap">
        <DistributionSet><Element value="10"/></DistributionSet>
      </DeterministicSingleParameterDistribution>
    </Deterministic>
  </ParameterValueDistribution>
</OpenSCENARIO>
)");
  const RunResult r =
      run_emrm("import " + quoted(dir / "distribution.xosc") + " -o " + quoted(dir / "scene.yaml") + " --campaign " +
               quoted(dir / "campaign.yaml") + " --factor-range speed_kph=90:100:10 --factor-range ttc_s=0.5:1:0.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("speed_kph sets EgoSpeed"));
  EXPECT_THAT(r.out, HasSubstr("Campaign written to"));
  EXPECT_THAT(r.out, HasSubstr("speed_kph × ttc_s × CutInGap"));
  const RunResult sweep = run_emrm("sweep " + quoted(dir / "campaign.yaml") + " -o " + quoted(dir / "store"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_THAT(sweep.out, HasSubstr("Swept 4 cells"));
  // Bad ranges and a campaign without its scene: exit 2, nothing written.
  for (const std::string& bad :
       {std::string(" --factor-range ttc_s=1:0.5:0.1 -o "), std::string(" --factor-range nope=1:2:1 -o "),
        std::string(" --campaign c.yaml --trace ")}) {
    const auto out = dir / "bad";
    const RunResult refused = run_emrm("import " + quoted(dir / "distribution.xosc") + bad + quoted(out));
    EXPECT_EQ(refused.exit_code, 2) << bad << refused.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << bad;
  }
}

TEST(ImportCli, ABadScenarioIsExit2AtItsLineAndNothingIsWritten) {
  const auto dir = scratch_dir("import_bad");
  write_text(dir / "motorway.xodr", read_text(kExample + "motorway.xodr"));
  // An expression naming a parameter the scenario does not declare.
  const std::string unknown = "${$EgoSpeed - $RelativeSpeed}";
  std::string bad = read_text(kExample + "cut_in.xosc");
  bad.replace(bad.find(unknown), unknown.size(), "${$EgoSpeed - $NoSuchParameter}");
  write_text(dir / "bad.xosc", bad);
  const RunResult r = run_emrm("import " + quoted(dir / "bad.xosc") + " -o " + quoted(dir / "scene.yaml") +
                               " --trace " + quoted(dir / "trace.csv"));
  expect_bad_input(r, "bad.xosc:");
  EXPECT_THAT(r.err, HasSubstr("NoSuchParameter"));
  EXPECT_FALSE(std::filesystem::exists(dir / "scene.yaml"));
  EXPECT_FALSE(std::filesystem::exists(dir / "trace.csv"));
  // A scene naming a scenario that is not there: exit 2 at the field.
  write_text(dir / "scene2.yaml", "family: openscenario\nopenscenario:\n  file: missing.xosc\n");
  expect_bad_input(run_emrm("simulate --scene " + quoted(dir / "scene2.yaml")), "scene2.yaml:3:");
}

}  // namespace import_cli_test
}  // namespace emrm::e2e
