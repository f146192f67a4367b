// An imported OpenSCENARIO scenario as the family "openscenario" (openscenario/family.hpp,
// docs/import.md): the example cut-in read as a scene, its factors, and its cells laid out at the
// threat onset on the motorway's drivable band.

#include "emrm/openscenario/family.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::openscenario {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

const std::string kExample = EMRM_SOURCE_DIR "/examples/openscenario";

std::vector<std::string> keys(const sim::FactorTable& table) {
  std::vector<std::string> out;
  for (const sim::Factor& f : table) out.push_back(f.key);
  return out;
}

TEST(ImportedFamily, AScenarioFileIsASceneWithEveryNumericParameterAFactorButTheEgosSpeed) {
  const Registration registration;
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/cut_in.xosc");
  EXPECT_EQ(scene.family, "openscenario");
  EXPECT_EQ(scene.openscenario.ego, "Ego");
  EXPECT_EQ(scene.ego.length_m, 4.5);
  EXPECT_EQ(scene.ego.width_m, 1.8);
  // The ego's Init speed is $EgoSpeed: speed_kph sets it, and its default is the declared value.
  EXPECT_EQ(scene.openscenario.speed_parameter, "EgoSpeed");
  const sim::FactorTable factors = sim::scenario_factors(scene);
  EXPECT_THAT(keys(factors),
              ElementsAre("speed_kph", "ttc_s", "mu", "RelativeSpeed", "LaneChangeTime", "CutInGap", "TargetDecel"));
  EXPECT_NEAR(factors[0].default_value, 27.7778 * 3.6, 1e-9);
  // Each factor's unit is that of the attributes it is ($name); RelativeSpeed is only used in an
  // expression, so it has none.
  std::vector<std::string> units;
  for (const sim::ImportedFactor& f : scene.openscenario.factors) units.push_back(f.unit);
  EXPECT_THAT(units, ElementsAre("1", "s", "m", "m/s2"));
}

TEST(ImportedFamily, ASceneFileChoosesTheFactorsAndTheSpeedParameter) {
  const Registration registration;
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/scene.yaml");
  const sim::FactorTable factors = sim::scenario_factors(scene);
  EXPECT_THAT(keys(factors), ElementsAre("speed_kph", "ttc_s", "mu", "RelativeSpeed", "LaneChangeTime"));
  EXPECT_NEAR(factors[0].default_value, 27.7778 * 3.6, 1e-9);  // EgoSpeed, in km/h
  EXPECT_NEAR(factors[3].default_value, 5.5556, 1e-12);
  EXPECT_TRUE(factors[4].accepts(0.5));
  EXPECT_FALSE(factors[4].accepts(0.49));
  EXPECT_TRUE(std::filesystem::path(scene.openscenario.file).is_absolute());
}

TEST(ImportedFamily, ImportChoosesTheFactorsAmongTheDeclaredNumericParameters) {
  const Registration registration;
  // The ego's speed parameter is speed_kph's whether --factors names it or not.
  const sim::SceneConfig scene = scene_of(kExample + "/cut_in.xosc", {.ego = "", .factors = {"CutInGap", "EgoSpeed"}});
  EXPECT_THAT(keys(sim::scenario_factors(scene)), ElementsAre("speed_kph", "ttc_s", "mu", "CutInGap"));
  try {
    (void)scene_of(kExample + "/cut_in.xosc", {.ego = "", .factors = {"Nope"}});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("--factors: 'Nope' is no numeric parameter the scenario declares"));
  }
}

TEST(ImportedFamily, ACellHandsOverAtTheOnsetOnTheMotorwaysDrivableBand) {
  const Registration registration;
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/scene.yaml");
  // 100 km/h, TTC 1.5 s, dry, 20 km/h slower, a 2 s lane change.
  const sim::CellInput cell{100.0, 1.5, 1.0, 20.0 / 3.6, 2.0};
  const sim::Scene s(scene, cell);
  ASSERT_TRUE(s.feasible()) << s.infeasible_reason();
  EXPECT_EQ(s.hazard().body().name, "CutIn");
  // The lanes -1 and -2 and the shoulder right of them, the border at the median left out: the
  // band is 8 m wide below the reference line, the ego centred in lane -2.
  EXPECT_NEAR(s.road().min_y_m, -8.0, 1e-9);
  EXPECT_NEAR(s.road().max_y_m, 0.0, 1e-9);
  EXPECT_NEAR(s.ego_initial().y_m, -5.625, 1e-6);
  EXPECT_NEAR(s.initial_speed_mps(), 100.0 / 3.6, 1e-9);
  // The car is ahead and drifting towards the ego's lane.
  const sim::ActorState car = s.hazard_at(0.0);
  EXPECT_GT(car.box.center.x, 0.0);
  EXPECT_LT(car.velocity_mps.y, 0.0);
  const sim::CellResult result = sim::simulate_cell(scene, cell, {});
  EXPECT_TRUE(result.feasible);
  EXPECT_GT(result.unmitigated.loss_level, 0);  // doing nothing hits the car
}

