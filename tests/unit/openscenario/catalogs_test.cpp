// Catalog references with parameter assignments, and parameter distribution files.

#include <gtest/gtest.h>

#include "emrm/openscenario/distribution.hpp"
#include "emrm/openscenario/reader.hpp"
#include "input_error.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using namespace test;

constexpr const char* kCatalog = R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="3" date="2026-01-01T00:00:00" description="vehicles" author="emrm"/>
  <Catalog name="VehicleCatalog">
    <Vehicle name="car" vehicleCategory="car">
      <ParameterDeclarations>
        <ParameterDeclaration name="Length" parameterType="double" value="4"/>
        <ParameterDeclaration name="Width" parameterType="double" value="${$Length / 2}"/>
      </ParameterDeclarations>
      <BoundingBox><Center x="1.4" y="0" z="0.75"/><Dimensions width="$Width" length="$Length" height="1.5"/></BoundingBox>
      <Performance maxSpeed="70" maxAcceleration="5" maxDeceleration="10"/>
      <Axles><RearAxle maxSteering="0" wheelDiameter="0.6" trackWidth="1.6" positionX="0" positionZ="0.3"/></Axles>
    </Vehicle>
  </Catalog>
</OpenSCENARIO>
)";

std::string reference(const std::string& entity, const std::string& assignments) {
  return fmt::format(
      R"(<ScenarioObject name="{}"><CatalogReference catalogName="VehicleCatalog" entryName="car">{}</CatalogReference></ScenarioObject>)",
      entity, assignments);
}

TEST(Catalogs, AReferenceTakesTheEntryWithItsParameterAssignments) {
  XoscParts parts;
  parts.parameters = R"(<ParameterDeclaration name="TruckLength" parameterType="double" value="12"/>)";
  parts.catalogs = R"(<VehicleCatalog><Directory path="catalogs/vehicles"/></VehicleCatalog>)";
  parts.entities =
      reference("Ego", "") + reference("Truck", R"(<ParameterAssignments><ParameterAssignment parameterRef="Length"
                       value="$TruckLength"/></ParameterAssignments>)");
  const auto file = write_scenario("catalog", parts);
  write_file(file.parent_path() / "catalogs/vehicles/vehicles.xosc", kCatalog);
  const Scenario scenario = load_openscenario(file);
  ASSERT_EQ(scenario.entities.size(), 2U);
  EXPECT_DOUBLE_EQ(scenario.entities[0].box.length_m, 4.0);
  EXPECT_DOUBLE_EQ(scenario.entities[0].box.width_m, 2.0);
  EXPECT_DOUBLE_EQ(scenario.entities[1].box.length_m, 12.0);  // assigned from a global parameter
  EXPECT_DOUBLE_EQ(scenario.entities[1].box.width_m, 6.0);    // and the entry's own expression follows
  EXPECT_DOUBLE_EQ(scenario.entities[1].box.center_x_m, 1.4);
  EXPECT_DOUBLE_EQ(scenario.entities[1].performance.max_acceleration_mps2, 5.0);
}

TEST(Catalogs, AMissingEntryOrParameterIsAnErrorAtTheReference) {
  XoscParts parts;
  parts.catalogs = R"(<VehicleCatalog><Directory path="catalogs/vehicles"/></VehicleCatalog>)";
  parts.entities =
      R"(<ScenarioObject name="Ego"><CatalogReference catalogName="VehicleCatalog" entryName="bus"/></ScenarioObject>)";
  auto file = write_scenario("catalog_missing", parts);
  write_file(file.parent_path() / "catalogs/vehicles/vehicles.xosc", kCatalog);
  InputError e = emrm::testing::input_error_of([&] { (void)load_openscenario(file); }, "bus");
  EXPECT_NE(e.message().find("no entry 'bus' (entries: car)"), std::string::npos) << e.what();
  EXPECT_GT(e.where().line, 0);

  parts.entities = reference(
      "Ego",
      R"(<ParameterAssignments><ParameterAssignment parameterRef="Colour" value="red"/></ParameterAssignments>)");
  file = write_scenario("catalog_parameter", parts);
  write_file(file.parent_path() / "catalogs/vehicles/vehicles.xosc", kCatalog);
  e = emrm::testing::input_error_of([&] { (void)load_openscenario(file); }, "Colour");
  EXPECT_NE(e.message().find("no parameter 'Colour'"), std::string::npos) << e.what();
}

