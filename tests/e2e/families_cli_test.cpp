// End-to-end: scenario families as a user meets them — `emrm families`, a scene of another family,
// its factors set by --factor, categorical factors by their levels.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace families_cli_test {

using ::testing::HasSubstr;

const std::string kHighway = std::string("--scene ") + EMRM_SOURCE_DIR + "/examples/highway_obstacle/scene.yaml";

TEST(FamiliesCli, ListsEveryShippedFamilyWithItsFactors) {
  const auto text = run_emrm("families");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("highway_obstacle: "));
  EXPECT_THAT(text.out, HasSubstr("obstacle one of truck, deer"));
  EXPECT_THAT(text.out, HasSubstr("default truck"));
  const auto json = run_emrm("families --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  std::vector<std::string> names;
  for (const auto& f : j["families"]) names.push_back(f["name"].get<std::string>());
  EXPECT_THAT(names, ::testing::IsSupersetOf({"tjunction", "highway_obstacle", "pedestrian_crossing", "cut_in"}));
  for (const auto& f : j["families"]) {
    if (f["name"] != "highway_obstacle") continue;
    EXPECT_FALSE(f["certificate"].get<bool>());
    ASSERT_EQ(f["factors"].size(), 6u);
    EXPECT_EQ(f["factors"][3]["key"], "obstacle");
    EXPECT_EQ(f["factors"][3]["levels"], nlohmann::json({"truck", "deer"}));
    EXPECT_FALSE(f["factors"][4].contains("levels"));
  }
}

TEST(FamiliesCli, SimulatesAHighwayCellWithADeer) {
  const auto r = run_emrm("simulate " + kHighway +
                          " --speed-kph 100 --ttc-s 1.2 --factor obstacle=deer --factor blocked_m=5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["family"], "highway_obstacle");
  EXPECT_EQ(j["input"]["obstacle"].get<double>(), 1.0);  // the level's index
  ASSERT_EQ(j["actors"].size(), 1u);
  EXPECT_EQ(j["actors"][0]["kind"], "animal");
  EXPECT_EQ(j["actors"][0]["name"], "deer");
  EXPECT_EQ(j["road"]["roadside"]["left"], "barrier");
  const auto text = run_emrm("simulate " + kHighway +
                             " --speed-kph 100 --ttc-s 1.2 --factor obstacle=deer --factor roadside=embankment");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("Cell: 100 km/h, TTC 1.2 s, mu 0.8, deer, blocked 6.25 m, embankment"));
}

TEST(FamiliesCli, BadFactorsExitTwoWithOneMessage) {
  const std::string cell = "simulate " + kHighway + " --speed-kph 100 --ttc-s 1.2 ";
  expect_bad_input(run_emrm(cell + "--factor obstacle=moose"), "obstacle is one of truck, deer, got 'moose'");
  expect_bad_input(run_emrm(cell + "--factor blocked_m=wide"), "blocked_m expects a finite number (m), got 'wide'");
  expect_bad_input(run_emrm(cell + "--factor blocked_m=nan"), "blocked_m expects a finite number");
  expect_bad_input(run_emrm(cell + "--factor blocked_m=11"), "blocked_m");
  expect_bad_input(run_emrm(cell + "--factor passage_m=2"), "has no factor 'passage_m'");
  expect_bad_input(run_emrm(cell + "--factor obstacle"), "expected KEY=VALUE");
  expect_bad_input(run_emrm(cell + "--factor obstacle=deer --factor obstacle=truck"), "given twice");
}

