// `emrm report` end to end: on the output of a small `emrm reproduce`, every figure exists as a
// valid PNG and SVG with a CSV that agrees with the results store, report.html opens in headless
// Chromium without console errors or broken images, and bad folders are bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "headless_chromium.hpp"
#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace report_cli_test {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// One reproduce for the whole suite (about a second): the tests read its folder.
class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto example_dir = small_example("report");
    out_ = new fs::path(example_dir.parent_path() / "out");
    const auto r =
        run_emrm("reproduce -o " + quoted(*out_) + " --examples " + quoted(example_dir) + " --sample 1 --threads 2");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    reproduce_out_ = new std::string(r.out);
  }
  static void TearDownTestSuite() {
    delete out_;
    delete reproduce_out_;
  }
  static fs::path* out_;
  static std::string* reproduce_out_;
};
fs::path* ReportCli::out_ = nullptr;
std::string* ReportCli::reproduce_out_ = nullptr;

bool is_png(const fs::path& file) {
  const std::string bytes = read_text(file);
  return bytes.size() > 1000 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

bool is_svg(const fs::path& file) {
  const std::string text = read_text(file);
  return text.size() > 500 && (text.rfind("<?xml", 0) == 0 || text.rfind("<svg", 0) == 0) &&
         text.find("</svg>") != std::string::npos;
}

TEST_F(ReportCli, ReproduceEndsWithTheReport) {
  EXPECT_THAT(*reproduce_out_, HasSubstr("Report: "));
  EXPECT_THAT(*reproduce_out_, HasSubstr("report.html"));
  EXPECT_TRUE(fs::exists(*out_ / "report.html"));
  // It says which actuation made its figures and tables (the shipped scene's: the production car).
  EXPECT_THAT(read_text(*out_ / "report.html"), HasSubstr("Actuation: perception latency 0.25 s"));
  EXPECT_THAT(read_text(*out_ / "report.html"), HasSubstr("(the <code>production</code> profile)"));
  // And the brakes' sensitivity table is among them.
  EXPECT_TRUE(fs::exists(*out_ / "tables" / "brake_sensitivity.csv"));
  // The map under each profile, side by side, one panel and CSV block per profile.
  EXPECT_TRUE(fs::exists(*out_ / "figures" / "regions_by_profile.png"));
  const std::string csv = read_text(*out_ / "figures" / "regions_by_profile.csv");
  for (const char* profile : {",ideal,", ",paper,", ",production,"}) EXPECT_THAT(csv, HasSubstr(profile));
}

TEST_F(ReportCli, EveryFigureIsAValidPngAndSvgWithItsCsv) {
  const auto r = run_emrm("report " + quoted(*out_));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* name :
       {"mitigability_map", "harm_reduction_map", "trajectory_grid", "loss_comparison", "sweep_curves",
        "coverage_comparison", "emrm_fsm", "loss_evaluation_fsm", "traceability_matrix"}) {
    const fs::path base = *out_ / "figures" / name;
    EXPECT_TRUE(is_png(base.string() + ".png")) << name;
    EXPECT_TRUE(is_svg(base.string() + ".svg")) << name;
    EXPECT_TRUE(fs::exists(base.string() + ".csv")) << name;
  }
  // Drawn again from the same store, every figure is the same bytes (a drawing once named its
  // curves by the paths of temporary files).
  std::map<fs::path, std::string> first;
  for (const auto& entry : fs::directory_iterator(*out_ / "figures")) first[entry.path()] = read_text(entry.path());
  ASSERT_EQ(run_emrm("report " + quoted(*out_)).exit_code, 0);
  for (const auto& [path, bytes] : first) EXPECT_TRUE(read_text(path) == bytes) << path << " differs when drawn again";
}

