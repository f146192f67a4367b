// End-to-end, as a functional-safety engineer adapting the shipped example to a wet road would:
// a campaign with grids of their own names (one of them over two friction values), a plan from an
// edited ODD (μ 0.5) and an edited safety case (a new hazard and a UCA whose region the wet ODD
// cannot reach), the run, and both reports. The reports hold a map for every grid slice and for
// the planned run, curves per ODD bin, estimates labelled with their bins, and the plan's
// shortfall first. Then (issue 40) their own `verify` and the report again (the verification shown,
// no section without something to say), an adaptive sweep of a grid of their own (its curves say
// which cells they are over, inferred cells marked), and `assess` of their esmini recording. Every
// report opens in headless Chromium without errors (screenshots in BUILD/test-artefacts/).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "headless_chromium.hpp"
#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace own_case_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr const char* kWetCampaign = R"(scene: scene.yaml
seed: 2
strategies: [emergency_stop, emrm]
grids:
  - name: wet_road
    speed_kph: [40, 60]
    ttc_s: [0.8, 1.6]
    mu: 0.5
    passage_m: 2.0
  - name: wet_or_damp
    speed_kph: [40, 60]
    ttc_s: [1.0, 2.0]
    mu: [0.4, 0.6]
    passage_m: 2.0
)";

// Their own grid, large enough that an adaptive sweep infers most of it.
constexpr const char* kWetAdaptive = R"(scene: scene.yaml
seed: 2
strategies: [emergency_stop, emrm]
grids:
  - name: suv_wet
    speed_kph: {from: 25, to: 75, step: 10}
    ttc_s: {from: 0.4, to: 2.8, step: 0.3}
    mu: 0.5
    passage_m: 2.0
)";

constexpr const char* kWetOdd = R"(name: wet T-junction ODD
safety: safety.yaml
scene: scene.yaml
seed: 1
factors:
  - {name: speed_kph, unit: km/h, bins: [30, 51, 72]}
  - {name: truck_speed_kph, unit: km/h, type: constant, value: 10}
  - {name: ttc_s, unit: s, bins: [0.25, 1.0, 2.0]}
  - {name: mu, type: constant, value: 0.5}
  - {name: passage_m, unit: m, bins: [1.0, 2.0, 3.0]}
relevance: "speed_kph / 3.6 * ttc_s <= 24.5"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, delta: 0.05, budget: 40}
baselines:
  manual: {speed_kph: [30, 72], ttc_s: [0.25, 2.0]}
)";

// A hazard of the wet road and a UCA leading to it, only on ice: no wet-road test can reach it.
constexpr const char* kNewHazard = R"(  - id: H10
    description: Wet road; the EMRM misjudges the grip and slides into the truck.
    losses: [L4, L6]
    severity: S3
    exposure: E2
    controllability: C3
    asil: B
    maneuverability: M3
    avoidability: A2
    mitigability: MT1
    smil: D

control_actions:)";
constexpr const char* kNewUca = R"(  - id: UCA5
    control_action: CA1
    type: provided
    context: EMRM brakes as on a dry road on ice and slides into the truck.
    hazards: [H10]
    fsm_transitions:
      - {from: S4, event: emrm_done, to: S1}
    region: "mu < 0.35"

smil:)";

std::string replaced_once(std::string text, const std::string& what, const std::string& with) {
  const auto at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  return at == std::string::npos ? text : text.replace(at, what.size(), with);
}

void expect_clean_in_chromium(const fs::path& html, const std::string& name) {
  const BrowserView view = open_in_chromium(html, name);
  if (!view.available) GTEST_SKIP() << "Chromium is not installed (scripts/install-deps.sh installs it)";
  ASSERT_TRUE(view.loaded) << view.log;
  EXPECT_GE(view.images, 3);
  EXPECT_EQ(view.broken_images, 0);
  EXPECT_EQ(view.errors, 0);
  EXPECT_THAT(view.log, ::testing::Not(HasSubstr("Uncaught")));
}

