// Calibration (docs/actuation.md, "Calibration"): synthetic brake tests made from hidden
// parameters and noise; the fit must recover them, and say when the data cannot.

#include "emrm/calibration/calibrate.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "test_scale.hpp"

namespace emrm::calibration {
namespace calibrate_test {

using ::testing::HasSubstr;

// 50 stops from 30 to 100 km/h on a dry road, with 0.3 m of noise on each distance.
std::vector<StopRecord> synthetic_stops(const sim::ActuationConfig& hidden, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<StopRecord> out;
  for (int i = 0; i < 50; ++i) {
    StopRecord s;
    s.speed_kph = 30.0 + 70.0 * i / 49.0;
    s.stop_distance_m = hidden.stopping_distance_m(s.speed_kph / 3.6, 1.0, false) + noise(rng);
    out.push_back(s);
  }
  return out;
}

// Two brake applications of 10 s each, sampled at 100 Hz with 0.05 m/s of noise.
std::vector<TraceSample> synthetic_trace(const sim::ActuationConfig& hidden, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<TraceSample> out;
  for (const auto& [run, v0] : {std::pair{"a", 19.0}, std::pair{"b", 26.0}})
    for (int k = 0; k < 1000; ++k) {
      const double t = -0.2 + 0.01 * k;
      out.push_back({run, t, std::max(0.0, braked_speed_mps(hidden, 1.0, v0, t) + noise(rng))});
    }
  return out;
}

TEST(Calibrate, StopsRecoverTheDeadTimeAndTheCap) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    sim::ActuationConfig hidden;
    hidden.brake_dead_time_s = 0.05 + 0.4 * unit(rng);
    hidden.max_decel_mps2 = 6.0 + 3.0 * unit(rng);
    const CalibrationResult r =
        calibrate_stops(synthetic_stops(hidden, 100 + trial), {{"brake_dead_time_s", "max_decel_mps2"}, {}, {}});
    ASSERT_TRUE(r.converged);
    EXPECT_NEAR(r.fitted.at("brake_dead_time_s").value, hidden.brake_dead_time_s, 0.03);
    EXPECT_NEAR(r.fitted.at("max_decel_mps2").value, hidden.max_decel_mps2, 0.15);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    // The interval holds the estimate and is not the whole range.
    const FittedValue& dead = r.fitted.at("brake_dead_time_s");
    EXPECT_LE(dead.ci_low, dead.value);
    EXPECT_GE(dead.ci_high, dead.value);
    EXPECT_LT(dead.ci_high - dead.ci_low, 0.2);
    EXPECT_NEAR(r.residual_rms, 0.3, 0.1);
  }
}

TEST(Calibrate, ATraceRecoversDeadTimeRampAndCapSeparately) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < test::sample(2, 1); ++trial) {
    sim::ActuationConfig hidden;
    hidden.brake_dead_time_s = 0.05 + 0.3 * unit(rng);
    hidden.brake_ramp_s = 0.1 + 0.5 * unit(rng);
    hidden.max_decel_mps2 = 6.0 + 3.0 * unit(rng);
    const CalibrationResult r = calibrate_trace(synthetic_trace(hidden, 200 + trial),
                                                {{"brake_dead_time_s", "brake_ramp_s", "max_decel_mps2"}, {}, {}});
    ASSERT_TRUE(r.converged);
    EXPECT_NEAR(r.fitted.at("brake_dead_time_s").value, hidden.brake_dead_time_s, 0.02);
    EXPECT_NEAR(r.fitted.at("brake_ramp_s").value, hidden.brake_ramp_s, 0.04);
    EXPECT_NEAR(r.fitted.at("max_decel_mps2").value, hidden.max_decel_mps2, 0.15);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  }
}

