// `emrm assess` (docs/openscenario.md): the trajectory a strategy executed, written as a recorded
// trajectory and judged again, gives the simulator's own outcome (avoided or not, loss level, Δv);
// esmini's CSV is read for positions and headings only (the CG's speed from its positions, no wheel
// angle); bad files name the line and column. The export replayed as esmini replays it:
// esmini_replay_test.cpp.

#include "emrm/exchange/assess.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::exchange {
namespace assess_test {

constexpr double kKphPerMps = 3.6;

std::string emrm_csv(const std::vector<sim::PathPoint>& path) {
  std::string out = "t,x,y,psi,v\n";
  for (const auto& p : path)
    out += fmt::format("{},{},{},{},{}\n", p.t_s, p.state.x_m, p.state.y_m, p.state.yaw_rad, p.state.speed_mps());
  return out;
}

void expect_same_outcome(const sim::StrategyOutcome& o, const Assessment& a, const std::string& what) {
  EXPECT_EQ(a.avoided, o.avoided) << what;
  EXPECT_EQ(a.contact, o.contact) << what;
  EXPECT_EQ(a.road_departure, o.road_departure) << what;
  EXPECT_EQ(a.impact.loss_level, o.impact.loss_level) << what;
  EXPECT_NEAR(a.impact.delta_v_mps * kKphPerMps, o.impact.delta_v_mps * kKphPerMps, 0.1) << what;
  EXPECT_NEAR(a.impact.impact_speed_mps * kKphPerMps, o.impact.impact_speed_mps * kKphPerMps, 0.1) << what;
  EXPECT_EQ(a.delta_loss, o.delta_loss) << what;
}

// Random cells over the ODD's ranges, every strategy: the executed trajectory judged again.
TEST(Assess, ExecutedTrajectoryGivesTheSimulatedOutcome) {
  const sim::SceneConfig config;
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> speed(25, 70), mu(0.3, 1.0), passage(1.5, 4.0), truck(5, 15);
  int contacts = 0, avoided = 0;
  for (int k = 0; k < 8; ++k) {
    const double v = speed(rng);
    const double ttc = std::uniform_real_distribution<double>(0.3, config.max_initial_distance_m / (v / 3.6))(rng);
    const sim::TJunctionCell cell{v, ttc, mu(rng), passage(rng), truck(rng)};
    sim::CellOptions options;
    options.seed = 11 + static_cast<std::uint64_t>(k);
    const sim::CellResult result = sim::simulate_cell(config, cell, options);
    for (const auto& o : result.strategies) {
      if (o.path.size() < 2) continue;
      const std::string what =
          fmt::format("seed {} cell {} km/h {} s mu {} passage {} truck {}: {}", options.seed, cell.speed_kph,
                      cell.ttc_s, cell.mu, cell.passage_m, cell.truck_speed_kph, o.strategy);
      const auto recorded = parse_trajectory_csv(emrm_csv(o.path), "emrm.csv", TrajectoryFormat::kEmrm, config);
      const Assessment a = assess(config, cell, recorded);
      expect_same_outcome(o, a, what + " (emrm CSV)");
      contacts += a.contact ? 1 : 0;
      avoided += a.avoided ? 1 : 0;
    }
  }
  // The cells exercise both ends of the judgement.
  EXPECT_GT(contacts, 0);
  EXPECT_GT(avoided, 0);
}

// Every family: the trajectory each strategy executed against the family's every actor (a deer, a
// pedestrian with an oncoming car, a car cutting in with one overtaking) judged again gives the same
// outcome, and a contact names the actor met.
TEST(Assess, EveryFamilysExecutedTrajectoryGivesTheSimulatedOutcome) {
  struct Case {
    const char* example;
    std::vector<std::pair<const char*, const char*>> factors;
    std::vector<std::pair<double, double>> speed_ttc;
  };
  const std::vector<Case> cases{
      {"highway_obstacle", {{"obstacle", "deer"}}, {{100, 1.2}, {130, 0.7}}},
      {"pedestrian_crossing", {{"oncoming", "car"}}, {{40, 1.0}, {50, 0.6}}},
      {"cut_in", {{"following", "car"}, {"target_decel_mps2", "8"}}, {{100, 1.5}, {120, 0.8}}},
  };
  int contacts = 0, avoided = 0;
  for (const Case& c : cases) {
    const sim::SceneConfig config =
        sim::load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/" + c.example + "/scene.yaml");
    const sim::FactorTable factors = sim::scenario_factors(config);
    for (const auto& [speed, ttc] : c.speed_ttc) {
      sim::CellInput cell = factors.defaults();
      cell[sim::kEgoSpeedFactor] = speed;
      cell[sim::kTtcFactor] = ttc;
      for (const auto& [key, value] : c.factors) cell[*factors.find(key)] = factors[*factors.find(key)].parse(value);
      const sim::CellResult result = sim::simulate_cell(config, cell, {});
      for (const auto& o : result.strategies) {
        if (o.path.size() < 2) continue;
        const std::string what = fmt::format("{} {} km/h TTC {} s: {}", c.example, speed, ttc, o.strategy);
        const auto recorded = parse_trajectory_csv(emrm_csv(o.path), "emrm.csv", TrajectoryFormat::kEmrm, config);
        const Assessment a = assess(config, cell, recorded);
        expect_same_outcome(o, a, what);
        if (a.contact) {
          EXPECT_FALSE(a.contact_with.empty()) << what;
        }
        contacts += a.contact ? 1 : 0;
        avoided += a.avoided ? 1 : 0;
      }
    }
  }
  EXPECT_GT(contacts, 0);
  EXPECT_GT(avoided, 0);
}

// A contact is found between samples: the same run thinned to a few vertices still touches.
TEST(Assess, FindsContactBetweenSamples) {
  const sim::SceneConfig config;
  const sim::TJunctionCell cell{60, 0.6, 1.0, 3.0, 10};
  const sim::Scene scene(config, cell);
  const auto model = sim::make_vehicle_model(config.simulation.vehicle_model, config.ego);
  const sim::RolloutResult coast = sim::no_action_rollout(scene, *model);
  ASSERT_EQ(coast.termination, sim::Termination::kContact);
  std::vector<sim::PathPoint> sparse{coast.path.front()};
  sim::PathPoint beyond = coast.path.front();  // straight on at constant speed, 1 s later
  beyond.t_s = 1.0;
  beyond.state.x_m += beyond.state.vx_mps;
  sparse.push_back(beyond);
  const Assessment a =
      assess(config, cell, parse_trajectory_csv(emrm_csv(sparse), "sparse.csv", TrajectoryFormat::kEmrm, config));
  ASSERT_TRUE(a.contact);
  EXPECT_NEAR(*a.event_time_s, coast.end_time_s, 1e-3);
  EXPECT_EQ(a.impact.loss_level, coast.impact.loss_level);
}

// Rows as esmini's dat2csv writes them for the ego (its rear axle) at `times`, from the CG's pose;
// `speed` and `wheel_angle` whatever esmini put there.
struct EsminiRow {
  double t_s, x_m, y_m, yaw_rad, speed_mps, wheel_rad;
};
std::string esmini_rows(const std::vector<EsminiRow>& rows, const sim::SceneConfig& config) {
  const double back = ego_reference_offset_m(config.ego);
  std::string out = "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n";
  for (const auto& r : rows)
    out += fmt::format("{:.6f}, 0, Ego, {:.6f}, {:.6f}, 0, {:.6f}, 0, 0, {:.6f}, {:.6f}, 0\n", r.t_s,
                       r.x_m - back * std::cos(r.yaw_rad), r.y_m - back * std::sin(r.yaw_rad),
                       std::fmod(r.yaw_rad + 2.0 * std::numbers::pi, 2.0 * std::numbers::pi), r.speed_mps, r.wheel_rad);
  return out;
}

// esmini's speed is its rear axle's over the last frame: on a circle the CG moves faster than the
// rear axle (it is further out). assess takes the CG's speed from the CG's positions, and ignores
// esmini's wheel angle (its own kinematic estimate, not the road-wheel angle).
TEST(Assess, EsminiSpeedIsTheCGsFromItsPositionsAndTheWheelAngleIsNotRead) {
  const sim::SceneConfig config;
  const double radius = 30.0, omega = 0.5, dt = 0.01, l_r = config.ego.cg_to_rear_axle_m;
  std::vector<EsminiRow> rows;
  for (int k = 0; k <= 50; ++k) {
    const double t = k * dt;
    const double a = omega * t;
    // The rear axle's speed on its own circle (radius hypot(R, l_r)), as esmini's backward difference.
    const double rear = 2.0 * std::hypot(radius, l_r) * std::sin(omega * dt / 2.0) / dt;
    rows.push_back({t, radius * std::sin(a), radius * (1.0 - std::cos(a)), a, rear, 0.3});
  }
  const auto recorded = parse_trajectory_csv(esmini_rows(rows, config), "sim.csv", TrajectoryFormat::kEsmini, config);
  EXPECT_FALSE(recorded.has_steer);
  ASSERT_EQ(recorded.samples.size(), rows.size());
  for (const auto& s : recorded.samples) {
    EXPECT_NEAR(s.speed_mps, omega * radius, 1e-3) << s.t_s;
    EXPECT_EQ(s.steer_rad, 0.0);
  }
  EXPECT_GT(rows.front().speed_mps - omega * radius, 0.01);  // the column would be wrong
}

// The entity "Truck" is the T-junction's truck about its rear axle; in another family's export a
// truck is an actor about its box's centre (the highway's), judged as the scene moves it: reading it
// as the T-junction's put its box metres off and turned grazing hits into direct ones.
TEST(Assess, OnlyTheTJunctionsTruckIsReadFromTheRecording) {
  const std::string rows =
      "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n"
      "0.000000, 0, Ego, 0, 0, 0, 0, 0, 0, 10, 0, 0\n0.000000, 1, Truck, 30, 0, 0, 1.570796, 0, 0, 0, 0, 0\n"
      "0.010000, 0, Ego, 0.1, 0, 0, 0, 0, 0, 10, 0, 0\n0.010000, 1, Truck, 30, 0, 0, 1.570796, 0, 0, 0, 0, 0\n";
  EXPECT_TRUE(parse_trajectory_csv(rows, "sim.csv", TrajectoryFormat::kEsmini, sim::SceneConfig{}).has_truck);
  const sim::SceneConfig highway =
      sim::load_scene_config(std::string(EMRM_SOURCE_DIR) + "/examples/highway_obstacle/scene.yaml");
  EXPECT_FALSE(parse_trajectory_csv(rows, "sim.csv", TrajectoryFormat::kEsmini, highway).has_truck);
}

// esmini keeps the previous step's speed on the frame that passes a trajectory's end: a car that
// braked to rest and whose last frame did not move is stopped, whatever that frame's speed says.
TEST(Assess, EsminiLastFrameThatDidNotMoveIsAtRest) {
  const sim::SceneConfig config;
  const sim::TJunctionCell cell{36, 2.0, 1.0, 3.0, 10};  // 10 m/s, the truck 20 m ahead
  const double v0 = 10.0, decel = 8.0, dt = 0.01, rest_s = v0 / decel;
  std::vector<EsminiRow> rows;
  double previous_x = 0.0;
  for (int k = 0; k * dt <= rest_s + 1.5 * dt; ++k) {
    const double t = std::min(k * dt, rest_s);
    const double x = v0 * t - 0.5 * decel * t * t - 3.0;
    const double speed = k == 0 ? v0 : (t < rest_s ? (x - previous_x) / dt : rows.back().speed_mps + 0.14);
    rows.push_back({k * dt, x, config.road.ego_lane_center_m, 0.0, speed, 0.0});
    previous_x = x;
  }
  const auto recorded = parse_trajectory_csv(esmini_rows(rows, config), "sim.csv", TrajectoryFormat::kEsmini, config);
  EXPECT_EQ(recorded.samples.back().speed_mps, 0.0);
  EXPECT_GT(recorded.samples[recorded.samples.size() - 3].speed_mps, 0.05);
  const Assessment a = assess(config, cell, recorded);
  EXPECT_TRUE(a.avoided);
  EXPECT_EQ(a.safe_state, SafeState::kStopped);
}

void expect_error_at(const std::string& text, int line, int column, const std::string& what,
                     TrajectoryFormat format = TrajectoryFormat::kEmrm) {
  try {
    (void)parse_trajectory_csv(text, "rec.csv", format, sim::SceneConfig{});
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "rec.csv") << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    if (column > 0) {
      EXPECT_EQ(e.where().column, column) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(Assess, BadFilesNameLineAndColumn) {
  expect_error_at("t,x,y,psi\n0,0,0,0\n", 1, 1, "expected a column 'v'");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0\n", 3, 0, "expected 5 fields");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0.1,nan,0,0,10\n", 3, 5, "expected a finite number for 'x'");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0,abc\n", 3, 11, "expected a finite number for 'v'");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0,1,0,0,10\n", 3, 1, "expected a time after");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n", 2, 1, "expected at least two samples");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0,-1\n", 3, 11, "expected a speed >= 0");
  // The dither of a car at rest is read as 0, not refused.
  EXPECT_EQ(parse_trajectory_csv("t,x,y,psi,v\n0,0,0,0,0.01\n0.1,0,0,0,-0.004\n", "rest.csv", TrajectoryFormat::kEmrm,
                                 sim::SceneConfig{})
                .samples.back()
                .speed_mps,
            0.0);
  expect_error_at("t,x,y,psi,v\n0,0,0,0,\"10\n", 2, 0, "");
  expect_error_at("t,x,y,psi,v,truck_x\n0,0,0,0,10,1\n0.1,1,0,0,10,1\n", 1, 1, "truck_y");
  expect_error_at(
      "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n0, 1, Truck, 0, 0, 0, 0, 0, 0, 1, 0, 0\n", 1, 1,
      "'Ego'", TrajectoryFormat::kEsmini);
}