// A campaign over the highway family as a user writes one: its factors by their keys, the obstacle
// and the roadside by their levels' names; then every command that reads the store.
// Sweeps a campaign of 8 cells over a shipped example's scene (`grids`: its grids, in YAML) into a
// scratch folder, checks that `emrm verify` finds every claim holding and returns the results folder.
std::string swept_and_verified(const std::string& name, const std::string& example, const std::string& grids) {
  const auto dir = scratch_dir(name);
  std::ofstream(dir / "campaign.yaml") << "scene: " << EMRM_SOURCE_DIR << "/examples/" << example
                                       << "/scene.yaml\nseed: 1\n"
                                       << grids;
  const std::string out = (dir / "out").string();
  const auto sweep = run_emrm("sweep " + (dir / "campaign.yaml").string() + " -o " + out + " --threads 2");
  EXPECT_EQ(sweep.exit_code, 0) << sweep.err;
  EXPECT_THAT(sweep.out, HasSubstr("Swept 8 cells"));
  const auto verify = run_emrm("verify " + out);
  EXPECT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  EXPECT_THAT(verify.out, HasSubstr("All claims hold."));
  return out;
}

TEST(FamiliesCli, AHighwayCampaignSweepsVerifiesDiagnosesAndReports) {
  const std::string out = swept_and_verified("highway_campaign", "highway_obstacle", R"(grids:
  - name: contrast
    speed_kph: [80, 120]
    ttc_s: [0.8, 1.6]
    mu: 0.8
    obstacle: [truck, deer]
    blocked_m: 5
    roadside: embankment
)");
  ASSERT_FALSE(HasFailure());
  const auto diagnose = run_emrm("diagnose " + out);
  EXPECT_EQ(diagnose.exit_code, 0) << diagnose.err;
  EXPECT_THAT(diagnose.out,
              HasSubstr("0 analytically stoppable cells classified R; 0 G cells below the stop boundary"));
  const auto boundary = run_emrm("boundary " + out);
  EXPECT_EQ(boundary.exit_code, 0) << boundary.err;
  EXPECT_THAT(boundary.out, HasSubstr("every line is monotone in TTC"));
  const auto report = run_emrm("report " + out);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  // The maps are sliced by the levels' names.
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / "figures" / "map_contrast_obstacle_deer.svg"))
      << report.out;
}

