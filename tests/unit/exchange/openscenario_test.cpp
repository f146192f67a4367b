// The OpenSCENARIO/OpenDRIVE export (docs/openscenario.md): every file validates against the
// official XSDs (schemas/), and the geometry read back with libxml2 is the scene's: the main
// road's lane borders, the truck's stopped position and the passage beside it, the vehicles'
// reference points.

#include "emrm/exchange/openscenario.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <numbers>
#include <random>

#include "emrm/core/error.hpp"
#include "emrm/core/expression.hpp"
#include "emrm/core/text.hpp"
#include "emrm/exchange/ego_trajectory.hpp"
#include "emrm/exchange/opendrive.hpp"
#include "emrm/exchange/plan_export.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/termination.hpp"
#include "exchange/xml_support.hpp"

namespace emrm::exchange {
namespace openscenario_test {

using testing::Document;

constexpr double kCm = 0.01;

sim::TJunctionCell cell_of(double speed_kph, double ttc_s, double mu, double passage_m, double truck_kph) {
  return {speed_kph, ttc_s, mu, passage_m, truck_kph};
}

// A scene unlike the default: three lanes, a wider shoulder, another truck.
sim::SceneConfig odd_scene() {
  sim::SceneConfig c;
  c.road.lanes = 3;
  c.road.lane_width_m = 3.25;
  c.road.shoulder_m = 2.0;
  c.road.ego_lane_center_m = -3.25;
  c.truck.length_m = 12.0;
  c.truck.width_m = 2.55;
  c.truck.decel_mps2 = 3.0;
  return c;
}

// The main road's borders from road 1: the reference line's y, then the lanes' widths outwards.
struct Borders {
  double left_m = 0.0;               // top of the leftmost lane
  double right_driving_m = 0.0;      // bottom of the rightmost driving lane
  double right_paved_m = 0.0;        // bottom of the shoulder
  std::vector<double> lane_borders;  // every border from left to right
};

Borders borders_of(const Document& xodr) {
  const std::string road = "/OpenDRIVE/road[@id='1']";
  const double ref = xodr.number(road + "/planView/geometry/@y");
  EXPECT_NEAR(xodr.number(road + "/planView/geometry/@hdg"), 0.0, 1e-12);
  Borders b;
  double top = ref;
  for (const auto& w : xodr.all(road + "/lanes/laneSection/left/lane/width/@a")) top += std::stod(w);
  b.left_m = top;
  b.lane_borders.push_back(top);
  for (const auto& w : xodr.all(road + "/lanes/laneSection/left/lane/width/@a")) {
    top -= std::stod(w);
    b.lane_borders.push_back(top);
  }
  double bottom = ref;
  const auto types = xodr.all(road + "/lanes/laneSection/right/lane/@type");
  const auto widths = xodr.all(road + "/lanes/laneSection/right/lane/width/@a");
  EXPECT_EQ(types.size(), widths.size());
  b.right_driving_m = ref;
  for (std::size_t i = 0; i < widths.size(); ++i) {
    bottom -= std::stod(widths[i]);
    b.lane_borders.push_back(bottom);
    if (types[i] == "driving") b.right_driving_m = bottom;
  }
  b.right_paved_m = bottom;
  return b;
}

TEST(OpenDrive, LaneBordersAreTheScenesRoad) {
  for (const sim::SceneConfig& config : {sim::SceneConfig{}, odd_scene()}) {
    const Document xodr(opendrive_xml(config, cell_of(50, 1.2, 0.8, 3.0, 10)));
    const Borders b = borders_of(xodr);
    const auto& road = config.road;
    EXPECT_NEAR(b.left_m, road.drivable_max_y_m(), kCm);
    EXPECT_NEAR(b.right_driving_m, road.drivable_max_y_m() - road.lanes * road.lane_width_m, kCm);
    EXPECT_NEAR(b.right_paved_m, road.drivable_min_y_m(), kCm);
    // The ego's lane centre lies midway between two lane borders.
    bool found = false;
    for (std::size_t i = 0; i + 1 < b.lane_borders.size(); ++i)
      found |= std::abs(0.5 * (b.lane_borders[i] + b.lane_borders[i + 1]) - road.ego_lane_center_m) < kCm;
    EXPECT_TRUE(found) << "no lane centred on the ego's lane centre y = " << road.ego_lane_center_m;
    EXPECT_EQ(xodr.all("/OpenDRIVE/road[@id='1']/lanes/laneSection/right/lane[@type='shoulder']").size(), 1u);
    // The side road joins from the left at the truck's lane.
    EXPECT_NEAR(xodr.number("/OpenDRIVE/road[@id='3']/planView/geometry/@y"), road.drivable_max_y_m(), kCm);
    EXPECT_EQ(xodr.all("/OpenDRIVE/junction/connection").size(), 2u);
    EXPECT_EQ(xodr.all("/OpenDRIVE/road[@junction='100']").size(), 2u);
  }
}

// The connecting roads inside the junction name the lanes they join, so that an engine moving an
// entity along the lanes (esmini's default controller) finds the next road: road 4 each main-road
// lane to the same lane of roads 1 and 2, road 5 the side road's left lane to road 1's innermost
// left lane.
TEST(OpenDrive, ConnectingRoadsLinkTheirLanes) {
  for (const sim::SceneConfig& config : {sim::SceneConfig{}, odd_scene()}) {
    const Document xodr(opendrive_xml(config, cell_of(50, 1.2, 0.8, 3.0, 10)));
    const auto lanes_of = [&](int road) {
      return xodr.all(fmt::format("/OpenDRIVE/road[@id='{}']/lanes/laneSection/*/lane[@id!='0']/@id", road));
    };
    const auto through = lanes_of(4);
    ASSERT_EQ(through, lanes_of(1));
    ASSERT_EQ(through, lanes_of(2));
    for (const auto& id : through) {
      const std::string lane = fmt::format("/OpenDRIVE/road[@id='4']/lanes/laneSection/*/lane[@id='{}']/link", id);
      EXPECT_EQ(xodr.all(lane + "/predecessor/@id"), std::vector<std::string>{id});
      EXPECT_EQ(xodr.all(lane + "/successor/@id"), std::vector<std::string>{id});
    }
    const std::string turn = "/OpenDRIVE/road[@id='5']/lanes/laneSection/right/lane[@id='-1']/link";
    EXPECT_EQ(xodr.all(turn + "/predecessor/@id"), std::vector<std::string>{"1"});
    EXPECT_EQ(xodr.all(turn + "/successor/@id"), std::vector<std::string>{"1"});
    EXPECT_EQ(xodr.all("/OpenDRIVE/road[@id='3']/lanes/laneSection/left/lane/@id"), std::vector<std::string>{"1"});
    EXPECT_EQ(xodr.all("/OpenDRIVE/road[@id='1']/lanes/laneSection/left/lane[@id='1']/@type"),
              std::vector<std::string>{"driving"});
  }
}

// The truck's polyline, read back: the truck's centre at time t (its rear axle moved forward along
// its heading), linear between vertices as an engine interpolates it.
struct TruckPath {
  std::vector<double> t, x, y, h;
  [[nodiscard]] core::Vec2 center_at(double time, double back_m) const {
    std::size_t i = 0;
    while (i + 2 < t.size() && time > t[i + 1]) ++i;
    const double u = std::clamp((time - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0);
    const double heading = h[i] + u * (h[i + 1] - h[i]);
    return {x[i] + u * (x[i + 1] - x[i]) + back_m * std::cos(heading),
            y[i] + u * (y[i + 1] - y[i]) + back_m * std::sin(heading)};
  }
};

TruckPath truck_path_of(const Document& xosc, const std::function<double(const std::string&)>& value) {
  const std::string v = "//ManeuverGroup[Actors/EntityRef/@entityRef='Truck']//Polyline/Vertex";
  TruckPath p;
  for (const auto& [out, attribute] :
       {std::pair{&p.t, "/@time"}, std::pair{&p.x, "/Position/WorldPosition/@x"},
        std::pair{&p.y, "/Position/WorldPosition/@y"}, std::pair{&p.h, "/Position/WorldPosition/@h"}})
    for (const auto& text : xosc.all(v + attribute)) out->push_back(value(text));
  return p;
}

// The truck follows a timed trajectory of the scene's motion: at every vertex, and at every frame
// of a simulator stepping at the scene's dt in between, it is where the cell has it (a simulator
// integrating a SpeedAction its own way leaves it elsewhere: esmini v·dt/2 short).
TEST(OpenScenario, TruckTrajectoryIsTheScenesTruckAtEveryFrame) {
  sim::SceneConfig no_braking;
  no_braking.truck.decel_mps2 = 0.0;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> speed(20, 70), passage(1.0, 4.0), truck(3, 25);
  for (const sim::SceneConfig& config : {sim::SceneConfig{}, odd_scene(), no_braking}) {
    const double back = truck_reference_offset_m(config.truck, {});
    const double dt = config.simulation.dt_s;
    for (int k = 0; k < 6; ++k) {
      const double v = speed(rng);
      const double ttc = std::uniform_real_distribution<double>(0.2, config.max_initial_distance_m / (v / 3.6))(rng);
      const sim::TJunctionCell cell = cell_of(v, ttc, 0.8, passage(rng), truck(rng));
      const sim::Scene scene(config, cell);
      sim::CellOptions options;
      options.strategies = {"emergency_stop"};
      const sim::CellResult result = sim::simulate_cell(config, cell, options);
      const EgoTrajectory trajectory{result.strategies.front().strategy, result.strategies.front().path};
      for (const EgoTrajectory* with : {static_cast<const EgoTrajectory*>(nullptr), &trajectory}) {
        const Document xosc(openscenario_xml(config, cell, with, {}));
        const TruckPath p = truck_path_of(xosc, [](const std::string& text) { return std::stod(text); });
        ASSERT_GE(p.t.size(), 2u);
        EXPECT_EQ(p.t.front(), 0.0);
        const double end = xosc.number("/OpenSCENARIO/Storyboard/StopTrigger//SimulationTimeCondition/@value");
        EXPECT_GE(p.t.back(), end);
        for (std::size_t i = 0; i < p.t.size(); ++i) {
          const core::Vec2 c = p.center_at(p.t[i], back);
          const core::Vec2 expected = scene.hazard_at(p.t[i]).box.center;
          EXPECT_NEAR(c.x, expected.x, 1e-3) << "vertex " << i << " at " << p.t[i] << " s";
          EXPECT_NEAR(c.y, expected.y, 1e-3) << "vertex " << i << " at " << p.t[i] << " s";
          EXPECT_NEAR(p.h[i], -std::numbers::pi / 2.0, 1e-12);
        }
        for (int f = 0; f * dt <= end; ++f) {
          const double t = f * dt;
          EXPECT_NEAR(p.center_at(t, back).y, scene.hazard_at(t).box.center.y, 1e-3) << "frame at " << t << " s";
        }
      }
    }
  }
}

// The truck at rest, from the scenario: its initial reference point, speed and braking, and its
// bounding box around the reference point.
TEST(OpenScenario, TruckStopsWherePassageIsTheCells) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> speed(20, 70), passage(1.0, 4.0), truck(3, 20), mu(0.3, 1.2);
  for (const sim::SceneConfig& config : {sim::SceneConfig{}, odd_scene()}) {
    for (int k = 0; k < 10; ++k) {
      const double v = speed(rng);
      const double ttc = std::uniform_real_distribution<double>(0.2, config.max_initial_distance_m / (v / 3.6))(rng);
      const sim::TJunctionCell cell = cell_of(v, ttc, mu(rng), passage(rng), truck(rng));
      const Document xosc(openscenario_xml(config, cell, nullptr, ExportOptions{}));
      const Document xodr(opendrive_xml(config, cell));
      const std::string init = "/OpenSCENARIO/Storyboard/Init/Actions/Private[@entityRef='Truck']/PrivateAction";
      const double x0 = xosc.number(init + "/TeleportAction/Position/WorldPosition/@x");
      const double y0 = xosc.number(init + "/TeleportAction/Position/WorldPosition/@y");
      const double h = xosc.number(init + "/TeleportAction/Position/WorldPosition/@h");
      // At rest: the last vertex of the truck's trajectory.
      const std::string truck_path = "//ManeuverGroup[Actors/EntityRef/@entityRef='Truck']//Polyline/Vertex";
      const auto rest_y = xosc.all(truck_path + "/Position/WorldPosition/@y");
      ASSERT_GE(rest_y.size(), 2u);
      EXPECT_EQ(xosc.all(truck_path + "/@time").front(), "0");
      EXPECT_NEAR(std::stod(rest_y.front()), y0, 1e-9);
      const std::string box = "/OpenSCENARIO/Entities/ScenarioObject[@name='Truck']/Vehicle/BoundingBox";
      const double center_ahead = xosc.number(box + "/Center/@x");
      const double length = xosc.number(box + "/Dimensions/@length");
      const double width = xosc.number(box + "/Dimensions/@width");
      // Heading h: the box's centre is center_ahead along it, the front half a length further.
      const double front_y_at_rest = std::stod(rest_y.back()) + std::sin(h) * (center_ahead + length / 2.0);
      const double near_x = x0 + std::cos(h) * center_ahead - width / 2.0;
      const Borders b = borders_of(xodr);
      EXPECT_NEAR(front_y_at_rest - b.right_paved_m, cell.passage_m, kCm);
      EXPECT_NEAR(near_x, cell.speed_kph / 3.6 * cell.ttc_s, kCm);
      EXPECT_NEAR(xosc.number("//RoadCondition/@frictionScaleFactor"), cell.mu, 1e-12);
      // The ego: its rear axle, with the box placed so that the front bumper is at x = 0.
      const std::string ego = "/OpenSCENARIO/Storyboard/Init/Actions/Private[@entityRef='Ego']/PrivateAction";
      const std::string ego_box = "/OpenSCENARIO/Entities/ScenarioObject[@name='Ego']/Vehicle/BoundingBox";
      const double ego_front = xosc.number(ego + "/TeleportAction/Position/WorldPosition/@x") +
                               xosc.number(ego_box + "/Center/@x") + xosc.number(ego_box + "/Dimensions/@length") / 2.0;
      EXPECT_NEAR(ego_front, 0.0, kCm);
      EXPECT_NEAR(xosc.number(ego + "/TeleportAction/Position/WorldPosition/@y"), config.road.ego_lane_center_m, kCm);
    }
  }
}

TEST(OpenScenario, ExportedFilesValidateAgainstTheSchemas) {
  const sim::SceneConfig config;
  const sim::TJunctionCell cell = cell_of(50, 1.0, 0.7, 2.5, 10);
  EXPECT_EQ(testing::opendrive().errors_of(opendrive_xml(config, cell)), "");
  EXPECT_EQ(testing::opendrive().errors_of(opendrive_xml(odd_scene(), cell)), "");
  sim::SceneConfig one_lane;
  one_lane.road.lanes = 1;
  one_lane.road.ego_lane_center_m = 0.0;
  EXPECT_EQ(testing::opendrive().errors_of(opendrive_xml(one_lane, cell)), "");
  EXPECT_EQ(testing::openscenario().errors_of(openscenario_xml(config, cell, nullptr, {})), "");
  sim::SceneConfig no_braking;
  no_braking.truck.decel_mps2 = 0.0;
  EXPECT_EQ(testing::openscenario().errors_of(openscenario_xml(no_braking, cell, nullptr, {})), "");
  // With every strategy's executed trajectory, at the step and thinned.
  sim::CellOptions options;
  options.seed = 3;
  const sim::CellResult result = sim::simulate_cell(config, cell, options);
  for (const auto& o : result.strategies) {
    const EgoTrajectory trajectory{o.strategy, o.path};
    for (const double tolerance : {0.0, 0.02}) {
      ExportOptions export_options;
      export_options.tolerance_m = tolerance;
      const std::string xosc = openscenario_xml(config, cell, &trajectory, export_options);
      EXPECT_EQ(testing::openscenario().errors_of(xosc), "") << o.strategy;
      const Document doc(xosc);
      const std::string ego = "//ManeuverGroup[Actors/EntityRef/@entityRef='Ego']//Polyline/Vertex";
      const auto times = doc.all(ego + "/@time");
      ASSERT_GE(times.size(), 2u);
      const double dt = config.simulation.dt_s;
      EXPECT_EQ(std::stod(times.back()), ended_on_frame_grid(o.path, dt).back().t_s);
      if (tolerance == 0.0) {
        // Every vertex is the rear axle of a path point: back to the CG along the heading.
        const auto points = ended_on_frame_grid(sim::with_closed_form_stop(o.path, dt), dt);
        ASSERT_EQ(times.size(), points.size());
        const auto xs = doc.all(ego + "/Position/WorldPosition/@x");
        const auto ys = doc.all(ego + "/Position/WorldPosition/@y");
        const auto hs = doc.all(ego + "/Position/WorldPosition/@h");
        const double l_r = config.ego.cg_to_rear_axle_m;
        for (std::size_t k = 0; k < points.size(); ++k) {
          const double h = std::stod(hs[k]);
          EXPECT_NEAR(std::stod(times[k]), points[k].t_s, 1e-14);  // 15 significant digits
          EXPECT_NEAR(std::stod(xs[k]) + l_r * std::cos(h), points[k].state.x_m, 1e-9) << o.strategy << " " << k;
          EXPECT_NEAR(std::stod(ys[k]) + l_r * std::sin(h), points[k].state.y_m, 1e-9) << o.strategy << " " << k;
        }
      }
      EXPECT_EQ(doc.number("/OpenSCENARIO/Storyboard/StopTrigger//SimulationTimeCondition/@value"),
                std::stod(times.back()));
    }
  }
}

TEST(OpenScenario, PlanIsOneLogicalScenarioWithEveryConcreteOne) {
  const sim::SceneConfig config;
  scenario::ScenarioFile plan;
  plan.file = "scenarios.csv";
  plan.factors = {"speed_kph", "ttc_s", "mu", "passage_m"};
  plan.rows = {{"S1", "boundary", {30, 1.0, 0.6, 2.0}, "c", {}, {}, 1.0, 1, {"scenarios.csv", 2, 1}},
               {"S2", "pairs", {50, 1.0, 1.0, 3.0}, "c", {}, {}, 1.0, 2, {"scenarios.csv", 3, 1}},
               {"S3", "pairs", {50, 1.0, 0.3, 2.5}, "c", {}, {}, 1.0, 3, {"scenarios.csv", 4, 1}}};
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-osc-plan-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const PlanExport out = export_plan(dir, config, plan, {});
  EXPECT_EQ(out.scenarios, 3u);
  EXPECT_EQ(out.road_networks, 2u);  // S2 and S3 share v·TTC
  const auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string logical = read(dir / kScenarioFile);
  const std::string distribution = read(dir / kDistributionFile);
  EXPECT_EQ(testing::openscenario().errors_of(logical), "");
  EXPECT_EQ(testing::openscenario().errors_of(distribution), "");
  const Document d(distribution);
  EXPECT_EQ(d.all("//ParameterValueSet").size(), 3u);
  EXPECT_EQ(d.all("//ParameterValueSet[1]/ParameterAssignment/@parameterRef"),
            plan_parameter_names(sim::scenario_factors(sim::SceneConfig{})));
  const Document l(logical);
  EXPECT_EQ(l.all("/OpenSCENARIO/ParameterDeclarations/ParameterDeclaration/@name"),
            plan_parameter_names(sim::scenario_factors(sim::SceneConfig{})));
  // Every parameter it declares acts: an expression or a reference reads it (scenario_id, the
  // label of each value set, is the one that names rather than moves).
  for (const auto& name : l.all("/OpenSCENARIO/ParameterDeclarations/ParameterDeclaration/@name"))
    if (name != "scenario_id") {
      EXPECT_NE(logical.find("$" + name), std::string::npos) << name << " is declared, never read";
    }
  // Every road network named in the distribution was written and validates.
  for (const auto& file : d.all("//ParameterAssignment[@parameterRef='road_network']/@value")) {
    ASSERT_TRUE(std::filesystem::is_regular_file(dir / file)) << file;
    EXPECT_EQ(testing::opendrive().errors_of(read(dir / file)), "");
  }
  // An infeasible scenario names its row.
  plan.rows[1].values = {70, 3.0, 1.0, 3.0};
  try {
    (void)export_plan(dir / "bad", config, plan, {});
    FAIL() << "an infeasible scenario was exported";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 3);
    EXPECT_NE(std::string(e.what()).find("S2"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
  std::filesystem::remove_all(dir);
}

// The logical scenario's value of an attribute for one parameter set: a number, a parameter
// reference ($mu) or an expression (${$speed_kph / 3.6}), evaluated by muparser, whose syntax
// covers the arithmetic the export writes.
std::string evaluated(const std::string& text, const std::vector<std::string>& names,
                      const std::vector<double>& values) {
  if (text.empty() || text[0] != '$') return text;
  std::string body = text.rfind("${", 0) == 0 ? text.substr(2, text.size() - 3) : text.substr(1);
  body.erase(std::remove(body.begin(), body.end(), '$'), body.end());
  const core::Expression e(body, names, {"tjunction.xosc", 1, 1});
  return fmt::format("{}", e.evaluate(values));
}

// Every scenario of the distribution, substituted into the logical scenario, is the single-cell
// export of its cell: the same Init (positions, speeds, friction) to rounding.
TEST(OpenScenario, LogicalScenarioAtEachParameterSetIsTheConcreteScenario) {
  const sim::SceneConfig config = odd_scene();
  scenario::ScenarioFile plan;
  plan.file = "scenarios.csv";
  plan.factors = {"speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph"};
  std::mt19937_64 rng(5);
  for (int k = 0; k < 12; ++k) {
    const double v = std::uniform_real_distribution<double>(20, 80)(rng);
    const double ttc = std::uniform_real_distribution<double>(0.2, config.max_initial_distance_m / (v / 3.6))(rng);
    plan.rows.push_back({fmt::format("S{}", k),
                         "pairs",
                         {v, ttc, std::uniform_real_distribution<double>(0.2, 1.5)(rng),
                          std::uniform_real_distribution<double>(1.0, 4.0)(rng),
                          std::uniform_real_distribution<double>(0.0, 25.0)(rng)},
                         "c",
                         {},
                         {},
                         1.0,
                         1,
                         {"scenarios.csv", k + 2, 1}});
  }
  // One more at the first one's junction (same v·TTC), its truck starting higher on the side road.
  auto shared = plan.rows.front();
  shared.id = "S_shared";
  shared.values[3] = 4.5;
  shared.values[4] = 30.0;
  plan.rows.push_back(shared);
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-osc-logical-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  EXPECT_EQ(export_plan(dir, config, plan, {}).road_networks, plan.rows.size() - 1);
  const auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const Document logical(read(dir / kScenarioFile));
  const Document distribution(read(dir / kDistributionFile));
  const std::vector<std::string> names{"speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph"};
  const auto attributes = logical.all("/OpenSCENARIO/Storyboard/Init//@*");
  ASSERT_GT(attributes.size(), 10u);
  for (std::size_t k = 0; k < plan.rows.size(); ++k) {
    const auto& row = plan.rows[k];
    const sim::TJunctionCell cell{row.values[0], row.values[1], row.values[2], row.values[3], row.values[4]};
    const auto assigned = distribution.all(fmt::format("//ParameterValueSet[{}]/ParameterAssignment/@value", k + 1));
    ASSERT_EQ(assigned.size(), plan_parameter_names(sim::scenario_factors(sim::SceneConfig{})).size());
    std::vector<double> values;
    for (std::size_t i = 0; i < names.size(); ++i) values.push_back(std::stod(assigned[i]));
    const Document concrete(openscenario_xml(config, cell, nullptr, {}));
    const auto expected = concrete.all("/OpenSCENARIO/Storyboard/Init//@*");
    ASSERT_EQ(expected.size(), attributes.size());
    for (std::size_t a = 0; a < attributes.size(); ++a) {
      const std::string got = evaluated(attributes[a], names, values);
      const auto x = core::parse_finite_number(got);
      const auto y = core::parse_finite_number(expected[a]);
      if (x && y) {
        EXPECT_NEAR(*x, *y, 1e-9 * std::max(1.0, std::abs(*y))) << row.id << ": " << attributes[a];
      } else {
        EXPECT_EQ(got, expected[a]) << row.id;
      }
    }
    // Its truck's trajectory is the cell's truck at every vertex (the expressions clamp each
    // scenario's braking at its own standstill).
    const sim::Scene scene(config, cell);
    const double back = truck_reference_offset_m(config.truck, {});
    const TruckPath path =
        truck_path_of(logical, [&](const std::string& text) { return std::stod(evaluated(text, names, values)); });
    ASSERT_GE(path.t.size(), 2u);
    for (std::size_t i = 0; i < path.t.size(); ++i) {
      const core::Vec2 c = path.center_at(path.t[i], back);
      EXPECT_NEAR(c.x, scene.hazard_at(path.t[i]).box.center.x, 1e-6) << row.id << " vertex " << i;
      EXPECT_NEAR(c.y, scene.hazard_at(path.t[i]).box.center.y, 1e-6) << row.id << " vertex " << i;
    }
    // Its road network has the cell's junction, and a side road long enough for its truck.
    const Document road(read(dir / assigned[5]));
    const JunctionLayout layout = junction_layout(config, cell);
    EXPECT_NEAR(road.number("/OpenDRIVE/road[@id='3']/planView/geometry/@x"), layout.side_road_x_m, 1e-3) << row.id;
    // Numbers are written to 15 significant digits (core::readable_number): equal to within 1e-12 m.
    EXPECT_GE(road.number("/OpenDRIVE/road[@id='3']/@length"), layout.side_road_length_m - 1e-12) << row.id;
  }
  std::filesystem::remove_all(dir);
}

// Issue 40, 8: a cell's export declared the factors as parameters that no position read, so
// `esmini --param speed_kph=60` changed nothing. A concrete scenario now declares no parameter;
// the cell's values are its FileHeader's properties, and the positions are the cell's numbers.
TEST(OpenScenario, ACellDeclaresNoParameterItsPositionsIgnore) {
  const sim::SceneConfig config;
  const auto cell = cell_of(60, 1.3, 0.5, 2.0, 10);
  for (const bool with_trajectory : {false, true}) {
    std::unique_ptr<EgoTrajectory> trajectory;
    if (with_trajectory) {
      sim::CellOptions options;
      options.strategies = {"emergency_stop"};
      const auto o = sim::simulate_cell(config, cell, options).strategies.front();
      trajectory = std::make_unique<EgoTrajectory>(EgoTrajectory{o.strategy, o.path});
    }
    const std::string xosc = openscenario_xml(config, cell, trajectory.get(), {}, kRoadFile);
    EXPECT_EQ(testing::openscenario().errors_of(xosc), "");
    const Document d(xosc);
    EXPECT_TRUE(d.all("//ParameterDeclaration").empty());
    EXPECT_EQ(xosc.find('$'), std::string::npos) << "a reference to a parameter it does not declare";
    const auto names = d.all("/OpenSCENARIO/FileHeader/Properties/Property/@name");
    const auto values = d.all("/OpenSCENARIO/FileHeader/Properties/Property/@value");
    ASSERT_EQ(names.size(), values.size());
    std::map<std::string, std::string> property;
    for (std::size_t k = 0; k < names.size(); ++k) property[names[k]] = values[k];
    EXPECT_EQ(property["speed_kph"], "60");
    EXPECT_EQ(property["ttc_s"], "1.3");
    EXPECT_EQ(property["mu"], "0.5");
    EXPECT_EQ(property["road_network"], kRoadFile);
  }
}

// A simulator stepping at dt records the first frame at or after a trajectory's end with the speed
// of the step before (esmini): the export ends every trajectory on a frame. A run that ends at rest
// holds its pose one frame past that one (a frame that does not move); one that ends moving goes
// on at its final velocity and yaw rate to that frame; the path before is unchanged.
TEST(OpenScenario, TrajectoryEndsOnTheFrameGrid) {
  const sim::SceneConfig config;
  const double dt = config.simulation.dt_s;
  int at_rest = 0, moving = 0;
  for (const auto& cell : {cell_of(30, 2.0, 1.0, 3.5, 20), cell_of(50, 0.8, 0.6, 2.0, 0),
                           cell_of(65, 1.0, 0.5, 2.0, 20), cell_of(40, 0.8, 0.3, 3.5, 20)}) {
    for (const auto& o : sim::simulate_cell(config, cell, {}).strategies) {
      const auto path = sim::with_closed_form_stop(o.path, dt);
      const auto ended = ended_on_frame_grid(path, dt);
      ASSERT_GE(ended.size(), path.size());
      ASSERT_LE(ended.size(), path.size() + 1);
      for (std::size_t k = 0; k < path.size(); ++k) EXPECT_EQ(ended[k].t_s, path[k].t_s);
      const auto& last = path.back();
      const auto& end = ended.back();
      const double frames = end.t_s / dt;
      EXPECT_NEAR(frames, std::round(frames), 1e-6) << o.strategy << " ends at " << end.t_s << " s";
      const double first_frame = std::ceil(last.t_s / dt - 1e-6) * dt;
      if (last.state.speed_mps() < sim::kStoppedSpeed_mps) {
        ++at_rest;
        EXPECT_NEAR(end.t_s, std::max(first_frame, last.t_s) + dt, 1e-9) << o.strategy;
        EXPECT_EQ(end.state.x_m, last.state.x_m);
        EXPECT_EQ(end.state.y_m, last.state.y_m);
        EXPECT_EQ(end.state.yaw_rad, last.state.yaw_rad);
      } else if (ended.size() > path.size()) {
        ++moving;
        const double tau = end.t_s - last.t_s;
        EXPECT_GT(tau, 0.0);
        EXPECT_LT(tau, dt);
        EXPECT_NEAR(std::hypot(end.state.x_m - last.state.x_m, end.state.y_m - last.state.y_m),
                    last.state.speed_mps() * tau, 1e-9);
        EXPECT_NEAR(end.state.yaw_rad - last.state.yaw_rad, last.state.yaw_rate_radps * tau, 1e-12);
      }
    }
  }
  EXPECT_GT(at_rest, 0);
  EXPECT_GT(moving, 0);
}

TEST(OpenScenario, ThinningKeepsEveryDroppedPointWithinTheTolerance) {
  const sim::SceneConfig config;
  sim::CellOptions options;
  options.strategies = {"emergency_stop", "dodge"};
  const sim::CellResult result = sim::simulate_cell(config, cell_of(60, 1.2, 1.0, 3.0, 10), options);
  for (const auto& o : result.strategies) {
    for (const double tolerance : {0.001, 0.05}) {
      const auto kept = thin_path(o.path, tolerance);
      ASSERT_GE(kept.size(), 2u);
      EXPECT_LE(kept.size(), o.path.size());
      EXPECT_EQ(kept.front().t_s, o.path.front().t_s);
      EXPECT_EQ(kept.back().t_s, o.path.back().t_s);
      std::size_t j = 0;
      for (const auto& p : o.path) {
        while (j + 1 < kept.size() && kept[j + 1].t_s < p.t_s) ++j;
        const auto& a = kept[j];
        const auto& b = kept[std::min(j + 1, kept.size() - 1)];
        const double u = b.t_s > a.t_s ? (p.t_s - a.t_s) / (b.t_s - a.t_s) : 0.0;
        EXPECT_LE(std::hypot(a.state.x_m + u * (b.state.x_m - a.state.x_m) - p.state.x_m,
                             a.state.y_m + u * (b.state.y_m - a.state.y_m) - p.state.y_m),
                  tolerance + 1e-12);
      }
    }
  }
}

}  // namespace openscenario_test
}  // namespace emrm::exchange