TEST_F(ReportCli, FigureDataAgreesWithTheResultsStore) {
  ASSERT_EQ(run_emrm("report " + quoted(*out_)).exit_code, 0);
  // The store's cells, as exported by the sweep.
  const auto regions = csv_rows(*out_ / "regions.csv");
  const auto& rh = regions.front();
  std::map<std::string, std::string> region_of, evidence_of, reduction_of;  // "speed ttc" of the fine grid ->
  for (std::size_t i = 1; i < regions.size(); ++i)
    if (regions[i][column_of(rh, "grid")] == "fine") {
      const std::string key = regions[i][column_of(rh, "speed_kph")] + " " + regions[i][column_of(rh, "ttc_s")];
      region_of[key] = regions[i][column_of(rh, "region")];
      evidence_of[key] = regions[i][column_of(rh, "feasible")] == "1" ? regions[i][column_of(rh, "evidence")] : "";
      reduction_of[key] = regions[i][column_of(rh, "p_mais3_reduction")];
    }

  const auto map = csv_rows(*out_ / "figures" / "mitigability_map.csv");
  const auto& mh = map.front();
  std::size_t fine_rows = 0;
  for (std::size_t i = 1; i < map.size(); ++i) {
    if (map[i][column_of(mh, "grid")] != "fine") continue;
    ++fine_rows;
    const std::string key = map[i][column_of(mh, "speed_kph")] + " " + map[i][column_of(mh, "ttc_s")];
    ASSERT_TRUE(region_of.count(key)) << key;
    EXPECT_EQ(map[i][column_of(mh, "region")], region_of[key]) << key;
    EXPECT_EQ(map[i][column_of(mh, "evidence")], evidence_of[key]) << key;
  }
  EXPECT_EQ(fine_rows, region_of.size());

  // The harm-reduction map's reductions are the store's (regions.csv keeps 6 digits).
  const auto harm = csv_rows(*out_ / "figures" / "harm_reduction_map.csv");
  const auto& hh = harm.front();
  fine_rows = 0;
  for (std::size_t i = 1; i < harm.size(); ++i) {
    if (harm[i][column_of(hh, "grid")] != "fine") continue;
    ++fine_rows;
    const std::string key = harm[i][column_of(hh, "speed_kph")] + " " + harm[i][column_of(hh, "ttc_s")];
    ASSERT_TRUE(reduction_of.count(key)) << key;
    const std::string& reduction = harm[i][column_of(hh, "p_mais3_reduction")];
    ASSERT_EQ(reduction.empty(), reduction_of[key].empty()) << key;
    if (!reduction.empty()) {
      EXPECT_NEAR(std::stod(reduction), std::stod(reduction_of[key]), 1e-5) << key;
    }
  }
  EXPECT_EQ(fine_rows, reduction_of.size());

  // Collision-avoidance rates of the loss comparison, recounted from cells.csv (one row per
  // feasible cell and strategy).
  const auto cells = csv_rows(*out_ / "cells.csv");
  const auto& ch = cells.front();
  std::map<std::string, std::pair<int, int>> avoided;  // strategy -> (avoided, feasible cells)
  for (std::size_t i = 1; i < cells.size(); ++i) {
    if (cells[i][column_of(ch, "grid")] != "fine") continue;
    auto& [yes, all] = avoided[cells[i][column_of(ch, "strategy")]];
    yes += cells[i][column_of(ch, "avoided")] == "1";
    ++all;
  }
  const auto loss = csv_rows(*out_ / "figures" / "loss_comparison.csv");
  const auto& lh = loss.front();
  int checked = 0;
  for (std::size_t i = 1; i < loss.size(); ++i) {
    const std::string s = loss[i][column_of(lh, "strategy")];
    if (!avoided.count(s)) continue;
    const double expected = 100.0 * avoided[s].first / avoided[s].second;
    EXPECT_NEAR(std::stod(loss[i][column_of(lh, "collision_avoidance_rate_pct")]), expected, 1e-3) << s;  // 6 digits
    ++checked;
  }
  EXPECT_EQ(checked, 6);  // the five strategies and the oracle

  // The EMRM FSM figure's counts are the transitions of the stored traces: every count is a number
  // and the detection transition was taken at least once.
  const auto fsm = csv_rows(*out_ / "figures" / "emrm_fsm.csv");
  bool detection = false;
  for (std::size_t i = 1; i < fsm.size(); ++i)
    if (fsm[i][1] == "hazard_detected") detection = std::stoi(fsm[i][3]) > 0;
  EXPECT_TRUE(detection);
}

