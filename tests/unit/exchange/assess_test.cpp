// `emrm assess` (docs/openscenario.md): the trajectory a strategy executed, written as a recorded
// trajectory and judged again, gives the simulator's own outcome (avoided or not, loss level, Δv),
// in emrm's CSV form and in esmini's (reference points at the rear axles); bad files name the
// line and column.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/exchange/assess.hpp"
#include "emrm/exchange/openscenario.hpp"
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

// As esmini's dat2csv writes a replay of the export: the rear axle for the ego, the truck's rear
// axle, heading in [0, 2π), a second frame at t = 0.
std::string esmini_csv(const std::vector<sim::PathPoint>& path, const sim::Scene& scene) {
  const auto& config = scene.config();
  const double ego_back = ego_reference_offset_m(config.ego);
  const double truck_back = truck_reference_offset_m(config.truck, {});
  std::string out = "Version: 3, OpenDRIVE: tjunction.xodr, 3DModel: \ntime, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n";
  const auto row = [&](double t, int id, const char* name, double x, double y, double h, double v, double steer) {
    h = std::fmod(h + 2.0 * std::numbers::pi, 2.0 * std::numbers::pi);
    out += fmt::format("{:.9f}, {}, {}, {:.9f}, {:.9f}, 0.000, {:.9f}, 0.000, 0.000, {:.9f}, {:.9f}, 0.000\n", t, id,
                       name, x, y, h, v, steer);
  };
  for (std::size_t k = 0; k < path.size(); ++k) {
    const auto& p = path[k];
    const auto& s = p.state;
    for (int copy = 0; copy < (k == 0 ? 2 : 1); ++copy) {
      row(p.t_s, 0, kEgoEntity, s.x_m - ego_back * std::cos(s.yaw_rad), s.y_m - ego_back * std::sin(s.yaw_rad),
          s.yaw_rad, s.speed_mps(), s.steer_rad);
      const sim::TruckState truck = scene.truck_at(p.t_s);
      row(p.t_s, 1, kTruckEntity, truck.box.center.x, truck.box.center.y + truck_back, truck.box.heading_rad,
          -truck.velocity_mps.y, 0.0);
    }
  }
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
    const sim::CellInput cell{v, ttc, mu(rng), passage(rng), truck(rng)};
    sim::CellOptions options;
    options.seed = 11 + static_cast<std::uint64_t>(k);
    const sim::CellResult result = sim::simulate_cell(config, cell, options);
    const sim::Scene scene(config, cell);
    for (const auto& o : result.strategies) {
      if (o.path.size() < 2) continue;
      const std::string what = fmt::format("seed {} cell {} km/h {} s mu {} passage {} truck {}: {}", options.seed, cell.speed_kph,
                                           cell.ttc_s, cell.mu, cell.passage_m, cell.truck_speed_kph, o.strategy);
      const auto recorded = parse_trajectory_csv(emrm_csv(o.path), "emrm.csv", TrajectoryFormat::kEmrm, config);
      const Assessment a = assess(config, cell, recorded);
      expect_same_outcome(o, a, what + " (emrm CSV)");
      const auto esmini = parse_trajectory_csv(esmini_csv(o.path, scene), "esmini.csv", TrajectoryFormat::kEsmini, config);
      EXPECT_TRUE(esmini.has_truck);
      EXPECT_TRUE(esmini.has_steer);
      EXPECT_EQ(esmini.samples.size(), o.path.size());
      const Assessment ae = assess(config, cell, esmini);
      expect_same_outcome(o, ae, what + " (esmini CSV)");
      contacts += a.contact ? 1 : 0;
      avoided += a.avoided ? 1 : 0;
    }
  }
  // The cells exercise both ends of the judgement.
  EXPECT_GT(contacts, 0);
  EXPECT_GT(avoided, 0);
}

// A contact is found between samples: the same run thinned to a few vertices still touches.
TEST(Assess, FindsContactBetweenSamples) {
  const sim::SceneConfig config;
  const sim::CellInput cell{60, 0.6, 1.0, 3.0, 10};
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
  expect_error_at("t,x,y,psi,v\n0,0,0,0,\"10\n", 2, 0, "");
  expect_error_at("t,x,y,psi,v,truck_x\n0,0,0,0,10,1\n0.1,1,0,0,10,1\n", 1, 1, "truck_y");
  expect_error_at("time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n0, 1, Truck, 0, 0, 0, 0, 0, 0, 1, 0, 0\n",
                  1, 1, "'Ego'", TrajectoryFormat::kEsmini);
}

TEST(Assess, InfeasibleCellIsRejected) {
  const sim::SceneConfig config;
  const auto recorded =
      parse_trajectory_csv("t,x,y,psi,v\n0,0,0,0,10\n0.1,1,0,0,10\n", "r.csv", TrajectoryFormat::kEmrm, config);
  EXPECT_THROW((void)assess(config, {70, 5.0, 1.0, 3.0, 10}, recorded), UsageError);
}

}  // namespace assess_test
}  // namespace emrm::exchange