// A pedestrian stepping out from behind a parked car: every actor in the JSON (the pedestrian, the
// parked car, the oncoming car), harm by impact speed, and a small campaign that sweeps and verifies.
TEST(FamiliesCli, APedestrianCrossingSimulatesSweepsAndVerifies) {
  const std::string scene = std::string(EMRM_SOURCE_DIR) + "/examples/pedestrian_crossing/scene.yaml";
  const auto one = run_emrm("simulate --scene " + scene + " --speed-kph 40 --ttc-s 0.9 --factor oncoming=car --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto j = nlohmann::json::parse(one.out);
  ASSERT_EQ(j["actors"].size(), 3u);
  EXPECT_EQ(j["actors"][0]["kind"], "pedestrian");
  EXPECT_EQ(j["actors"][2]["name"], "oncoming car");
  EXPECT_EQ(j["road"]["roadside"]["right"], "barrier");
  EXPECT_EQ(j["unmitigated"]["loss_level"], 7);  // 40 km/h into a pedestrian: P(fatal) above 10 %

  // At 25 km/h and TTC 0.5 s every strategy strikes the pedestrian, at L6: EMRM takes the strike of
  // the lowest risk, which is not the lowest Δv of the car's occupants; verify weighs the same way.
  const std::string out = swept_and_verified("pedestrian_campaign", "pedestrian_crossing", R"(grids:
  - name: crossing
    speed_kph: [25, 50]
    ttc_s: [0.5, 1.4]
    oncoming: [none, car]
)");
  ASSERT_FALSE(HasFailure());
  const auto diagnose = run_emrm("diagnose " + out);
  EXPECT_EQ(diagnose.exit_code, 0) << diagnose.out << diagnose.err;
}

// A car cutting in: the follower in the JSON, a cell that cannot be one said so, and a campaign
// that sweeps (also adaptively), verifies, diagnoses and draws its boundaries without the v·TTC stop
// boundary, which does not hold for it.
TEST(FamiliesCli, ACutInSimulatesSweepsAndVerifiesWithoutTheStopBoundary) {
  const std::string scene = std::string(EMRM_SOURCE_DIR) + "/examples/cut_in/scene.yaml";
  const auto one = run_emrm("simulate --scene " + scene + " --speed-kph 100 --ttc-s 1.0 --factor following=car --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto j = nlohmann::json::parse(one.out);
  ASSERT_EQ(j["actors"].size(), 2u);
  EXPECT_EQ(j["actors"][0]["name"], "cutting car");
  EXPECT_EQ(j["actors"][1]["name"], "following car");
  const auto slower =
      run_emrm("simulate --scene " + scene + " --speed-kph 30 --ttc-s 1 --factor relative_speed_kph=40");
  EXPECT_EQ(slower.exit_code, 0) << slower.err;
  EXPECT_THAT(slower.out, HasSubstr("Infeasible: the cutting car would be 40 km/h slower than the ego"));

  const std::string out = swept_and_verified("cut_in_campaign", "cut_in", R"(grids:
  - name: cut
    keep_trees: true
    speed_kph: [80, 120]
    ttc_s: [1.0, 2.5]
    following: [none, car]
)");
  ASSERT_FALSE(HasFailure());
  const auto diagnose = run_emrm("diagnose " + out);
  EXPECT_EQ(diagnose.exit_code, 0) << diagnose.out << diagnose.err;
  EXPECT_THAT(diagnose.out, HasSubstr("no analytic stop boundary in this scene's family"));
  const auto boundary = run_emrm("boundary " + out + " --no-figures");
  EXPECT_EQ(boundary.exit_code, 0) << boundary.err;
  // The trajectory grid draws the family's cells with every actor.
  const auto report = run_emrm("report " + out);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const auto grid_csv = std::filesystem::path(out) / "figures" / "trajectory_grid.csv";
  ASSERT_TRUE(std::filesystem::exists(grid_csv)) << report.out;
  std::ifstream csv(grid_csv);
  std::string header;
  std::getline(csv, header);
  EXPECT_THAT(header, HasSubstr("relative_speed_kph,lateral_speed_mps,target_decel_mps2,following"));
  const auto adaptive = run_emrm("sweep " + (std::filesystem::path(out).parent_path() / "campaign.yaml").string() +
                                 " --adaptive -o " + out + "_adaptive --threads 2");
  EXPECT_EQ(adaptive.exit_code, 0) << adaptive.err;
  EXPECT_EQ(run_emrm("verify " + out + "_adaptive").exit_code, 0);
  // The search takes five varied factors: a grid of six is refused before anything runs.
  const auto six = std::filesystem::path(out).parent_path() / "six.yaml";
  std::ofstream(six) << "scene: " << EMRM_SOURCE_DIR << R"(/examples/cut_in/scene.yaml
grids:
  - {name: six, speed_kph: [80, 120], ttc_s: [1, 2], mu: [0.5, 1], relative_speed_kph: [10, 20],
     lateral_speed_mps: [1, 2], following: [none, car]}
)";
  const auto refused = run_emrm("sweep " + six.string() + " --adaptive -o " + out + "_six");
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_THAT(refused.err, HasSubstr("this grid varies 6 (speed_kph, ttc_s, mu, relative_speed_kph, lateral_speed_mps, "
                                     "following)"));
}

TEST(FamiliesCli, AGridNamesALevelOrIsRefusedAtItsPlace) {
  const auto dir = scratch_dir("highway_bad_level");
  std::ofstream(dir / "campaign.yaml") << "scene: " << EMRM_SOURCE_DIR << "/examples/highway_obstacle/scene.yaml"
                                       << R"(
grids:
  - name: g
    speed_kph: 100
    ttc_s: 1
    obstacle: [truck, moose]
)";
  const auto r = run_emrm("sweep " + (dir / "campaign.yaml").string() + " -o " + (dir / "out").string());
  expect_bad_input(r, "campaign.yaml:6:23: error: expected one of the levels truck, deer, got 'moose'");
}

}  // namespace families_cli_test
}  // namespace emrm::e2e
