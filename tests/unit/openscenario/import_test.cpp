// What `emrm import` makes of a scenario (openscenario/import.hpp, docs/import.md): the ranges of a
// ParameterValueDistribution file and of --factor-range as the sweeps of a campaign, the ego's
// speed parameter in km/h, value sets as grids, and what it refuses.

#include "emrm/openscenario/import.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "emrm/core/error.hpp"
#include "input_error.hpp"
#include "scratch.hpp"

namespace emrm::openscenario::import_test {  // its own names in the unity build
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

const std::filesystem::path kExample = EMRM_SOURCE_DIR "/examples/openscenario";

// A folder holding the example's scenario and road, and a distribution of `body` naming it.
std::filesystem::path distribution(const std::string& name, const std::string& body) {
  const auto dir = emrm::test::scratch_dir("openscenario_import", name);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(kExample / "cut_in.xosc", dir / "cut_in.xosc");
  std::filesystem::copy_file(kExample / "motorway.xodr", dir / "motorway.xodr");
  const auto file = dir / "distribution.xosc";
  std::ofstream(file) << R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="2" date="2026-01-01T00:00:00" description="d" author="emrm"/>
  <ParameterValueDistribution>
    <ScenarioFile filepath="cut_in.xosc"/>
    <Deterministic>
)" << body << R"(
    </Deterministic>
  </ParameterValueDistribution>
</OpenSCENARIO>
)";
  return file;
}

std::vector<std::string> factor_keys(const std::vector<FactorSweep>& sweeps) {
  std::vector<std::string> out;
  for (const auto& s : sweeps) out.push_back(s.factor);
  return out;
}

const std::string kSpeedAndGap = R"(
      <DeterministicSingleParameterDistribution parameterName="CutInGap">
        <DistributionSet><Element value="8"/><Element value="12"/></DistributionSet>
      </DeterministicSingleParameterDistribution>
      <DeterministicSingleParameterDistribution parameterName="EgoSpeed">
        <DistributionRange stepWidth="5"><Range lowerLimit="20" upperLimit="30"/></DistributionRange>
      </DeterministicSingleParameterDistribution>)";

TEST(ImportScenario, ADistributionsParametersAreTheFactorsAndItsRangesTheSweeps) {
  const Registration registration;
  const ImportedScenario imported = import_scenario(distribution("ranges", kSpeedAndGap));
  // The scenario the distribution names; the ego's speed parameter is speed_kph's, the other one
  // varied the only declared factor.
  EXPECT_EQ(std::filesystem::path(imported.scene.openscenario.file).filename(), "cut_in.xosc");
  EXPECT_EQ(imported.scene.openscenario.speed_parameter, "EgoSpeed");
  ASSERT_EQ(imported.scene.openscenario.factors.size(), 1U);
  EXPECT_EQ(imported.scene.openscenario.factors[0].parameter, "CutInGap");
  EXPECT_EQ(imported.scene.openscenario.factors[0].unit, "m");
  // In the factor table's order; the speed in km/h.
  ASSERT_THAT(factor_keys(imported.sweeps), ElementsAre("speed_kph", "CutInGap"));
  const auto& speed = std::get<ValueRange>(imported.sweeps[0].values);
  EXPECT_DOUBLE_EQ(speed.lower, 72.0);
  EXPECT_DOUBLE_EQ(speed.upper, 108.0);
  EXPECT_DOUBLE_EQ(speed.step, 18.0);
  EXPECT_EQ(std::get<std::vector<double>>(imported.sweeps[1].values), (std::vector<double>{8.0, 12.0}));
  EXPECT_TRUE(imported.value_sets.empty());
  // The campaign: one grid, the TTC over the default range.
  const std::string campaign = campaign_yaml(imported, "scene.yaml");
  EXPECT_THAT(campaign, HasSubstr("scene: scene.yaml\n"));
  EXPECT_THAT(campaign, HasSubstr("  - name: imported\n"));
  EXPECT_THAT(campaign, HasSubstr("    ttc_s: {from: 0.1, to: 2, step: 0.1}"));
  EXPECT_THAT(campaign, HasSubstr("    speed_kph: {from: 72, to: 108, step: 18}\n"));
  EXPECT_THAT(campaign, HasSubstr("    CutInGap: [8, 12]\n"));
}

TEST(ImportScenario, AFactorRangeReplacesTheDistributionsAndMustBeAFactorsValue) {
  const Registration registration;
  const auto file = distribution("override", kSpeedAndGap);
  const ImportedScenario imported =
      import_scenario(file, {}, {parse_factor_range("speed_kph=60:120:20"), parse_factor_range("ttc_s=0.2:1:0.2")});
  ASSERT_THAT(factor_keys(imported.sweeps), ElementsAre("speed_kph", "ttc_s", "CutInGap"));
  const auto& speed = std::get<ValueRange>(imported.sweeps[0].values);
  EXPECT_EQ(speed.lower, 60.0);
  EXPECT_EQ(speed.upper, 120.0);
  EXPECT_THAT(campaign_yaml(imported, "s.yaml"), ::testing::Not(HasSubstr("emrm import's default")));
  // A factor the scene does not have, a value the factor refuses.
  try {
    (void)import_scenario(file, {}, {parse_factor_range("RelativeSpeed=1:2:1")});
    FAIL() << "expected a UsageError";
  } catch (const UsageError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("the scene has no factor 'RelativeSpeed'"));
  }
  try {
    (void)import_scenario(file, {}, {parse_factor_range("mu=0.5:3:0.5")});
    FAIL() << "expected a UsageError";
  } catch (const UsageError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("--factor-range mu=0.5:3:0.5: mu must be"));
  }
}

