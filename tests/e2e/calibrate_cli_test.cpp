// End-to-end: `emrm calibrate` as a user runs it, from a brake-test file to a profile that
// `--profile` takes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace {

using ::testing::HasSubstr;

// Stops from 30 to 100 km/h on a dry road with a 0.2 s dead time and a 7.5 m/s² cap, no noise.
std::filesystem::path stops_file(const std::filesystem::path& dir) {
  std::ofstream out(dir / "stops.csv");
  out << "speed_kph,mu,stop_distance_m\n";
  for (int i = 0; i < 15; ++i) {
    const double kph = 30.0 + 5.0 * i;
    const double v = kph / 3.6;
    out << kph << ",1.0," << v * 0.2 + v * v / (2.0 * 7.5) << "\n";
  }
  return dir / "stops.csv";
}

TEST(CalibrateCli, FitsStopsAndWritesAProfileThatSimulateTakes) {
  const auto dir = scratch_dir("calibrate-ok");
  const auto profile = dir / "fitted.yaml";
  const auto r = run_emrm("calibrate --stops " + quoted(stops_file(dir)) +
                          " --fit brake_dead_time_s,max_decel_mps2 -o " + quoted(profile) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["fitted"]["brake_dead_time_s"]["value"].get<double>(), 0.2, 1e-3);
  EXPECT_NEAR(j["fitted"]["max_decel_mps2"]["value"].get<double>(), 7.5, 1e-2);
  for (const char* key : {"value", "ci_low", "ci_high"}) EXPECT_TRUE(j["fitted"]["max_decel_mps2"].contains(key));
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_LT(j["residual_rms"].get<double>(), 1e-3);
  const auto use = run_emrm("simulate --speed-kph 50 --ttc-s 1.0 --strategy emergency_stop --profile " + quoted(profile));
  EXPECT_EQ(use.exit_code, 0) << use.err;
}

TEST(CalibrateCli, UnidentifiableParametersExitOneWithAWarning) {
  const auto dir = scratch_dir("calibrate-confounded");
  const auto r = run_emrm("calibrate --stops " + quoted(stops_file(dir)) + " --fit brake_dead_time_s,brake_ramp_s -o " +
                          quoted(dir / "p.yaml"));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("warning:"));
}

TEST(CalibrateCli, BadInputIsExitTwoWithOneMessage) {
  const auto dir = scratch_dir("calibrate-bad");
  std::ofstream(dir / "bad.csv") << "speed_kph,mu,stop_distance_m\n50,1,-2\n";
  const auto bad = run_emrm("calibrate --stops " + quoted(dir / "bad.csv") + " --fit brake_dead_time_s -o " +
                            quoted(dir / "p.yaml"));
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_THAT(bad.err, HasSubstr("bad.csv:2:6"));
  const auto unknown = run_emrm("calibrate --stops " + quoted(stops_file(dir)) + " --fit steer_dead_time_s -o " +
                                quoted(dir / "p.yaml"));
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_THAT(unknown.err, HasSubstr("brake_dead_time_s, brake_ramp_s, max_decel_mps2"));
  const auto bounds = run_emrm("calibrate --stops " + quoted(stops_file(dir)) +
                               " --fit brake_dead_time_s --bounds brake_dead_time_s=0.5 -o " + quoted(dir / "p.yaml"));
  EXPECT_EQ(bounds.exit_code, 2);
  EXPECT_THAT(bounds.err, HasSubstr("NAME=LO:HI"));
}

}  // namespace
}  // namespace emrm::e2e