class OwnCase : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(small_example("own_case"));
    write_text(*dir_ / "wet.yaml", kWetCampaign);
    write_text(*dir_ / "wet_adaptive.yaml", kWetAdaptive);
    write_text(*dir_ / "odd.yaml", kWetOdd);
    std::string safety = read_text(*dir_ / "safety.yaml");
    safety = replaced_once(safety, "control_actions:", kNewHazard);
    safety = replaced_once(safety, "smil:\n  levels", std::string(kNewUca) + "\n  levels");
    write_text(*dir_ / "safety.yaml", safety);
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path* dir_;
};
fs::path* OwnCase::dir_ = nullptr;

TEST_F(OwnCase, ASweepOfGridsOfTheirOwnNamesGetsAMapPerSlice) {
  const fs::path out = dir_->parent_path() / "sweep";
  const auto sweep = run_emrm("sweep " + quoted(*dir_ / "wet.yaml") + " -o " + quoted(out) + " --threads 2");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.out << sweep.err;
  const auto report = run_emrm("report " + quoted(out));
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string html = read_text(out / "report.html");
  const auto ids = figure_ids(html);
  const std::set<std::string> maps(ids.begin(), ids.end());
  EXPECT_TRUE(maps.count("map_wet_road")) << html.substr(0, 200);
  // The grid over two friction values: one map per value, each named by it.
  std::size_t slices = 0;
  for (const auto& id : ids) slices += id.rfind("map_wet_or_damp", 0) == 0;
  EXPECT_EQ(slices, 2u);
  EXPECT_EQ(maps.count("mitigability_map"), 0u);  // none of the paper's grids
  // And the harm reduction of each, which R hides inside a loss level, whatever the grid is named.
  EXPECT_TRUE(maps.count("harm_map_wet_road")) << html.substr(0, 200);
  std::size_t harm_slices = 0;
  for (const auto& id : ids) harm_slices += id.rfind("harm_map_wet_or_damp", 0) == 0;
  EXPECT_EQ(harm_slices, 2u);
  // Issue 40, 7: no section of the paper's case that has nothing to say on their store: no empty
  // tables, no trajectory trees of a 'canonical' grid they never had; what is missing is listed
  // once, with the command that adds it.
  EXPECT_THAT(html, ::testing::Not(HasSubstr("id=\"tables\"")));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("canonical'")));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("not drawn")));
  const auto absent = html.find("id=\"absent\"");
  ASSERT_NE(absent, std::string::npos);
  EXPECT_NE(html.find("emrm verify", absent), std::string::npos);
  EXPECT_THAT(html, ::testing::Not(HasSubstr("id=\"verification\"")));

  // Their own verify, then the report again: it shows the verification, and no longer lists it.
  const auto verify = run_emrm("verify " + quoted(out) + " --threads 2");
  ASSERT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  ASSERT_EQ(run_emrm("report " + quoted(out)).exit_code, 0);
  const std::string verified = read_text(out / "report.html");
  const auto section = verified.find("id=\"verification\"");
  ASSERT_NE(section, std::string::npos);
  EXPECT_NE(verified.find("verify.json", section), std::string::npos);
  EXPECT_THAT(verified, ::testing::Not(HasSubstr("a verification: <code>emrm verify")));
  expect_clean_in_chromium(out / "report.html", "own_case_sweep");
}