TEST(ImportScenario, AFactorRangeIsKeyFromToStep) {
  const FactorSweep s = parse_factor_range("LaneChangeTime=0.5:4:0.5");
  EXPECT_EQ(s.factor, "LaneChangeTime");
  const auto& r = std::get<ValueRange>(s.values);
  EXPECT_EQ(r.values().size(), 8U);
  for (const std::string bad : {"ttc_s", "=1:2:1", "ttc_s=1:2", "ttc_s=2:1:0.1", "ttc_s=1:2:0", "ttc_s=1:2:-1",
                                "ttc_s=a:2:1", "ttc_s=1:2:1:4", "ttc_s=nan:2:1", "ttc_s=1:inf:1"})
    EXPECT_THROW((void)parse_factor_range(bad), UsageError) << bad;
}

TEST(ImportScenario, ValueSetsAreGridsOfTheirOwn) {
  const Registration registration;
  const ImportedScenario imported = import_scenario(distribution("sets", R"(
      <DeterministicMultiParameterDistribution>
        <ValueSetDistribution>
          <ParameterValueSet><ParameterAssignment parameterRef="RelativeSpeed" value="5"/><ParameterAssignment parameterRef="LaneChangeTime" value="2"/></ParameterValueSet>
          <ParameterValueSet><ParameterAssignment parameterRef="RelativeSpeed" value="10"/><ParameterAssignment parameterRef="LaneChangeTime" value="3"/></ParameterValueSet>
        </ValueSetDistribution>
      </DeterministicMultiParameterDistribution>)"),
                                                    {}, {parse_factor_range("speed_kph=80:100:20")});
  ASSERT_EQ(imported.value_sets.size(), 2U);
  EXPECT_EQ(imported.value_sets[1].at("RelativeSpeed"), 10.0);
  const std::string campaign = campaign_yaml(imported, "scene.yaml");
  EXPECT_THAT(campaign, HasSubstr("  - name: set1\n    LaneChangeTime: 2\n    RelativeSpeed: 5\n"));
  EXPECT_THAT(campaign, HasSubstr("  - name: set2\n    LaneChangeTime: 3\n    RelativeSpeed: 10\n"));
}

TEST(ImportScenario, ADistributionOfAnUndeclaredOrTextParameterIsRefusedAtItsElement) {
  const Registration registration;
  const auto undeclared = distribution("undeclared", R"(
      <DeterministicSingleParameterDistribution parameterName="NoSuch">
        <DistributionSet><Element value="1"/></DistributionSet>
      </DeterministicSingleParameterDistribution>)");
  // A scenario file that is not there: at the ScenarioFile element.
  std::filesystem::remove(undeclared.parent_path() / "cut_in.xosc");
  const InputError missing = emrm::testing::input_error_of([&] { (void)import_scenario(undeclared); }, "missing");
  EXPECT_THAT(missing.message(), HasSubstr("ScenarioFile: expected the scenario the distribution varies"));
  EXPECT_EQ(missing.where().line, 5);
  std::filesystem::copy_file(kExample / "cut_in.xosc", undeclared.parent_path() / "cut_in.xosc");
  const InputError e = emrm::testing::input_error_of([&] { (void)import_scenario(undeclared); }, "undeclared");
  EXPECT_THAT(e.message(), HasSubstr("the distribution varies 'NoSuch', which cut_in.xosc does not declare"));
  EXPECT_EQ(e.where().line, 8);  // the distribution element, after the blank line the body opens with
  // A value the factor refuses (a speed of 0), and one that is no number.
  const auto zero = distribution("zero", R"(
      <DeterministicSingleParameterDistribution parameterName="EgoSpeed">
        <DistributionSet><Element value="0"/></DistributionSet>
      </DeterministicSingleParameterDistribution>)");
  EXPECT_THAT(emrm::testing::input_error_of([&] { (void)import_scenario(zero); }, "zero").message(),
              HasSubstr("speed_kph"));
  const auto text = distribution("text", R"(
      <DeterministicSingleParameterDistribution parameterName="CutInGap">
        <DistributionSet><Element value="near"/></DistributionSet>
      </DeterministicSingleParameterDistribution>)");
  EXPECT_THAT(emrm::testing::input_error_of([&] { (void)import_scenario(text); }, "text").message(),
              HasSubstr("CutInGap: expected a number, got 'near'"));
}

}  // namespace
}  // namespace emrm::openscenario::import_test
