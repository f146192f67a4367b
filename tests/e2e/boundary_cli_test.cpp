// End-to-end: `emrm boundary` on a tiny sweep through the shipped scene (a production car: perception
// latency, brake dead time and ramp): the CSV columns, the stop boundary within one TTC step of the
// analytic one through the same actuators, the figures; a grid of one TTC level is skipped; bad
// input is exit 2 with one line.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace boundary_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr double kTtcStep = 0.2;

// 3 speeds × 10 TTCs × 2 μ; the cells beyond 24.5 m are infeasible (70 km/h above 1.26 s), so at
// 70 km/h no TTC of the grid lets the car stop. Grid single has one TTC level.
std::string campaign_text() {
  return "scene: " + example("scene.yaml") +
         "\n"
         "seed: 5\n"
         "strategies: [emergency_stop, dodge, emrm, best_strategy]\n"
         "grids:\n"
         "  - name: wet\n"
         "    speed_kph: [30, 50, 70]\n"
         "    ttc_s: {from: 0.2, to: 2.0, step: 0.2}\n"
         "    mu: [0.6, 1.0]\n"
         "  - name: single\n"
         "    speed_kph: [30, 40]\n"
         "    ttc_s: 1.0\n";
}

std::optional<double> number(const std::string& field) {
  if (field.empty()) return std::nullopt;
  return std::stod(field);
}

class BoundaryCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(scratch_dir("boundary"));
    write_text(*dir_ / "campaign.yaml", campaign_text());
    const auto r =
        run_emrm("sweep " + quoted(*dir_ / "campaign.yaml") + " -o " + quoted(*dir_ / "out") + " --threads 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    run_ = new RunResult(run_emrm("boundary " + quoted(*dir_ / "out")));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete dir_;
  }
  static fs::path* dir_;
  static RunResult* run_;
};
fs::path* BoundaryCli::dir_ = nullptr;
RunResult* BoundaryCli::run_ = nullptr;

TEST_F(BoundaryCli, WritesTheCsvFilesWithTheirColumnsAndSaysWhatItDid) {
  ASSERT_EQ(run_->exit_code, 0) << run_->out << run_->err;
  EXPECT_THAT(run_->out, HasSubstr("1 grid with boundaries (wet), 1 grid skipped"));
  EXPECT_THAT(run_->out, HasSubstr("grid 'single' skipped: 1 TTC level"));
  EXPECT_THAT(run_->out, HasSubstr("6 lines"));
  EXPECT_THAT(run_->out, HasSubstr("42 boundaries written (stop, avoid, mitigate, strategy:emergency_stop, "
                                   "strategy:dodge, strategy:emrm, strategy:best_strategy)"));
  EXPECT_THAT(run_->out, HasSubstr("Drew 2 figures"));
  EXPECT_THAT(run_->out, HasSubstr((*dir_ / "out" / "boundary" / "boundary.csv").string()));

  const auto rows = csv_rows(*dir_ / "out" / "boundary" / "boundary.csv");
  ASSERT_EQ(rows.size(), 43u);  // header + 2 μ × 7 boundaries × 3 speeds
  EXPECT_EQ(rows[0], (std::vector<std::string>{"grid", "mu", "passage_m", "truck_speed_kph", "boundary", "speed_kph",
                                               "ttc_below_s", "ttc_at_s", "exceptions", "cells_used"}));
  const auto analytic = csv_rows(*dir_ / "out" / "boundary" / "analytic_stop.csv");
  ASSERT_EQ(analytic.size(), 7u);  // 2 μ × 3 speeds
  EXPECT_EQ(analytic[0], (std::vector<std::string>{"grid", "mu", "speed_kph", "stopping_distance_m", "ttc_s"}));
}

