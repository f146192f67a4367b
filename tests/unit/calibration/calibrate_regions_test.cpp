// Calibrating to a map (docs/actuation.md, "Calibrating to a map"): target fractions made from a
// hidden actuation; the fit must find an actuation that reproduces them, bracket the hidden value,
// and say when one fraction cannot pin two parameters.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "emrm/calibration/calibrate.hpp"
#include "emrm/core/error.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "test_scale.hpp"

namespace emrm::calibration {
namespace calibrate_regions_test {

using ::testing::HasSubstr;

campaign::Campaign grid_campaign(const std::string& grid) {
  return campaign::parse_campaign("seed: 3\ngrids:\n" + grid, "test.yaml", ".");
}

// The region shares (%) of a grid's feasible cells under `a`, every cell simulated.
std::map<std::string, double> simulated_pct(const campaign::Campaign& c, const sim::ActuationConfig& a) {
  sim::SceneConfig scene = c.scene;
  scene.actuation = a;
  std::map<std::string, double> count{{"G", 0.0}, {"Y", 0.0}, {"O", 0.0}, {"R", 0.0}};
  double feasible = 0.0;
  for (const auto& cell : c.grids.front().cells) {
    sim::CellOptions o;
    o.strategies = c.strategies;
    o.seed = campaign::cell_seed(c, c.grids.front().name, cell);
    const sim::CellResult r = sim::simulate_cell(scene, cell, o);
    if (!r.feasible) continue;
    feasible += 1.0;
    count[std::string(sim::region_name(r.region))] += 1.0;
  }
  for (auto& [name, n] : count) n *= 100.0 / feasible;
  return count;
}

TEST(CalibrateRegions, GAloneRecoversAHiddenDeadTimeWithoutSimulating) {
  const campaign::Campaign c = grid_campaign(
      "  - name: map\n    speed_kph: {from: 30, to: 72, step: 1}\n    ttc_s: {from: 0.25, to: 2.95, step: 0.06}\n");
  for (const double hidden : {0.15, 0.3, 0.5}) {
    sim::ActuationConfig a;
    a.brake_dead_time_s = hidden;
    double feasible = 0.0, green = 0.0;
    for (const auto& cell : c.grids.front().cells) {
      if (!sim::Scene(c.scene, cell).feasible()) continue;
      feasible += 1.0;
      green += sim::analytically_stoppable(cell, a) ? 1.0 : 0.0;
    }
    const RegionTarget target{"t.yaml", "map", {}, {{"G", 100.0 * green / feasible}}};
    CalibrationRequest request;
    request.fit = {"brake_dead_time_s"};
    const RegionCalibration r = calibrate_regions(c, target, {}, request, 1);
    const FittedValue& v = r.calibration.fitted.at("brake_dead_time_s");
    EXPECT_NEAR(v.value, hidden, 0.02) << hidden;
    EXPECT_LE(v.ci_low, hidden);
    EXPECT_GE(v.ci_high, hidden);
    EXPECT_LT(v.ci_low, v.value);  // a real interval, not a point
    EXPECT_NEAR(r.fitted_pct.at("G"), target.pct.at("G"), 100.0 / feasible) << hidden;
    EXPECT_EQ(r.sweeps, 0u);
    EXPECT_EQ(static_cast<double>(r.feasible_cells), feasible);
    EXPECT_TRUE(r.calibration.converged);
    EXPECT_TRUE(r.calibration.warnings.empty()) << r.calibration.warnings.front();
  }
}

TEST(CalibrateRegions, OneFractionCannotPinTwoParameters) {
  const campaign::Campaign c = grid_campaign(
      "  - name: map\n    speed_kph: {from: 30, to: 72, step: 3}\n    ttc_s: {from: 0.25, to: 2.95, step: 0.1}\n");
  const RegionTarget target{"t.yaml", "map", {}, {{"G", 50.0}}};
  CalibrationRequest request;
  request.fit = {"brake_dead_time_s", "brake_ramp_s"};
  const RegionCalibration r = calibrate_regions(c, target, {}, request, 1);
  EXPECT_THAT(r.calibration.warnings, testing::Contains(HasSubstr("at most 1 of them can be determined")));
}

// Y, O and R need the planners: the fit simulates, and reproduces fractions made by simulation.
TEST(CalibrateRegions, AllFourFractionsBySimulationAreReproduced) {
  // Sanitized, four of the nine cells: still a G, a Y and an unavoidable one.
  const campaign::Campaign c = grid_campaign(test::sample<std::string>(
      "  - name: map\n    speed_kph: [40, 60, 70]\n    ttc_s: [0.4, 0.7, 1.1]\n    passage_m: 3.0\n",
      "  - name: map\n    speed_kph: [40, 70]\n    ttc_s: [0.4, 1.1]\n    passage_m: 3.0\n"));
  sim::ActuationConfig hidden;
  hidden.brake_dead_time_s = 0.3;
  const RegionTarget target{"t.yaml", "map", {}, simulated_pct(c, hidden)};
  ASSERT_GT(target.pct.at("G"), 0.0);  // the grid spans the regions, so every fraction can move
  ASSERT_GT(target.pct.at("Y"), 0.0);
  ASSERT_GT(target.pct.at("O") + target.pct.at("R"), 0.0);
  CalibrationRequest request;
  request.fit = {"brake_dead_time_s"};
  request.bounds["brake_dead_time_s"] = {0.0, 0.6};
  // Two threads, against fractions simulated one cell after another: the same for any thread count.
  const RegionCalibration one = calibrate_regions(c, target, {}, request, 2);
  for (const auto& [region, pct] : target.pct) EXPECT_DOUBLE_EQ(one.fitted_pct.at(region), pct) << region;
  const FittedValue& v = one.calibration.fitted.at("brake_dead_time_s");
  EXPECT_LE(v.ci_low, 0.3);
  EXPECT_GE(v.ci_high, 0.3);
  EXPECT_GT(one.sweeps, 0u);
  EXPECT_DOUBLE_EQ(one.calibration.residual_rms, 0.0);
}

TEST(CalibrateRegions, BadRequestsAreSaid) {
  const campaign::Campaign c = grid_campaign("  - name: map\n    speed_kph: [40, 60]\n    ttc_s: [1.0, 2.0]\n");
  CalibrationRequest request;
  request.fit = {"brake_dead_time_s"};
  const RegionTarget other{"t.yaml", "fine", {"t.yaml", 2, 7}, {{"G", 50.0}}};
  try {
    (void)calibrate_regions(c, other, {}, request);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("t.yaml:2:7: error: grid 'fine' is not in the campaign"));
  }
  const RegionTarget g{"t.yaml", "map", {}, {{"G", 50.0}}};
  EXPECT_THROW((void)calibrate_regions(c, g, {"Y"}, request), UsageError);
  EXPECT_THROW((void)calibrate_regions(c, g, {"G", "G"}, request), UsageError);
  request.fit = {"steer_rate"};
  EXPECT_THROW((void)calibrate_regions(c, g, {}, request), UsageError);
}

}  // namespace calibrate_regions_test
}  // namespace emrm::calibration