// Issue 40, 8: esmini's recording read without --format esmini said only "expected a column 't'".
// Each format read as the other names the file's format and the flag that reads it.
TEST(Assess, AFileInTheOtherFormatSaysWhichFlagReadsIt) {
  const std::string esmini =
      "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n0, 0, Ego, 0, 0, 0, 0, 0, 0, 1, 0, 0\n";
  expect_error_at(esmini, 1, 1,
                  "got esmini's dat2csv output (columns time, id, name, x, y, h, …): pass --format esmini");
  expect_error_at("Version: 2, OpenDRIVE: tjunction.xodr, 3DModel: \n" + esmini, 1, 1, "pass --format esmini");
  expect_error_at("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0,10\n", 1, 1,
                  "got emrm's trajectory CSV (columns t, x, y, psi, v): leave out --format esmini",
                  TrajectoryFormat::kEsmini);
  // A header of neither keeps the missing column's message.
  expect_error_at("time,x,y\n0,0,0\n", 1, 1, "expected a column 't'");
}

TEST(Assess, InfeasibleCellIsRejected) {
  const sim::SceneConfig config;
  const auto recorded =
      parse_trajectory_csv("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0,10\n", "r.csv", TrajectoryFormat::kEmrm, config);
  EXPECT_THROW((void)assess(config, {70, 5.0, 1.0, 3.0, 10}, recorded), UsageError);
}

}  // namespace assess_test
}  // namespace emrm::exchange