TEST_F(BoundaryCli, TheAnalyticBoundaryIsThatOfTheStoredScenesActuators) {
  // The shipped scene: perception 0.25 s, brake dead time 0.1 s, ramp 0.25 s, no cap.
  const auto analytic = csv_rows(*dir_ / "out" / "boundary" / "analytic_stop.csv");
  for (std::size_t i = 1; i < analytic.size(); ++i) {
    const double mu = std::stod(analytic[i][1]);
    const double v = std::stod(analytic[i][2]) / 3.6;
    const double a = mu * 9.81;  // sim::kGravity_mps2
    const double distance = v * 0.35 + v * 0.125 + v * v / (2 * a) - a * 0.25 * 0.25 / 24;
    EXPECT_NEAR(std::stod(analytic[i][3]), distance, 1e-5) << analytic[i][2];
    EXPECT_NEAR(std::stod(analytic[i][4]), distance / v, 1e-5) << analytic[i][2];
  }
}

TEST_F(BoundaryCli, TheStopBoundaryLiesWithinOneTtcStepOfTheAnalyticOne) {
  std::map<std::pair<std::string, std::string>, double> analytic;  // (mu, speed) -> ttc
  for (const auto& a : csv_rows(*dir_ / "out" / "boundary" / "analytic_stop.csv"))
    if (a[0] == "wet") analytic[{a[1], a[2]}] = std::stod(a[4]);
  const auto rows = csv_rows(*dir_ / "out" / "boundary" / "boundary.csv");
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<std::string>> by_line;
  std::size_t bracketed = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& r = rows[i];
    by_line[{r[1], r[5], r[4]}] = r;
    if (r[4] != "stop") continue;
    const double boundary = analytic.at({r[1], r[5]});
    const auto at = number(r[7]);
    const auto below = number(r[6]);
    if (at) {
      ++bracketed;
      EXPECT_LE(std::abs(*at - boundary), kTtcStep + 1e-9) << "mu " << r[1] << ", " << r[5] << " km/h";
    } else {
      // Nothing stops within the feasible cells: the analytic boundary is above the highest of them.
      ASSERT_TRUE(below.has_value());
      EXPECT_GT(boundary, *below - kTtcStep) << "mu " << r[1] << ", " << r[5] << " km/h";
    }
    EXPECT_EQ(r[8], "0") << "the stop boundary is monotone in TTC";
  }
  EXPECT_GE(bracketed, 3u) << "too few speeds with a stop boundary to compare";
  // G is where the emergency stop avoids: its strategy boundary is the stop boundary.
  for (const auto& [key, r] : by_line) {
    if (std::get<2>(key) != "stop") continue;
    const auto& s = by_line.at({std::get<0>(key), std::get<1>(key), "strategy:emergency_stop"});
    EXPECT_EQ(std::vector<std::string>(r.begin() + 6, r.end()), std::vector<std::string>(s.begin() + 6, s.end()));
  }
}

TEST_F(BoundaryCli, DrawsOneFigurePerCombinationOfTheOtherFactors) {
  for (const char* stem : {"boundary_wet_mu_0.6", "boundary_wet_mu_1"})
    for (const char* ext : {".png", ".svg", ".csv"})
      EXPECT_TRUE(fs::exists(*dir_ / "out" / "boundary" / (std::string(stem) + ext))) << stem << ext;
  const auto figure = csv_rows(*dir_ / "out" / "boundary" / "boundary_wet_mu_1.csv");
  ASSERT_FALSE(figure.empty());
  EXPECT_EQ(figure[0],
            (std::vector<std::string>{"series", "speed_kph", "ttc_below_s", "ttc_at_s", "drawn_ttc_s", "exceptions"}));
  EXPECT_THAT(read_text(*dir_ / "out" / "boundary" / "boundary_wet_mu_1.svg"), HasSubstr("analytic stop boundary"));
}