TEST(ParameterDistribution, DeterministicRangesSetsAndValueSetsAreRead) {
  const auto dir = emrm::test::scratch_dir("openscenario", "distribution");
  const auto file = write_file(dir / "distribution.xosc", R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="3" date="2026-01-01T00:00:00" description="d" author="emrm"/>
  <ParameterValueDistribution>
    <ScenarioFile filepath="scenario.xosc"/>
    <Deterministic>
      <DeterministicSingleParameterDistribution parameterName="EgoSpeed">
        <DistributionRange stepWidth="0.5"><Range lowerLimit="1" upperLimit="3"/></DistributionRange>
      </DeterministicSingleParameterDistribution>
      <DeterministicSingleParameterDistribution parameterName="Weather">
        <DistributionSet><Element value="dry"/><Element value="wet"/></DistributionSet>
      </DeterministicSingleParameterDistribution>
      <DeterministicMultiParameterDistribution>
        <ValueSetDistribution>
          <ParameterValueSet><ParameterAssignment parameterRef="A" value="1"/><ParameterAssignment parameterRef="B" value="2"/></ParameterValueSet>
          <ParameterValueSet><ParameterAssignment parameterRef="A" value="3"/><ParameterAssignment parameterRef="B" value="4"/></ParameterValueSet>
        </ValueSetDistribution>
      </DeterministicMultiParameterDistribution>
    </Deterministic>
  </ParameterValueDistribution>
</OpenSCENARIO>
)");
  const ParameterDistribution d = load_parameter_distribution(file);
  EXPECT_EQ(d.scenario_file, dir / "scenario.xosc");
  ASSERT_EQ(d.single.size(), 2U);
  EXPECT_EQ(d.single[0].parameter, "EgoSpeed");
  const auto& range = std::get<ValueRange>(d.single[0].values);
  EXPECT_EQ(range.values(), (std::vector<double>{1.0, 1.5, 2.0, 2.5, 3.0}));
  EXPECT_EQ(std::get<std::vector<std::string>>(d.single[1].values), (std::vector<std::string>{"dry", "wet"}));
  ASSERT_EQ(d.multi.size(), 1U);
  ASSERT_EQ(d.multi[0].sets.size(), 2U);
  EXPECT_EQ(d.multi[0].sets[1].at("B"), "4");
}

TEST(ParameterDistribution, AStochasticDistributionIsNotSupported) {
  const auto dir = emrm::test::scratch_dir("openscenario", "stochastic");
  const std::string text = R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="3" date="2026-01-01T00:00:00" description="d" author="emrm"/>
  <ParameterValueDistribution>
    <ScenarioFile filepath="scenario.xosc"/>
    <Stochastic numberOfTestRuns="10" randomSeed="1">
      <StochasticDistribution parameterName="EgoSpeed"><UniformDistribution><Range lowerLimit="1" upperLimit="3"/></UniformDistribution></StochasticDistribution>
    </Stochastic>
  </ParameterValueDistribution>
</OpenSCENARIO>
)";
  const auto file = write_file(dir / "distribution.xosc", text);
  const InputError e = emrm::testing::input_error_of([&] { (void)load_parameter_distribution(file); }, text);
  EXPECT_NE(e.message().find("Stochastic is not supported"), std::string::npos) << e.what();
  EXPECT_EQ(e.where().line, 6);
  EXPECT_EQ(e.where().column, 5);
}

}  // namespace
}  // namespace emrm::openscenario