TEST(Calibrate, StopsAloneSayDeadTimeAndRampAreNotSeparable) {
  sim::ActuationConfig hidden;
  hidden.brake_dead_time_s = 0.2;
  hidden.brake_ramp_s = 0.3;
  const CalibrationResult r =
      calibrate_stops(synthetic_stops(hidden, 7), {{"brake_dead_time_s", "brake_ramp_s"}, {}, {}});
  ASSERT_FALSE(r.warnings.empty());
  bool said = false;
  for (const auto& w : r.warnings) said = said || w.find("not separately identifiable") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(Calibrate, BoundsThatExcludeTheSolutionAreSaid) {
  sim::ActuationConfig hidden;
  hidden.brake_dead_time_s = 0.2;
  hidden.max_decel_mps2 = 8.0;
  const CalibrationResult r = calibrate_stops(
      synthetic_stops(hidden, 8), {{"brake_dead_time_s", "max_decel_mps2"}, {{"max_decel_mps2", {2.0, 5.0}}}, {}});
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_THAT(r.warnings.front(), HasSubstr("lies on its bound"));
}

TEST(Calibrate, BadRequestsAreUsageErrors) {
  const auto stops = synthetic_stops({}, 1);
  EXPECT_THROW((void)calibrate_stops(stops, {{"steer_dead_time_s"}, {}, {}}), UsageError);
  EXPECT_THROW((void)calibrate_stops(stops, {{}, {}, {}}), UsageError);
  EXPECT_THROW((void)calibrate_stops(stops, {{"brake_dead_time_s"}, {{"brake_dead_time_s", {0.5, 0.1}}}, {}}),
               UsageError);
  EXPECT_THROW((void)calibrate_stops(stops, {{"brake_dead_time_s"}, {{"max_decel_mps2", {1.0, 9.0}}}, {}}), UsageError);
}

// The closed form the calibration fits is the simulator's emergency stop.
TEST(Calibrate, TheFittedSpeedModelIsTheSimulatorsStop) {
  sim::SceneConfig config;
  config.truck.speed_kph = 0.0;
  config.max_initial_distance_m = 200.0;
  config.actuation = {0.0, 0.13, 0.35, 7.5, 0.0, 0.0};
  const double v0 = 22.0;
  const sim::Scene scene(config, {v0 * 3.6, 6.0, 1.0, 3.0, 0.0});
  const auto model = sim::make_vehicle_model("single_track_fiala", config.ego);
  const auto run =
      sim::Roller(scene, *model, sim::ControlLimits{}).roll(scene.ego_initial(), 0.0, {}, sim::Tail::full_stop(), 1);
  int compared = 0;
  for (const auto& p : run.path) {
    if (p.state.speed_mps() < 1.0) break;
    EXPECT_NEAR(p.state.speed_mps(), braked_speed_mps(config.actuation, 1.0, v0, p.t_s), 0.01) << "t = " << p.t_s;
    ++compared;
  }
  EXPECT_GT(compared, 30);  // the closed-form stop (StopsShortTest) ends the path once the ramp is done
}

// Files: every column, every bad field is named with its line and column.
class CalibrateFiles : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::path(::testing::TempDir()) / "emrm-calibrate-test";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  static std::string error_of(const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(CalibrateFiles, StopsFilesAreCheckedFieldByField) {
  EXPECT_EQ(read_stops(write("ok.csv", "mu,speed_kph,stop_distance_m\n1.0,50,20.1\n")).size(), 1u);
  EXPECT_THAT(error_of([&] { (void)read_stops(write("cols.csv", "speed_kph,stop_distance_m\n50,20\n")); }),
              HasSubstr("cols.csv:1:1: error: missing column 'mu'"));
  EXPECT_THAT(error_of([&] { (void)read_stops(write("nan.csv", "speed_kph,mu,stop_distance_m\n50,1,nan\n")); }),
              HasSubstr("nan.csv:2:6: error: stop_distance_m: expected a finite number, got 'nan'"));
  EXPECT_THAT(error_of([&] { (void)read_stops(write("neg.csv", "speed_kph,mu,stop_distance_m\n50,1,-3\n")); }),
              HasSubstr("neg.csv:2:6: error: stop_distance_m: expected a distance > 0"));
  EXPECT_THAT(error_of([&] { (void)read_stops(write("mu.csv", "speed_kph,mu,stop_distance_m\n50,0,3\n")); }),
              HasSubstr("mu.csv:2:4: error: mu: expected 0 < mu <= 2"));
  EXPECT_THAT(error_of([&] { (void)read_stops(write("empty.csv", "speed_kph,mu,stop_distance_m\n")); }),
              HasSubstr("at least one data row"));
}

TEST_F(CalibrateFiles, TraceFilesAreCheckedFieldByField) {
  EXPECT_EQ(read_decel_trace(write("ok.csv", "run,t_s,speed_mps\na,0,20\na,0.01,20\nb,0,10\n")).size(), 3u);
  EXPECT_THAT(error_of([&] { (void)read_decel_trace(write("back.csv", "run,t_s,speed_mps\na,0.1,20\na,0.1,19\n")); }),
              HasSubstr("back.csv:3:3: error: t_s: expected the times of run 'a' to increase"));
  EXPECT_THAT(error_of([&] { (void)read_decel_trace(write("x.csv", "run,t_s,speed_mps\na,0,fast\n")); }),
              HasSubstr("x.csv:2:5: error: speed_mps: expected a finite number"));
  // A wheel-speed trace dithers around zero at rest: read as 0, not refused (it stopped a user's
  // calibration at -0.0047 m/s); a speed below the dither is refused at its field.
  const auto at_rest =
      read_decel_trace(write("rest.csv", "run,t_s,speed_mps\na,0,20\na,1,0.01\na,1.01,-0.0047\na,1.02,-0.05\n"));
  ASSERT_EQ(at_rest.size(), 4u);
  EXPECT_EQ(at_rest[2].speed_mps, 0.0);
  EXPECT_EQ(at_rest[3].speed_mps, 0.0);
  EXPECT_THAT(error_of([&] { (void)read_decel_trace(write("back2.csv", "run,t_s,speed_mps\na,0,20\na,1,-0.5\n")); }),
              HasSubstr("back2.csv:3:5: error: speed_mps: expected a speed >= 0 m/s (a car at rest may dither "
                        "down to -0.05 m/s), got -0.5"));
}

TEST_F(CalibrateFiles, RegionTargetsOfBothShapesAreRead) {
  const RegionTarget own = read_region_target(write("own.yaml", "grid: fine\nregions_pct: {G: 40, R: 20}\n"));
  EXPECT_EQ(own.grid, "fine");
  EXPECT_EQ(own.pct.size(), 2u);
  EXPECT_DOUBLE_EQ(own.pct.at("R"), 20.0);
  const RegionTarget paper = read_region_target(write(
      "paper.yaml",
      "version: 1\nfine_grid:\n  grid: fine\n  feasible_cells: 10\n  regions_pct: {G: 40, Y: 30, O: 10, R: 20}\n"));
  EXPECT_EQ(paper.pct.size(), 4u);
  EXPECT_EQ(paper.grid_at.line, 3);
}

TEST_F(CalibrateFiles, RegionTargetFieldsAreCheckedWithLineAndColumn) {
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("r.yaml", "grid: fine\nregions_pct: {G: 40, B: 2}\n")); }),
              HasSubstr("r.yaml:2:22: error: regions_pct: unknown region 'B'"));
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("p.yaml", "grid: fine\nregions_pct: {G: 140}\n")); }),
              HasSubstr("p.yaml:2:18: error: regions_pct.G: expected a percentage in [0, 100], got 140"));
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("n.yaml", "grid: fine\nregions_pct: {G: .nan}\n")); }),
              HasSubstr("n.yaml:2:18"));
  EXPECT_THAT(error_of([&] {
                (void)read_region_target(write("s.yaml", "grid: fine\nregions_pct: {G: 40, Y: 30, O: 10, R: 10}\n"));
              }),
              HasSubstr("s.yaml:2:14: error: regions_pct: G + Y + O + R must be 100"));
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("g.yaml", "regions_pct: {G: 40}\n")); }),
              HasSubstr("g.yaml:1:1: error: missing field 'grid'"));
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("k.yaml", "grid: a\nregion_pct: {G: 4}\n")); }),
              HasSubstr("k.yaml:2:1: error: unknown field 'region_pct'"));
  EXPECT_THAT(error_of([&] { (void)read_region_target(write("y.yaml", "grid: [\n")); }), HasSubstr("y.yaml:"));
}

}  // namespace calibrate_test
}  // namespace emrm::calibration