// Issue 40, 7: with many boundary lines and a long title ("oracle (best strategy in hindsight)
// avoids above") gnuplot puts the key in two columns, and its last rows fell off the figure. Every
// text of the figure, the key's last row among them, lies inside it.
TEST_F(BoundaryCli, EveryKeyEntryLiesInsideTheFigure) {
  const std::string svg = read_text(*dir_ / "out" / "boundary" / "boundary_wet_mu_1.svg");
  ASSERT_THAT(svg, HasSubstr("oracle (best strategy in hindsight) avoids above"));
  const auto box = svg.find("viewBox=\"0 0 ");
  ASSERT_NE(box, std::string::npos);
  std::istringstream view(svg.substr(box + 13, 20));
  double width = 0.0, height = 0.0;
  view >> width >> height;
  ASSERT_GT(height, 0.0);
  std::size_t texts = 0;
  for (auto at = svg.find("<g transform=\"translate("); at != std::string::npos;
       at = svg.find("<g transform=\"translate(", at + 1)) {
    const auto open = svg.find('(', at) + 1;
    const double x = std::stod(svg.substr(open));
    const double y = std::stod(svg.substr(svg.find(',', open) + 1));
    EXPECT_LE(y, height - 2.0) << svg.substr(at, 160);
    EXPECT_LE(x, width) << svg.substr(at, 160);
    ++texts;
  }
  EXPECT_GT(texts, 20u);
}

TEST_F(BoundaryCli, CapsTheFiguresAndWritesCsvAloneOnRequest) {
  const auto capped =
      run_emrm("boundary " + quoted(*dir_ / "out") + " -o " + quoted(*dir_ / "capped") + " --max-figures 1");
  ASSERT_EQ(capped.exit_code, 0) << capped.err;
  EXPECT_THAT(capped.out, HasSubstr("Drew 1 figure (.png, .svg, .csv) in"));
  EXPECT_THAT(capped.out, HasSubstr("the first 1 of 2 slices"));
  EXPECT_FALSE(fs::exists(*dir_ / "capped" / "boundary_wet_mu_1.png"));

  const auto bare = run_emrm("boundary " + quoted(*dir_ / "out") + " -o " + quoted(*dir_ / "bare") + " --no-figures");
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  EXPECT_EQ(read_text(*dir_ / "bare" / "boundary.csv"), read_text(*dir_ / "out" / "boundary" / "boundary.csv"));
  EXPECT_FALSE(fs::exists(*dir_ / "bare" / "boundary_wet_mu_1.png"));
}

TEST_F(BoundaryCli, BadInputIsExitTwoWithOneLine) {
  expect_bad_input(run_emrm("boundary " + quoted(*dir_ / "nosuch")), "does not exist");
  expect_bad_input(run_emrm("boundary " + quoted(*dir_)), "holds no results.sqlite");
  const fs::path junk = *dir_ / "junk";
  write_text(junk / "results.sqlite", "this is not a database");
  expect_bad_input(run_emrm("boundary " + quoted(junk)), "not an emrm results store");
  EXPECT_FALSE(fs::exists(junk / "boundary")) << "bad input writes nothing";
}

TEST_F(BoundaryCli, AStoreWithAFeasibleCellOutsideTheRegionsIsBadInput) {
  if (std::system("command -v sqlite3 >/dev/null 2>&1") != 0) GTEST_SKIP() << "the sqlite3 shell is needed";
  const fs::path dir = *dir_ / "tampered";
  fs::create_directories(dir);
  fs::copy_file(*dir_ / "out" / "results.sqlite", dir / "results.sqlite", fs::copy_options::overwrite_existing);
  const std::string sql = "sqlite3 " + quoted(dir / "results.sqlite") +
                          " \"UPDATE cells SET region = 'X' WHERE grid = 'wet' AND region = 'G'\"";
  ASSERT_EQ(std::system(sql.c_str()), 0);
  expect_bad_input(run_emrm("boundary " + quoted(dir)), "its region of cell wet#");
  EXPECT_FALSE(fs::exists(dir / "boundary")) << "bad input writes nothing";
}

}  // namespace boundary_cli_test
}  // namespace emrm::e2e