// The small campaign holds one of the paper's four map grids (`fine`): its map fills the page as
// one panel instead of leaving three slots empty with "no grid … in the store".
TEST_F(ReportCli, OnePaperGridAloneFillsItsMapWithoutEmptyPanels) {
  ASSERT_EQ(run_emrm("report " + quoted(*out_)).exit_code, 0);
  for (const char* map : {"mitigability_map", "harm_reduction_map"}) {
    const std::string svg = read_text(*out_ / "figures" / (std::string(map) + ".svg"));
    ASSERT_FALSE(svg.empty()) << map;
    EXPECT_THAT(svg, ::testing::Not(HasSubstr("in the store"))) << map;
    EXPECT_THAT(svg, ::testing::Not(HasSubstr("(b) Speed"))) << map;  // one panel: no letter
    EXPECT_THAT(svg, HasSubstr("Speed × TTC, fine grid")) << map;
  }
}

// Side files edited by hand with values of the wrong type: the report shows them as they are and
// says so; it never ends in an uncaught exception (was: "internal error", exit 70).
TEST_F(ReportCli, SideFilesOfTheWrongShapeAreShownAsTheyAreNotACrash) {
  const fs::path copy = out_->parent_path() / "side_files";
  fs::remove_all(copy);
  fs::copy(*out_, copy, fs::copy_options::recursive);
  write_text(copy / "analysis" / "findings.json", R"([{"severity": 1, "file": [], "line": "x", "message": null}])");
  write_text(copy / "diagnostics.json", R"({"stop_boundary": {"feasible": "many"}})");
  write_text(copy / "plan_results" / "estimates.json", R"({"weighted_success": {"all": {"n": "x"}}, "cells": 3})");
  const auto r = run_emrm("report " + quoted(copy));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_text(copy / "report.html");
  EXPECT_THAT(html, HasSubstr("analysis/findings.json is not in the form emrm writes"));
  EXPECT_THAT(html, HasSubstr("diagnostics.json is not in the form emrm writes"));
  EXPECT_THAT(html, HasSubstr("is not in the form emrm run writes"));
}

TEST_F(ReportCli, HtmlOpensInHeadlessChromiumWithoutErrorsOrMissingImages) {
  ASSERT_EQ(run_emrm("report " + quoted(*out_)).exit_code, 0);
  const BrowserView view = open_in_chromium(*out_ / "report.html", "report");
  if (!view.available) GTEST_SKIP() << "Chromium is not installed (scripts/install-deps.sh installs it)";
  EXPECT_TRUE(is_png(view.screenshot));
  ASSERT_TRUE(view.loaded) << view.log;  // the page's load handler ran
  EXPECT_GE(view.images, 8);             // every figure embedded
  EXPECT_EQ(view.broken_images, 0);
  EXPECT_EQ(view.errors, 0);
  EXPECT_THAT(view.log, ::testing::Not(HasSubstr("Uncaught")));
  EXPECT_THAT(view.log, ::testing::Not(HasSubstr(":CONSOLE")));
}

TEST(ReportCliBadInput, MissingEmptyOrOtherFoldersAreBadInput) {
  const auto dir = scratch_dir("report-bad");
  auto r = run_emrm("report " + quoted(dir / "nowhere"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("does not exist"));

  fs::create_directories(dir / "empty");
  r = run_emrm("report " + quoted(dir / "empty"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("holds no results.sqlite"));

  write_text(dir / "file.txt", "not a folder");
  r = run_emrm("report " + quoted(dir / "file.txt"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("is not a folder"));

  fs::create_directories(dir / "garbage");
  write_text(dir / "garbage" / "results.sqlite", "this is not a database");
  r = run_emrm("report " + quoted(dir / "garbage"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(ReportCli, AStoreOfAnotherSchemaVersionIsBadInput) {
  const auto dir = scratch_dir("report-old");
  fs::create_directories(dir);
  fs::copy_file(*out_ / "results.sqlite", dir / "results.sqlite");
  ASSERT_EQ(std::system(("sqlite3 " + quoted(dir / "results.sqlite") +
                         " \"UPDATE meta SET value = '1' WHERE key = 'schema_version'\"")
                            .c_str()),
            0);
  const auto r = run_emrm("report " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("schema version 1"));
}

}  // namespace report_cli_test
}  // namespace emrm::e2e