TEST(ImportedFamily, ACellWithoutAThreatIsInfeasibleAndSaysWhy) {
  const Registration registration;
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/scene.yaml");
  // The cutting car barely slower, the search too short to reach the cut-in.
  sim::SceneConfig short_search = scene;
  short_search.openscenario.onset_search_s = 1.0;
  const sim::Scene s(short_search, sim::CellInput{100.0, 0.5, 1.0, 0.5, 2.0});
  EXPECT_FALSE(s.feasible());
  EXPECT_THAT(s.infeasible_reason(), HasSubstr("stays above 0.5 s"));
}

TEST(ImportedFamily, ACellWhoseValuesTheStoryboardDoesNotTakeIsInfeasibleAndSaysWhy) {
  const Registration registration;
  // The scenario itself: its factors have no limits, so a cell may give a lane change of -1 s,
  // which the reader refuses for that cell only.
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/cut_in.xosc");
  const sim::FactorTable factors = sim::scenario_factors(scene);
  sim::CellInput cell = factors.defaults();
  cell[*factors.find("LaneChangeTime")] = -1.0;
  const sim::Scene s(scene, cell);
  EXPECT_FALSE(s.feasible());
  EXPECT_THAT(s.infeasible_reason(), HasSubstr("the scenario does not play with this cell's values"));
  EXPECT_THAT(s.infeasible_reason(), HasSubstr("cut_in.xosc:"));
  const sim::CellResult result = sim::simulate_cell(scene, cell, {});
  EXPECT_FALSE(result.feasible);
  // The declared values still play.
  EXPECT_TRUE(sim::Scene(scene, factors.defaults()).layout().infeasible.empty());
}

TEST(ImportedFamily, ANamedStoryboardElementIsTheHandOver) {
  const Registration registration;
  const sim::SceneConfig scene = sim::load_scene_config(kExample + "/scene.yaml");
  // A TTC of 3 s is reached while the car still drifts across; at the start of its braking it is in
  // the ego's lane, and the TTC no longer moves the hand-over.
  const sim::CellInput cell{100.0, 3.0, 1.0, 20.0 / 3.6, 2.0};
  const sim::Scene early(scene, cell);
  ASSERT_TRUE(early.feasible()) << early.infeasible_reason();
  EXPECT_LT(early.hazard_at(0.0).velocity_mps.y, -0.1);
  sim::SceneConfig braking = scene;
  braking.openscenario.handover = "BrakeEvent";
  const sim::Scene armed(braking, cell);
  ASSERT_TRUE(armed.feasible()) << armed.infeasible_reason();
  EXPECT_EQ(armed.hazard().body().name, "CutIn");
  EXPECT_NEAR(armed.hazard_at(0.0).velocity_mps.y, 0.0, 1e-6);
  EXPECT_LT(armed.hazard_at(0.5).velocity_mps.x, armed.hazard_at(0.0).velocity_mps.x);  // braking
  const sim::Scene later(braking, sim::CellInput{100.0, 0.5, 1.0, 20.0 / 3.6, 2.0});
  EXPECT_EQ(later.initial_distance_m(), armed.initial_distance_m());
  // An element that never starts within the search makes the cell infeasible, saying so.
  sim::SceneConfig never = braking;
  never.openscenario.onset_search_s = 0.5;
  const sim::Scene s(never, cell);
  EXPECT_FALSE(s.feasible());
  EXPECT_THAT(s.infeasible_reason(), HasSubstr("'BrakeEvent' (openscenario.handover) does not start"));
}

TEST(ImportedFamily, ASceneNamingWhatTheScenarioDoesNotHaveIsRefusedAtTheField) {
  const Registration registration;
  const auto dir = std::filesystem::temp_directory_path() / "emrm-imported-family-names";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& block) {
    const auto file = dir / "scene.yaml";
    std::ofstream(file) << "family: openscenario\nopenscenario:\n  file: " << kExample << "/cut_in.xosc\n" << block;
    return file;
  };
  const auto refused = [&](const std::string& block) {
    try {
      (void)sim::load_scene_config(write(block));
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "expected an InputError for " << block;
    return InputError({}, "none");
  };
  InputError e = refused("  handover: NoSuchEvent\n");
  EXPECT_THAT(e.message(), HasSubstr("'NoSuchEvent' is no storyboard element of cut_in.xosc"));
  EXPECT_EQ(e.where().line, 4);
  e = refused("  factors:\n    - {parameter: Nope}\n");
  EXPECT_THAT(e.message(), HasSubstr("'Nope' is no numeric parameter cut_in.xosc declares"));
  EXPECT_EQ(e.where().line, 5);
  e = refused("  speed_parameter: Speed\n");
  EXPECT_EQ(e.where().line, 4);
  EXPECT_NO_THROW((void)sim::load_scene_config(write("  handover: CutInLaneChange\n")));
}

}  // namespace
}  // namespace emrm::openscenario
