#include "emrm/sim/scene.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "emrm/core/yaml.hpp"
#include "input_error.hpp"

namespace emrm::sim {
namespace scene_test {

using ::testing::HasSubstr;

const std::string kShippedScene = std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/scene.yaml";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// 1-based line and column of the first occurrence of `needle` in `text`.
std::pair<int, int> position_of(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  if (pos == std::string::npos) throw std::logic_error("not in text: " + needle);
  int line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < pos; ++i)
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  return {line, static_cast<int>(pos - line_start) + 1};
}

InputError parse_error(const std::string& text) {
  return emrm::testing::input_error_of([&] { (void)parse_scene_config(text, "scene.yaml"); }, text);
}

UsageError cell_error(const TJunctionCell& cell) {
  try {
    validate_cell(SceneConfig{}, cell);
  } catch (const UsageError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a UsageError";
  return UsageError("none");
}

TJunctionCell cell(double speed_kph, double ttc_s, double passage_m = 3.0, double truck_speed_kph = 10.0) {
  TJunctionCell c;
  c.speed_kph = speed_kph;
  c.ttc_s = ttc_s;
  c.passage_m = passage_m;
  c.truck_speed_kph = truck_speed_kph;
  return c;
}

// ---- defaults ------------------------------------------------------------------------------------

TEST(SceneConfig, DefaultsAreThoseOfDesignSection6) {
  const SceneConfig c;
  EXPECT_EQ(c.road.lane_width_m, 3.5);
  EXPECT_EQ(c.road.lanes, 2);
  EXPECT_EQ(c.road.shoulder_m, 1.5);
  EXPECT_EQ(c.road.drivable_min_y_m(), -5.0);
  EXPECT_EQ(c.road.drivable_max_y_m(), 3.5);
  EXPECT_EQ(c.road.ego_lane_center_m, -1.75);
  EXPECT_EQ(c.truck.length_m, 10.0);
  EXPECT_EQ(c.truck.width_m, 2.5);
  EXPECT_EQ(c.truck.mass_kg, 12000.0);
  EXPECT_EQ(c.truck.speed_kph, 10.0);
  EXPECT_EQ(c.truck.decel_mps2, 4.0);
  EXPECT_EQ(c.ego.length_m, 4.508);
  EXPECT_EQ(c.ego.width_m, 1.610);
  EXPECT_EQ(c.ego.mass_kg, 1093.0);
  EXPECT_EQ(c.ego.yaw_inertia_kgm2, 1792.0);
  EXPECT_EQ(c.ego.cg_to_front_axle_m, 1.156);
  EXPECT_EQ(c.ego.cg_to_rear_axle_m, 1.423);
  EXPECT_EQ(c.ego.cg_height_m, 0.575);
  EXPECT_EQ(c.ego.max_steer_rad, 0.6);
  EXPECT_EQ(c.ego.max_steer_rate_radps, 0.8);
  // Not CommonRoad's 130 000 (a neutral car): softened for 2.2 deg/g of understeer (docs/physics.md).
  EXPECT_EQ(c.ego.front_cornering_stiffness_n_per_rad, 70000.0);
  EXPECT_EQ(c.ego.rear_cornering_stiffness_n_per_rad, 105000.0);
  EXPECT_EQ(c.simulation.vehicle_model, "single_track_fiala");
  EXPECT_EQ(c.simulation.dt_s, 0.01);
  EXPECT_EQ(c.actuation.perception_latency_s, 0.0);
  EXPECT_EQ(c.severity.restitution, 0.0);
  EXPECT_EQ(c.severity.mais3_intercept, 4.591);
  EXPECT_EQ(c.severity.mais3_slope_per_mps, 0.185);
  EXPECT_EQ(c.severity.fatal_reference_mps, 31.74);
  EXPECT_EQ(c.severity.fatal_exponent, 4.0);
  EXPECT_EQ(c.severity.l6_p_mais3, 0.10);
  EXPECT_EQ(c.severity.l7_p_fatal, 0.10);
  EXPECT_EQ(c.max_initial_distance_m, 24.5);
}

// ---- feasibility ---------------------------------------------------------------------------------

TEST(Scene, PaperGridHasExactly1165FeasibleCells) {
  const SceneConfig config;
  int feasible = 0, cells = 0;
  for (int speed_kph = 30; speed_kph <= 72; ++speed_kph)
    for (int k = 0; k <= 45; ++k) {
      ++cells;
      feasible += Scene(config, cell(speed_kph, 0.25 + 0.06 * k)).feasible();
    }
  EXPECT_EQ(cells, 43 * 46);
  EXPECT_EQ(feasible, 1165);
}

TEST(Scene, InitialDistanceIsSpeedTimesTtc) {
  const SceneConfig config;
  const Scene scene(config, cell(72.0, 1.0));
  EXPECT_DOUBLE_EQ(scene.initial_speed_mps(), 20.0);
  EXPECT_DOUBLE_EQ(scene.initial_distance_m(), 20.0);
  EXPECT_TRUE(Scene(config, cell(49.0, 1.8)).feasible());  // 24.5 m, on the limit
  EXPECT_FALSE(Scene(config, cell(49.0, 1.81)).feasible());
}

// ---- the truck -----------------------------------------------------------------------------------

TEST(Scene, TruckStopsWithItsFrontExactlyPassageAboveTheRoadEdge) {
  const SceneConfig config;
  for (const double passage : {0.5, 1.0, 2.2, 3.0}) {
    for (const double truck_kph : {0.0, 5.0, 10.0, 20.0}) {
      const Scene scene(config, cell(50.0, 1.0, passage, truck_kph));
      const double stop_s = truck_kph / 3.6 / config.truck.decel_mps2;
      EXPECT_NEAR(scene.truck_front_y_at(stop_s), -5.0 + passage, 1e-12);
      EXPECT_NEAR(scene.truck_front_y_at(stop_s + 10.0), -5.0 + passage, 1e-12);
      // Still creeping before the stop: the gap is wider.
      if (truck_kph > 0) {
        EXPECT_GT(scene.truck_front_y_at(stop_s / 2), -5.0 + passage);
      }
      // v²/(2a) above it at t = 0.
      const double v = truck_kph / 3.6;
      EXPECT_NEAR(scene.truck_front_y_at(0.0), -5.0 + passage + v * v / (2 * config.truck.decel_mps2), 1e-12);
    }
  }
}

TEST(Scene, WithoutBrakingTheGapAtTtcIsThePassage) {
  SceneConfig config;
  config.truck.decel_mps2 = 0.0;
  for (const double ttc : {0.25, 1.0, 2.95}) {
    const Scene scene(config, cell(40.0, ttc, 1.5, 12.0));
    EXPECT_NEAR(scene.truck_front_y_at(ttc), -5.0 + 1.5, 1e-12);
    EXPECT_NEAR(scene.hazard_at(ttc + 1.0).velocity_mps.y, -12.0 / 3.6, 1e-12);  // it keeps going
    EXPECT_LT(scene.truck_front_y_at(ttc + 1.0), -5.0 + 1.5);
  }
}

TEST(Scene, TruckNeverMovesBackAndItsSpeedIsTheSlopeOfItsPosition) {
  const SceneConfig config;
  const Scene scene(config, cell(50.0, 1.0, 2.0, 15.0));
  const double h = 1e-6;
  double previous = scene.truck_front_y_at(0.0);
  for (double t = 0.0; t <= 4.0; t += 0.01) {
    const double y = scene.truck_front_y_at(t);
    EXPECT_LE(y, previous) << "t = " << t;
    previous = y;
    const auto truck = scene.hazard_at(t);
    EXPECT_LE(truck.velocity_mps.y, 0.0);
    EXPECT_EQ(truck.velocity_mps.x, 0.0);
    const double slope =
        (scene.truck_front_y_at(t + h) - scene.truck_front_y_at(std::max(t - h, 0.0))) / (t + h - std::max(t - h, 0.0));
    EXPECT_NEAR(truck.velocity_mps.y, slope, 1e-4) << "t = " << t;
  }
  EXPECT_NEAR(scene.hazard_at(0.0).velocity_mps.y, -15.0 / 3.6, 1e-12);
  EXPECT_EQ(scene.hazard_at(4.0).velocity_mps.y, 0.0);
}

TEST(Scene, TruckBoxSpansFromItsNearSideAtTheInitialDistance) {
  const SceneConfig config;
  const Scene scene(config, cell(36.0, 1.5));  // d = 15 m
  const auto truck = scene.hazard_at(0.3);
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& p : truck.box.corners()) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  EXPECT_NEAR(min_x, 15.0, 1e-12);
  EXPECT_NEAR(max_x, 17.5, 1e-12);
  EXPECT_NEAR(scene.passed_x_m(), 17.5, 1e-12);
  EXPECT_NEAR(min_y, scene.truck_front_y_at(0.3), 1e-12);
  EXPECT_NEAR(max_y - min_y, 10.0, 1e-12);
  EXPECT_NEAR(truck.box.heading_rad, -std::numbers::pi / 2, 1e-15);
  // Its front is the end it drives towards.
  EXPECT_NEAR(truck.box.corners()[0].y, min_y, 1e-12);
}

// ---- the ego -------------------------------------------------------------------------------------

TEST(Scene, EgoStartsWithItsFrontBumperAtTheOriginInItsLane) {
  const SceneConfig config;
  const Scene scene(config, cell(54.0, 1.0));
  const auto s = scene.ego_initial();
  EXPECT_DOUBLE_EQ(s.vx_mps, 15.0);
  EXPECT_EQ(s.vy_mps, 0.0);
  EXPECT_EQ(s.yaw_rad, 0.0);
  EXPECT_EQ(s.yaw_rate_radps, 0.0);
  EXPECT_DOUBLE_EQ(s.x_m, -config.ego.cg_to_front_m());
  const auto box = scene.ego_box(s);
  double max_x = -1e9, min_x = 1e9;
  for (const auto& p : box.corners()) {
    max_x = std::max(max_x, p.x);
    min_x = std::min(min_x, p.x);
  }
  EXPECT_NEAR(max_x, 0.0, 1e-12);
  EXPECT_NEAR(min_x, -4.508, 1e-12);
  EXPECT_NEAR(box.center.y, -1.75, 1e-12);
  EXPECT_TRUE(scene.on_drivable_area(box));
}

TEST(Scene, EgoBoxTurnsAboutTheCg) {
  const SceneConfig config;
  const Scene scene(config, cell(50.0, 1.0));
  VehicleState s;
  s.x_m = 3.0;
  s.y_m = -2.0;
  s.yaw_rad = std::numbers::pi / 2;  // facing +y: the front is cg_to_front above the CG
  const auto box = scene.ego_box(s);
  double max_y = -1e9, min_y = 1e9;
  for (const auto& p : box.corners()) {
    max_y = std::max(max_y, p.y);
    min_y = std::min(min_y, p.y);
  }
  EXPECT_NEAR(max_y, -2.0 + config.ego.cg_to_front_m(), 1e-12);
  EXPECT_NEAR(min_y, -2.0 - config.ego.cg_to_rear_m(), 1e-12);
}

TEST(Scene, DrivableAreaHoldsAllFourCornersWithinTheBand) {
  const SceneConfig config;
  const Scene scene(config, cell(50.0, 1.0));
  const double hw = 1.61 / 2, hl = 4.508 / 2;
  const auto at = [](double y, double heading) { return core::OrientedBox{{10.0, y}, heading, 4.508, 1.61}; };
  EXPECT_TRUE(scene.on_drivable_area(at(-5.0 + hw, 0.0)));  // touching the edge is still on it
  EXPECT_FALSE(scene.on_drivable_area(at(-5.0 + hw - 1e-3, 0.0)));
  EXPECT_TRUE(scene.on_drivable_area(at(3.5 - hw, 0.0)));
  EXPECT_FALSE(scene.on_drivable_area(at(3.5 - hw + 1e-3, 0.0)));
  EXPECT_TRUE(scene.on_drivable_area(at(-5.0 + hl + 1e-9, std::numbers::pi / 2)));
  EXPECT_FALSE(scene.on_drivable_area(at(-5.0 + hl - 1e-3, -std::numbers::pi / 2)));
  // Turned 30°: the lowest corner is hl·sin 30° + hw·cos 30° below the centre.
  const double reach = hl * 0.5 + hw * std::sqrt(3.0) / 2;
  EXPECT_TRUE(scene.on_drivable_area(at(-5.0 + reach + 1e-9, std::numbers::pi / 6)));
  EXPECT_FALSE(scene.on_drivable_area(at(-5.0 + reach - 1e-3, std::numbers::pi / 6)));
  EXPECT_FALSE(scene.on_drivable_area(at(-5.0 + reach - 1e-3, -std::numbers::pi / 6)));
}

// ---- loading -------------------------------------------------------------------------------------

// Keys of every mapping, recursively, as "a.b" paths.
void collect_keys(const YAML::Node& node, const std::string& prefix, std::set<std::string>& keys) {
  if (!node.IsMap()) return;
  for (const auto& entry : node) {
    const std::string key = prefix + entry.first.as<std::string>();
    keys.insert(key);
    collect_keys(entry.second, key + ".", keys);
  }
}

// Every key, each at its built-in default but for the actuation: the shipped scene is the
// production car (profiles/production.yaml), the built-in default instant (docs/decisions.md).
TEST(SceneLoad, ShippedSceneWritesOutEveryDefault) {
  auto loaded = load_scene_config(kShippedScene);
  EXPECT_FALSE(loaded.actuation.instant());
  loaded.actuation = {};
  EXPECT_EQ(to_yaml(loaded), to_yaml(SceneConfig{}));
  std::set<std::string> in_file, in_schema;
  collect_keys(YAML::LoadFile(kShippedScene), "", in_file);
  collect_keys(core::write_yaml(SceneConfig{}), "", in_schema);
  in_schema.insert("family");  // written only when not the T-junction (docs/decisions.md)
  EXPECT_EQ(in_file, in_schema);
}

TEST(SceneLoad, PartialFileKeepsTheOtherDefaults) {
  const auto c = parse_scene_config("truck:\n  decel_mps2: 0\nego:\n  mass_kg: 1500\n", "scene.yaml");
  EXPECT_EQ(c.truck.decel_mps2, 0.0);
  EXPECT_EQ(c.ego.mass_kg, 1500.0);
  EXPECT_EQ(c.truck.mass_kg, 12000.0);
  EXPECT_EQ(c.simulation.dt_s, 0.01);
}

TEST(SceneLoad, SavedSceneLoadsBackToTheSameYaml) {
  for (const std::string& text :
       {read_text(kShippedScene), std::string("name: other\nroad: {lanes: 3, shoulder_m: 0.25}\n"
                                              "truck: {decel_mps2: 0, speed_kph: 7.3}\n"
                                              "simulation: {vehicle_model: kinematic_bicycle, dt_s: 0.005}\n"
                                              "planner: {max_nodes: 1234, goal_bias: 0.05}\n")}) {
    const std::string saved = to_yaml(parse_scene_config(text, "scene.yaml"));
    EXPECT_EQ(to_yaml(parse_scene_config(saved, "saved.yaml")), saved);
  }
}

TEST(SceneLoad, MissingFileIsAnInputError) {
  EXPECT_THROW((void)load_scene_config("/nonexistent/scene.yaml"), InputError);
}

struct BadScene {
  std::string text;
  std::string at;  // where the error must point: the first occurrence of this text
  std::string says;
};

TEST(SceneLoad, BadInputNamesLineAndColumn) {
  const std::vector<BadScene> cases{
      {"road:\n  lanes: two\n", "two", "expected an integer"},
      {"truck:\n  mass: 1\n", "mass", "unknown field 'mass'"},
      {"road:\n  lane_width: 3\n", "lane_width", "unknown field"},
      {"colour: red\n", "colour", "unknown field"},
      {"ego:\n  mass_kg: -5\n", "-5", "ego.mass_kg: expected a mass in [50, 60000] kg for a road vehicle, got -5"},
      {"ego:\n  yaw_inertia_kgm2: 0\n", "0", "ego.yaw_inertia_kgm2"},
      {"ego:\n  front_cornering_stiffness_n_per_rad: 0\n", "0", "stiffness"},
      {"ego:\n  length_m: 2\n", "2", "wheelbase"},
      {"truck:\n  length_m: 0\n", "0", "truck.length_m"},
      {"truck:\n  speed_kph: -1\n", "-1", "truck.speed_kph: expected a value >= 0"},
      {"truck:\n  decel_mps2: -4\n", "-4", "truck.decel_mps2"},
      {"truck:\n  mass_kg: .nan\n", ".nan", "finite"},
      {"road:\n  lanes: 0\n", "0", "at least 1 lane"},
      {"road:\n  shoulder_m: -0.5\n", "-0.5", "road.shoulder_m"},
      {"road:\n  ego_lane_center_m: 3.0\n", "3.0", "does not fit on the drivable area"},
      {"road:\n  ego_lane_center_m: -4.5\n", "-4.5", "does not fit on the drivable area"},
      // The ego lane keeps its default but no longer fits: point at the road that changed.
      {"road:\n  lane_width_m: 2.0\n  shoulder_m: 0\n", "lane_width_m", "ego_lane_center_m"},
      {"simulation:\n  dt_s: 0\n", "0", "simulation.dt_s: expected a value in [0.0001, 0.1], got 0"},
      {"simulation:\n  dt_s: -0.01\n", "-0.01", "simulation.dt_s"},
      {"simulation:\n  horizon_s: 0\n", "0", "simulation.horizon_s"},
      {"simulation:\n  dt_s: 0.05\n  horizon_s: 0.02\n", "0.05", "no longer than the horizon"},
      // Older scenes: the latency has moved to the actuators, and the message says where.
      {"simulation:\n  latency_s: 0.25\n", "0.25", "'latency_s' has moved: write it as actuation.perception_latency_s"},
      {"actuation:\n  perception_latency_s: -0.1\n", "-0.1", "actuation.perception_latency_s"},
      {"actuation:\n  brake_dead_time_s: .nan\n", ".nan", "finite"},
      {"actuation:\n  brake_ramp_s: -1\n", "-1", "actuation.brake_ramp_s: expected a value >= 0"},
      {"actuation:\n  max_decel_mps2: -9\n", "-9", "actuation.max_decel_mps2"},
      {"actuation:\n  steer_dead_time_s: -0.05\n", "-0.05", "actuation.steer_dead_time_s"},
      {"actuation:\n  steer_time_constant_s: x\n", "x", "number"},
      {"actuation:\n  steer_lag_s: 0.1\n", "steer_lag_s", "unknown field 'steer_lag_s'"},
      {"simulation:\n  vehicle_model: unicycle\n", "unicycle", "unknown vehicle model 'unicycle'"},
      {"severity:\n  restitution: 1.5\n", "1.5", "severity.restitution"},
      {"planner:\n  min_duration_s: 0.5\n  max_duration_s: 0.2\n", "0.5", "min_duration_s <= max_duration_s"},
      {"planner:\n  goal_bias: 1.5\n", "1.5", "planner.goal_bias: expected a value in [0, 1]"},
      {"planner:\n  goal_bias: -0.1\n", "-0.1", "planner.goal_bias"},
      {"planner:\n  max_nodes: 0\n", "0", "at least 1 node"},
      {"max_initial_distance_m: 0\n", "0", "max_initial_distance_m"},
      {"road: 3\n", "3", "expected a mapping"},
  };
  for (const auto& c : cases) {
    const auto e = parse_error(c.text);
    const auto [line, column] = position_of(c.text, c.at);
    EXPECT_EQ(e.where().file, "scene.yaml") << c.text;
    EXPECT_EQ(e.where().line, line) << c.text << e.what();
    EXPECT_EQ(e.where().column, column) << c.text << e.what();
    EXPECT_THAT(e.message(), HasSubstr(c.says)) << c.text;
  }
}

TEST(SceneLoad, StoresWrittenBeforeTheActuatorsReadTheirLatencyAsThePerceptionLatency) {
  // A user's scene file with the old key is told where it went; a store's scene (written by an
  // older emrm) is read with its meaning kept.
  const std::string old_text = "simulation:\n  dt_s: 0.01\n  latency_s: 0.3\n";
  EXPECT_THROW((void)parse_scene_config(old_text, "scene.yaml"), InputError);
  const SceneConfig stored = parse_stored_scene_config(old_text, "results.sqlite (scene)");
  EXPECT_EQ(stored.actuation.perception_latency_s, 0.3);
  EXPECT_EQ(stored.simulation.dt_s, 0.01);
  EXPECT_TRUE(stored.actuation.instant());
  // A current store's scene reads as it is.
  SceneConfig current;
  current.actuation.brake_ramp_s = 0.2;
  EXPECT_EQ(parse_stored_scene_config(to_yaml(current), "store").actuation.brake_ramp_s, 0.2);
}

TEST(SceneLoad, UnknownVehicleModelListsTheKnownOnes) {
  const auto e = parse_error("simulation:\n  vehicle_model: unicycle\n");
  for (const auto& name : vehicle_model_names()) EXPECT_THAT(e.message(), HasSubstr(name));
}

TEST(SceneLoad, MalformedYamlNamesLineAndColumn) {
  const auto e = parse_error("name: x\nroad: {lanes: 2\ntruck: {}\n");
  EXPECT_EQ(e.where().file, "scene.yaml");
  EXPECT_GT(e.where().line, 0);
  EXPECT_GT(e.where().column, 0);
  EXPECT_THAT(e.message(), HasSubstr("malformed YAML"));
}

// ---- validation of scenes built in code ----------------------------------------------------------

core::ConfigError validate_error(const SceneConfig& config) {
  try {
    validate(config);
  } catch (const core::ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a ConfigError";
  return core::ConfigError("none", {}, "none");
}

struct BadField {
  std::string text;                        // the mistake in a scene file ...
  std::string at;                          // ... reported at the first occurrence of this text
  std::function<void(SceneConfig&)> edit;  // ... and the same mistake in code
  std::string path;
};

// Every kind of constraint and rule, once: the file and the code are held to the same rule, with
// the same words; the file's error stands at the field.
TEST(SceneValidate, ACodeBuiltSceneBreaksTheSameRuleWithTheSameWordsAsAFile) {
  const std::vector<BadField> cases{
      {"road:\n  lane_width_m: -1\n", "-1", [](SceneConfig& c) { c.road.lane_width_m = -1; }, "road.lane_width_m"},
      {"road:\n  lanes: 0\n", "0", [](SceneConfig& c) { c.road.lanes = 0; }, "road.lanes"},
      {"road:\n  shoulder_m: -0.5\n", "-0.5", [](SceneConfig& c) { c.road.shoulder_m = -0.5; }, "road.shoulder_m"},
      {"road:\n  ego_lane_center_m: 3.0\n", "3.0", [](SceneConfig& c) { c.road.ego_lane_center_m = 3.0; },
       "road.ego_lane_center_m"},
      {"truck:\n  mass_kg: 0\n", "0", [](SceneConfig& c) { c.truck.mass_kg = 0; }, "truck.mass_kg"},
      {"ego:\n  length_m: 2\n", "2", [](SceneConfig& c) { c.ego.length_m = 2; }, "ego.length_m"},
      {"ego:\n  max_steer_rad: 1.6\n", "1.6", [](SceneConfig& c) { c.ego.max_steer_rad = 1.6; }, "ego.max_steer_rad"},
      {"ego:\n  kinematic_blend_speed_mps: -1\n", "-1", [](SceneConfig& c) { c.ego.kinematic_blend_speed_mps = -1; },
       "ego.kinematic_blend_speed_mps"},
      {"simulation:\n  vehicle_model: unicycle\n", "unicycle",
       [](SceneConfig& c) { c.simulation.vehicle_model = "unicycle"; }, "simulation.vehicle_model"},
      {"simulation:\n  dt_s: 5\n", "5", [](SceneConfig& c) { c.simulation.dt_s = 5; }, "simulation.dt_s"},
      {"severity:\n  restitution: 1.5\n", "1.5", [](SceneConfig& c) { c.severity.restitution = 1.5; },
       "severity.restitution"},
      {"severity:\n  l7_p_fatal: 0\n", "0", [](SceneConfig& c) { c.severity.l7_p_fatal = 0; }, "severity.l7_p_fatal"},
      {"planner:\n  max_nodes: 0\n", "0", [](SceneConfig& c) { c.planner.max_nodes = 0; }, "planner.max_nodes"},
      {"planner:\n  min_duration_s: 0.5\n", "0.5", [](SceneConfig& c) { c.planner.min_duration_s = 0.5; },
       "planner.min_duration_s"},
      {"max_initial_distance_m: -3\n", "-3", [](SceneConfig& c) { c.max_initial_distance_m = -3; },
       "max_initial_distance_m"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    const InputError in_file = parse_error(c.text);
    const auto [line, column] = position_of(c.text, c.at);
    EXPECT_EQ(in_file.where().line, line) << in_file.what();
    EXPECT_EQ(in_file.where().column, column) << in_file.what();
    EXPECT_THAT(in_file.message(), ::testing::StartsWith(c.path + ": "));

    SceneConfig config;
    c.edit(config);
    const core::ConfigError in_code = validate_error(config);
    EXPECT_EQ(in_code.path().str(), c.path);
    EXPECT_EQ(in_code.message(), "scene: " + in_file.message());
    EXPECT_TRUE(in_code.where().file.empty());
    EXPECT_STREQ(in_code.what(), ("error: scene: " + in_file.message()).c_str());
  }
}

TEST(SceneValidate, DefaultsTheShippedSceneAndItsEditsThatStayInRangePass) {
  EXPECT_NO_THROW(validate(SceneConfig{}));
  EXPECT_NO_THROW(validate(load_scene_config(kShippedScene)));
  SceneConfig edited;
  edited.simulation.vehicle_model = "kinematic_bicycle";
  edited.truck.decel_mps2 = 0.0;
  edited.planner.goal_bias = 1.0;
  EXPECT_NO_THROW(validate(edited));
}

TEST(SceneValidate, EachPartValidatesOnItsOwnNamedAfterThePart) {
  const auto message = [](auto part, auto edit) {
    edit(part);
    try {
      validate(part);
    } catch (const core::ConfigError& e) {
      return std::string(e.message());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(RoadConfig{}, [](RoadConfig& r) { r.lanes = 0; }), "road: lanes: expected at least 1 lane, got 0");
  EXPECT_EQ(message(TruckConfig{}, [](TruckConfig& t) { t.width_m = 0; }),
            "truck: width_m: expected a value > 0, got 0");
  EXPECT_EQ(message(SimulationConfig{}, [](SimulationConfig& s) { s.horizon_s = -1; }),
            "simulation: horizon_s: expected a value in [0.0001, 60], got -1");
  EXPECT_EQ(message(SeverityConfig{}, [](SeverityConfig& s) { s.l6_p_mais3 = 2; }),
            "severity: l6_p_mais3: expected a probability in (0, 1], got 2");
  EXPECT_EQ(message(PlannerConfig{}, [](PlannerConfig& p) { p.goal_bias = -0.5; }),
            "planner: goal_bias: expected a value in [0, 1], got -0.5");
  EXPECT_EQ(message(VehicleParams{}, [](VehicleParams& p) { p.cg_height_m = 0; }),
            "vehicle: cg_height_m: expected a CG height in [0.1, 4] m for a road vehicle, got 0");
  EXPECT_EQ(message(RoadConfig{}, [](RoadConfig&) {}), "no error");
}

// ---- cells ---------------------------------------------------------------------------------------

TEST(ValidateCell, AcceptsTheOddCorners) {
  const SceneConfig config;
  EXPECT_NO_THROW(validate_cell(config, cell(30.0, 0.25, 1.0, 0.0)));
  EXPECT_NO_THROW(validate_cell(config, cell(72.0, 2.95, 8.5, 20.0)));  // passage as wide as the road
  TJunctionCell slippery = cell(50, 1);
  slippery.mu = 2.0;
  EXPECT_NO_THROW(validate_cell(config, slippery));
}

TEST(ValidateCell, RejectsEachFactorOutOfRangeByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Bad {
    std::function<void(TJunctionCell&)> edit;
    std::string says;
  };
  const std::vector<Bad> cases{
      {[](TJunctionCell& c) { c.speed_kph = -10; }, "speed_kph"},
      {[](TJunctionCell& c) { c.speed_kph = 0; }, "speed_kph"},
      {[&](TJunctionCell& c) { c.speed_kph = nan; }, "speed_kph"},
      {[&](TJunctionCell& c) { c.speed_kph = inf; }, "speed_kph"},
      {[](TJunctionCell& c) { c.ttc_s = 0; }, "ttc_s"},
      {[&](TJunctionCell& c) { c.ttc_s = nan; }, "ttc_s"},
      {[](TJunctionCell& c) { c.mu = 0; }, "0 < mu <= 2"},
      {[](TJunctionCell& c) { c.mu = -0.5; }, "mu"},
      {[](TJunctionCell& c) { c.mu = 2.01; }, "0 < mu <= 2"},
      {[&](TJunctionCell& c) { c.mu = nan; }, "mu"},
      {[](TJunctionCell& c) { c.truck_speed_kph = -1; }, "truck_speed_kph"},
      {[&](TJunctionCell& c) { c.truck_speed_kph = inf; }, "truck_speed_kph"},
      {[](TJunctionCell& c) { c.passage_m = 0; }, "passage_m"},
      {[&](TJunctionCell& c) { c.passage_m = nan; }, "passage_m"},
      {[](TJunctionCell& c) { c.passage_m = 8.51; }, "wider than the road"},
  };
  for (const auto& bad : cases) {
    TJunctionCell c;
    bad.edit(c);
    EXPECT_THAT(cell_error(c).what(), HasSubstr(bad.says));
  }
}

}  // namespace scene_test
}  // namespace emrm::sim