TEST_F(OwnCase, APlanFromTheEditedCaseRunsAndItsReportShowsMapsBinsEstimatesAndTheShortfall) {
  const fs::path plan = dir_->parent_path() / "plan";
  const auto planned = run_emrm("plan " + quoted(*dir_ / "odd.yaml") + " -o " + quoted(plan));
  EXPECT_EQ(planned.exit_code, 1) << planned.out << planned.err;  // C4 cannot hold for UCA5
  EXPECT_THAT(planned.out, HasSubstr("UCA5: its region is empty inside the ODD"));
  const fs::path out = dir_->parent_path() / "run";
  const auto run = run_emrm("run " + quoted(plan / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;  // the shortfall travels: a warning, exit 1
  EXPECT_THAT(run.out + run.err, HasSubstr("UCA5"));
  const auto report = run_emrm("report " + quoted(out));
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;
  const std::string html = read_text(out / "report.html");

  // The shortfall first, before the regions.
  const auto shortfalls = html.find("id=\"shortfalls\"");
  ASSERT_NE(shortfalls, std::string::npos);
  EXPECT_LT(shortfalls, html.find("id=\"regions\""));
  EXPECT_NE(html.find("UCA5", shortfalls), std::string::npos);
  // A map per pair of the ODD's varying factors (speed, TTC, passage; μ and the truck are fixed).
  std::size_t pair_maps = 0;
  for (const auto& id : figure_ids(html)) pair_maps += id.rfind("plan_map_", 0) == 0;
  EXPECT_EQ(pair_maps, 3u);
  // Curves per ODD speed bin, not per exact speed.
  const auto curves = csv_rows(out / "figures" / "sweep_curves.csv");
  std::set<std::string> bins;
  for (std::size_t i = 1; i < curves.size(); ++i) bins.insert(curves[i][column_of(curves[0], "bin")]);
  EXPECT_EQ(bins, (std::set<std::string>{"[30, 51)", "[51, 72]"}));
  // Estimates labelled with their bins, in the statistics section and in estimates.csv.
  const auto statistics = html.find("id=\"statistics\"");
  ASSERT_NE(statistics, std::string::npos);
  EXPECT_NE(html.find("[30, 51)", statistics), std::string::npos);
  const auto estimates = csv_rows(out / "estimates.csv");
  for (std::size_t i = 1; i < estimates.size(); ++i)
    EXPECT_FALSE(estimates[i][column_of(estimates[0], "speed_kph")].empty());
  // The coverage of the plan beside the scenarios the run read.
  EXPECT_THAT(html, ::testing::Not(HasSubstr("no coverage.json in this folder")));
  expect_clean_in_chromium(out / "report.html", "own_case_run");
}

// Their esmini recording of the EMRM's run, judged by `emrm assess` in their own scene: the
// outcome is the simulator's (the recording is the simulated run, logged as esmini's dat2csv logs
// it: the rear axle's position every frame); read without --format esmini it names that flag.
TEST_F(OwnCase, AssessJudgesTheirEsminiRecordingAsTheSimulatorDid) {
  const std::string cell = " --speed-kph 60 --ttc-s 0.8 --mu 0.5 --passage-m 2";
  const std::string scene = " --scene " + quoted(*dir_ / "scene.yaml");
  const auto simulated = run_emrm("simulate" + scene + cell + " --strategy emrm --json");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const auto outcome = nlohmann::json::parse(simulated.out)["strategies"]["emrm"];
  // l_r, the CG's distance ahead of the rear axle, as their scene file gives it.
  const std::string scene_text = read_text(*dir_ / "scene.yaml");
  const auto at = scene_text.find("cg_to_rear_axle_m:");
  ASSERT_NE(at, std::string::npos);
  const double l_r = std::stod(scene_text.substr(at + std::string("cg_to_rear_axle_m:").size()));
  std::ostringstream csv;
  csv.precision(17);
  csv << "Version: 2, OpenDRIVE: tjunction.xodr, 3DModel: \n"
      << "time, id, name, x, y, z, h, p, r, speed, wheel_angle, wheel_rot\n";
  for (const auto& p : outcome["trajectory"]) {
    const double psi = p["psi"];
    csv << p["t"].get<double>() << ", 0, Ego, " << p["x"].get<double>() - l_r * std::cos(psi) << ", "
        << p["y"].get<double>() - l_r * std::sin(psi) << ", 0, " << psi << ", 0, 0, " << p["v"].get<double>()
        << ", 0, 0\n";
  }
  const fs::path recording = dir_->parent_path() / "esmini_emrm.csv";
  write_text(recording, csv.str());

  const auto assessed = run_emrm("assess " + quoted(recording) + " --format esmini" + scene + cell + " --json");
  ASSERT_EQ(assessed.exit_code, 0) << assessed.err;
  const auto judged = nlohmann::json::parse(assessed.out)["outcome"];
  EXPECT_EQ(judged["avoided"], outcome["avoided"]);
  EXPECT_EQ(judged["loss_level"], outcome["loss_level"]);
  EXPECT_NEAR(judged["delta_v_kph"].get<double>(), outcome["delta_v_kph"].get<double>(), 0.1);
  EXPECT_NEAR(judged["impact_speed_kph"].get<double>(), outcome["impact_speed_kph"].get<double>(), 0.1);

  const auto unflagged = run_emrm("assess " + quoted(recording) + scene + cell);
  EXPECT_EQ(unflagged.exit_code, 2);
  EXPECT_THAT(unflagged.err, HasSubstr("esmini_emrm.csv:1:1: error: expected emrm's trajectory CSV"));
  EXPECT_THAT(unflagged.err, HasSubstr("pass --format esmini"));
}

// Issue 40, 3: an adaptive sweep's curves were computed from its simulated cells, which lie near
// the boundaries, and captioned with the grid's cell count. Now they say which cells they are over,
// a curve over every feasible cell comes from the regions (inferred ones included), and the maps
// mark the inferred cells.
TEST_F(OwnCase, AnAdaptiveSweepSaysWhichCellsItsCurvesAreOverAndMarksInferredCells) {
  const fs::path out = dir_->parent_path() / "adaptive";
  const auto sweep =
      run_emrm("sweep " + quoted(*dir_ / "wet_adaptive.yaml") + " -o " + quoted(out) + " --adaptive --threads 2");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.out << sweep.err;
  const auto report = run_emrm("report " + quoted(out));
  ASSERT_EQ(report.exit_code, 0) << report.out << report.err;

  // Per speed from cells.json: feasible cells, inferred ones, and those avoided or mitigated by region.
  const auto cells = nlohmann::json::parse(read_text(out / "cells.json"));
  std::map<std::string, std::array<int, 4>> by_speed;  // feasible, inferred, G or Y, not R
  int inferred = 0, simulated = 0;
  for (const auto& c : cells) {
    if (!c["feasible"].get<bool>()) continue;
    std::ostringstream speed;  // as the CSV writes it: 25, 35, …
    speed << c["speed_kph"].get<double>();
    auto& n = by_speed[speed.str()];
    const std::string region = c["region"];
    const bool is_inferred = c["method"] == "inferred";
    inferred += is_inferred;
    simulated += !is_inferred;
    n[0] += 1;
    n[1] += is_inferred;
    n[2] += region == "G" || region == "Y";
    n[3] += region != "R";
  }
  ASSERT_GT(inferred, 0) << "expected an adaptive sweep to infer cells";
  const auto curves = csv_rows(out / "figures" / "sweep_curves.csv");
  const auto& header = curves.at(0);
  std::size_t region_rows = 0;
  for (std::size_t i = 1; i < curves.size(); ++i) {
    const auto& row = curves[i];
    const auto& n = by_speed.at(row[column_of(header, "speed_kph")]);
    const int count = std::stoi(row[column_of(header, "cells")]);
    if (row[column_of(header, "strategy")] == "regions_every_cell") {
      ++region_rows;
      EXPECT_EQ(count, n[0]);
      EXPECT_NEAR(std::stod(row[column_of(header, "collision_avoidance_rate_pct")]), 100.0 * n[2] / n[0], 1e-3);
      EXPECT_NEAR(std::stod(row[column_of(header, "mitigability_success_pct")]), 100.0 * n[3] / n[0], 1e-3);
    } else {
      EXPECT_EQ(count, n[0] - n[1]) << "a strategy's rate is over the simulated cells";
    }
  }
  EXPECT_EQ(region_rows, by_speed.size());
  const std::string html = read_text(out / "report.html");
  EXPECT_THAT(html, HasSubstr("Per strategy over the " + std::to_string(simulated) + " simulated of the " +
                              std::to_string(simulated + inferred) + " feasible cells only"));
  EXPECT_THAT(html, HasSubstr("A dot marks the " + std::to_string(inferred) + " cells an adaptive sweep inferred"));
  EXPECT_THAT(html, HasSubstr("Hatched: the " + std::to_string(inferred) + " cells an adaptive sweep inferred"));
  expect_clean_in_chromium(out / "report.html", "own_case_adaptive");
}

}  // namespace own_case_cli_test
}  // namespace emrm::e2e
