// The OpenSCENARIO/OpenDRIVE export of the families other than the T-junction (docs/openscenario.md,
// "Other families"): both files validate against the official XSDs, every actor is an entity of its
// kind that follows the cell's own motion (each vertex where Actor::at puts it), the ego starts where
// the scene starts it, and the road's lanes span the family's drivable area.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/exchange/opendrive.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/exchange/plan_export.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "exchange/xml_support.hpp"

namespace emrm::exchange {
namespace family_export_test {

using testing::Document;

struct Case {
  const char* example;
  std::vector<std::pair<const char*, const char*>> factors;  // besides speed and TTC
  double speed_kph;
  double ttc_s;
  std::vector<std::pair<std::string, std::string>> entities;  // name, element (Vehicle, Pedestrian, ...)
};

sim::SceneConfig scene_of(const Case& c) {
  return sim::load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/" + c.example + "/scene.yaml");
}

sim::CellInput cell_of(const sim::SceneConfig& config, const Case& c) {
  const sim::FactorTable factors = sim::scenario_factors(config);
  sim::CellInput cell = factors.defaults();
  cell[sim::kEgoSpeedFactor] = c.speed_kph;
  cell[sim::kTtcFactor] = c.ttc_s;
  for (const auto& [key, value] : c.factors) cell[*factors.find(key)] = factors[*factors.find(key)].parse(value);
  factors.validate(cell);
  return cell;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all{
      {"highway_obstacle", {{"obstacle", "deer"}}, 100, 1.2, {{"Deer", "Pedestrian"}}},
      {"highway_obstacle", {{"obstacle", "truck"}}, 100, 1.2, {{"Truck", "Vehicle"}}},
      {"pedestrian_crossing",
       {{"oncoming", "car"}},
       40,
       1.0,
       {{"Pedestrian", "Pedestrian"}, {"ParkedCar", "Vehicle"}, {"OncomingCar", "Vehicle"}}},
      {"cut_in", {{"following", "car"}}, 100, 1.5, {{"CuttingCar", "Vehicle"}, {"FollowingCar", "Vehicle"}}},
  };
  return all;
}

TEST(FamilyExport, EveryActorFollowsTheCellsMotionAndTheFilesValidate) {
  for (const Case& c : cases()) {
    const sim::SceneConfig config = scene_of(c);
    const sim::CellInput cell = cell_of(config, c);
    const sim::Scene scene(config, cell);
    const sim::CellResult result = sim::simulate_cell(config, cell, {});
    const EgoTrajectory trajectory{result.strategies.back().strategy, result.strategies.back().path};
    const std::string xosc = openscenario_xml(config, cell, &trajectory, {}, road_file_of(config));
    EXPECT_EQ(testing::openscenario().errors_of(xosc), "") << c.example;
    const Document doc(xosc);
    ASSERT_EQ(c.entities.size(), scene.actors().size()) << c.example;
    for (std::size_t a = 0; a < c.entities.size(); ++a) {
      const auto& [name, element] = c.entities[a];
      const sim::Actor& actor = scene.actors()[a];
      const std::string object = "//Entities/ScenarioObject[@name='" + name + "']/" + element;
      EXPECT_EQ(doc.number(object + "/@mass"), actor.body().mass_kg) << name;
      EXPECT_EQ(doc.number(object + "/BoundingBox/Dimensions/@length"), actor.body().length_m) << name;
      if (actor.body().kind == sim::ActorKind::kAnimal) {
        EXPECT_EQ(doc.all(object + "/@pedestrianCategory"), std::vector<std::string>{"animal"});
      }
      // Every vertex of its trajectory is the cell's actor at the vertex's time.
      const std::string vertex = "//ManeuverGroup[Actors/EntityRef/@entityRef='" + name + "']//Polyline/Vertex";
      const auto times = doc.all(vertex + "/@time");
      const auto xs = doc.all(vertex + "/Position/WorldPosition/@x");
      const auto ys = doc.all(vertex + "/Position/WorldPosition/@y");
      if (actor.motion().speed_mps > 0.0 || a == 0) {
        ASSERT_GE(times.size(), 2u) << name;
      }
      for (std::size_t k = 0; k < times.size(); ++k) {
        const sim::ActorState at = actor.at(std::stod(times[k]));
        EXPECT_NEAR(std::stod(xs[k]), at.box.center.x, 1e-9) << name << " at " << times[k];
        EXPECT_NEAR(std::stod(ys[k]), at.box.center.y, 1e-9) << name << " at " << times[k];
      }
      // Between two vertices it moves on a straight line at one speed: half-way it is half-way.
      for (std::size_t k = 0; k + 1 < times.size(); ++k) {
        const double t0 = std::stod(times[k]), t1 = std::stod(times[k + 1]);
        const sim::ActorState mid = actor.at((t0 + t1) / 2.0);
        EXPECT_NEAR(mid.box.center.x, (actor.at(t0).box.center.x + actor.at(t1).box.center.x) / 2.0, 1e-3)
            << name << " between " << t0 << " and " << t1;
      }
    }
    // The ego starts where the scene starts it: its front bumper at x = 0 in its lane.
    const std::string ego = "//Init//Private[@entityRef='Ego']/PrivateAction";
    EXPECT_NEAR(doc.number(ego + "/TeleportAction/Position/WorldPosition/@x") + config.ego.cg_to_rear_axle_m,
                scene.ego_initial().x_m, 1e-9);
    EXPECT_NEAR(doc.number(ego + "/TeleportAction/Position/WorldPosition/@y"), scene.ego_initial().y_m, 1e-9);

    // The road: valid, its lanes spanning the drivable area from the reference line.
    const std::string xodr = straight_road_xml(config, cell);
    EXPECT_EQ(testing::opendrive().errors_of(xodr), "") << c.example;
    const Document road(xodr);
    const double reference_y = road.number("//planView/geometry/@y");
    double right = 0.0, left = 0.0;
    for (const auto& w : road.all("//laneSection/right/lane/width/@a")) right += std::stod(w);
    for (const auto& w : road.all("//laneSection/left/lane/width/@a")) left += std::stod(w);
    EXPECT_NEAR(reference_y - right, scene.road().min_y_m, 1e-9) << c.example;
    EXPECT_NEAR(reference_y + left, scene.road().max_y_m, 1e-9) << c.example;
    EXPECT_LT(road.number("//planView/geometry/@x"), scene.ego_initial().x_m);
  }
}

TEST(FamilyExport, FilesAreNamedByTheFamily) {
  const sim::SceneConfig config = scene_of(cases().back());
  EXPECT_EQ(road_file_of(config), "cut_in.xodr");
  EXPECT_EQ(scenario_file_of(config), "cut_in.xosc");
  EXPECT_EQ(road_file_of(sim::SceneConfig{}), kRoadFile);
}

// A plan of another family exports one concrete scenario per planned scenario, in a folder named by
// its id: each the single-cell export of its cell (with its id for scenario_id) beside its road;
// an infeasible scenario or an id that cannot name a folder is exit 2 at its row, nothing written.
TEST(FamilyExport, PlanExportsEachScenarioAsTheCellsDocument) {
  const sim::SceneConfig config = scene_of(cases().back());
  scenario::ScenarioFile plan;
  plan.file = "scenarios.csv";
  plan.factors = {"speed_kph", "ttc_s", "following"};
  plan.rows = {{"S1", "boundary", {100, 1.5, 1}, "c", {}, {}, 1.0, 1, {"scenarios.csv", 2, 1}},
               {"S-2.b", "pairs", {80, 2.0, 0}, "c", {}, {}, 1.0, 2, {"scenarios.csv", 3, 1}}};
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-family-plan-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const PlanExport out = export_plan(dir, config, plan, {});
  EXPECT_FALSE(out.logical);
  EXPECT_EQ(out.scenarios, 2u);
  EXPECT_EQ(out.files.size(), 4u);
  const auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const sim::FactorTable factors = sim::scenario_factors(config);
  for (const auto& row : plan.rows) {
    sim::CellInput cell = factors.defaults();
    for (std::size_t i = 0; i < plan.factors.size(); ++i) cell[*factors.find(plan.factors[i])] = row.values[i];
    const std::string xosc = read(dir / row.id / scenario_file_of(config));
    EXPECT_EQ(testing::openscenario().errors_of(xosc), "") << row.id;
    std::string expected = openscenario_xml(config, cell, nullptr, {}, road_file_of(config));
    const std::string cell_id = R"(<Property name="scenario_id" value="cell"/>)";
    ASSERT_NE(expected.find(cell_id), std::string::npos);
    expected.replace(expected.find(cell_id), cell_id.size(),
                     R"(<Property name="scenario_id" value=")" + row.id + "\"/>");
    EXPECT_EQ(xosc, expected) << row.id;
    EXPECT_EQ(read(dir / row.id / road_file_of(config)), straight_road_xml(config, cell)) << row.id;
  }
  std::filesystem::remove_all(dir);
  for (const std::string bad : {"../up", "a/b", "..", ""}) {
    auto hostile = plan;
    hostile.rows[1].id = bad;
    try {
      (void)export_plan(dir, config, hostile, {});
      FAIL() << "the id '" << bad << "' named a folder";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().line, 3) << bad;
    }
    EXPECT_FALSE(std::filesystem::exists(dir)) << bad;
  }
  plan.rows[1].values = {80, 0.0, 0};  // TTC 0: infeasible
  EXPECT_THROW((void)export_plan(dir, config, plan, {}), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace family_export_test
}  // namespace emrm::exchange
