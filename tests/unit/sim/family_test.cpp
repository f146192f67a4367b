// Scenario families (sim/family.hpp): a family registered from outside the library, named by a
// scene file and simulated like the shipped T-junction.

#include "emrm/sim/family.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "input_error.hpp"

namespace emrm::sim {
namespace {

using ::testing::HasSubstr;

// A toy family: a parked body (a static object) standing across the road from the left edge down to
// `passage_m` above the right edge, v·TTC ahead of the ego. Its factors are the T-junction's (the
// truck's speed unused: the body is parked), so that with the T-junction's truck at rest it lays out
// the very same scene from the same cells.
ScenarioFamilyInfo parked_body_family() {
  return {
      .name = "toy_parked_body",
      .description = "a test's family: a parked body across the road",
      .factors = [](const SceneConfig& config) { return find_family("tjunction")->factors(config); },
      .layout =
          [](const SceneConfig& config, const CellInput& cell) {
            SceneLayout out;
            const RoadConfig& road = config.road;
            out.road = {road.drivable_min_y_m(), road.drivable_max_y_m(), Roadside::kBarrier, Roadside::kBarrier};
            out.ego_y_m = road.ego_lane_center_m;
            out.initial_distance_m = cell.ego_speed_kph() / 3.6 * cell.time_to_collision_s();
            const TruckConfig& body = config.truck;
            out.actors.emplace_back(
                ActorBody{ActorKind::kStaticObject, body.length_m, body.width_m, body.mass_kg, body.yaw_inertia_kgm2},
                ActorMotion{.front = {out.initial_distance_m + body.width_m / 2.0, road.drivable_min_y_m() + cell[3]},
                            .direction = {0.0, -1.0}});
            out.passed_x_m = out.initial_distance_m + body.width_m;
            return out;
          }};
}

TEST(ScenarioFamily, TheTJunctionIsShipped) {
  const auto names = family_names();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "tjunction");
  EXPECT_EQ(SceneConfig{}.family, "tjunction");
  EXPECT_TRUE(find_family("tjunction")->tjunction_analytics);
}

TEST(ScenarioFamily, ARegistrationLastsAsLongAsItsObject) {
  {
    const FamilyRegistration toy(parked_body_family());
    const auto names = family_names();
    EXPECT_NE(std::find(names.begin(), names.end(), "toy_parked_body"), names.end());
    EXPECT_THROW(FamilyRegistration again(parked_body_family()), UsageError);
  }
  const auto names = family_names();
  EXPECT_EQ(std::find(names.begin(), names.end(), "toy_parked_body"), names.end());
  EXPECT_THROW((void)find_family("toy_parked_body"), UsageError);
}

TEST(ScenarioFamily, AFamilyNeedsItsFactorsAndItsLayout) {
  ScenarioFamilyInfo info = parked_body_family();
  info.layout = nullptr;
  EXPECT_THROW(FamilyRegistration bad(std::move(info)), UsageError);
}

TEST(ScenarioFamily, ASceneFileNamesItsFamily) {
  const FamilyRegistration toy(parked_body_family());
  const SceneConfig config = parse_scene_config("family: toy_parked_body\n", "toy.yaml");
  EXPECT_EQ(config.family, "toy_parked_body");
  EXPECT_EQ(scenario_factors(config).key_list(), "speed_kph, ttc_s, mu, passage_m, truck_speed_kph");
  EXPECT_THAT(to_yaml(config), HasSubstr("family: toy_parked_body"));
  // The T-junction's scenes are written as before families existed: stores keep their hashes.
  EXPECT_THAT(to_yaml(SceneConfig{}), ::testing::Not(HasSubstr("family")));
  EXPECT_EQ(parse_scene_config(to_yaml(config), "again.yaml").family, "toy_parked_body");
}

TEST(ScenarioFamily, AnUnknownFamilyIsRefusedWhereTheFileNamesIt) {
  const std::string text = "name: x\nfamily: highway\n";
  const InputError e = testing::input_error_of([&] { (void)parse_scene_config(text, "s.yaml"); }, text);
  EXPECT_EQ(e.where().line, 2);
  EXPECT_EQ(e.where().column, 9);
  EXPECT_THAT(e.what(), HasSubstr("unknown scenario family 'highway'"));
  EXPECT_THAT(e.what(), HasSubstr("tjunction"));
}

TEST(ScenarioFamily, ACellOfAnotherFamilyIsCheckedAgainstItsFactors) {
  const FamilyRegistration toy(parked_body_family());
  SceneConfig config;
  config.family = "toy_parked_body";
  EXPECT_NO_THROW(validate_cell(config, {50.0, 1.0, 1.0, 3.0, 0.0}));
  EXPECT_THROW(validate_cell(config, {50.0, 1.0, 1.0, 3.0}), UsageError);        // a factor short
  EXPECT_THROW(validate_cell(config, {50.0, 1.0, 1.0, 99.0, 0.0}), UsageError);  // wider than the road
}

// The toy's parked body is the T-junction's truck at rest: every strategy ends the same, to the
// bit; only the certificate differs (the toy has none, so an unavoidable cell stays undecided).
TEST(ScenarioFamily, AFamilyFromOutsideSimulatesAsTheSameSceneDoes) {
  const FamilyRegistration toy(parked_body_family());
  SceneConfig toy_config;
  toy_config.family = "toy_parked_body";
  const SceneConfig tjunction;
  CellOptions options;
  options.strengthen = false;
  for (const TJunctionCell c : {TJunctionCell{60.0, 1.6, 1.0, 3.0, 0.0}, TJunctionCell{50.0, 0.6, 0.8, 2.2, 0.0},
                                TJunctionCell{40.0, 1.0, 1.0, 3.2, 0.0}}) {
    SCOPED_TRACE(cell_text(scenario_factors(tjunction), c));
    const CellResult want = simulate_cell(tjunction, c, options);
    const CellResult got = simulate_cell(toy_config, c, options);
    ASSERT_EQ(got.strategies.size(), want.strategies.size());
    for (std::size_t i = 0; i < want.strategies.size(); ++i) {
      SCOPED_TRACE(want.strategies[i].strategy);
      EXPECT_EQ(got.strategies[i].avoided, want.strategies[i].avoided);
      EXPECT_EQ(got.strategies[i].contact, want.strategies[i].contact);
      EXPECT_EQ(got.strategies[i].impact.delta_v_mps, want.strategies[i].impact.delta_v_mps);
      EXPECT_EQ(got.strategies[i].path.size(), want.strategies[i].path.size());
    }
    if (want.evidence == Evidence::kCertificate) {
      EXPECT_EQ(got.evidence, Evidence::kUndecided);
      EXPECT_THAT(got.no_certificate, HasSubstr("scenario family 'toy_parked_body' has no certificate bound"));
    } else {
      EXPECT_EQ(got.region, want.region);
    }
  }
}

}  // namespace
}  // namespace emrm::sim
