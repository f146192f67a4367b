// `emrm report` on a user's own case (docs/report.md, "Maps of any grid", "A planned run"): a grid
// of any name gets a map, a grid varying three factors one map per slice, a planned run a map per
// pair of the ODD's factors and sweep curves with one point per ODD bin; each figure named in
// report.html with a caption that says what it shows.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace report_maps_cli_test {

using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

// A wet road at μ 0.5 under a grid name of the user's own, and the same corner over two μ values:
// 4 + 8 cells, two strategies, so that the sweep takes well under a second.
constexpr const char* kWetCampaign = R"(scene: scene.yaml
seed: 1
strategies: [emergency_stop, emrm]
grids:
  - name: wet
    speed_kph: [30, 50]
    ttc_s: [1.0, 2.0]
    mu: 0.5
  - name: wet3
    speed_kph: [30, 50]
    ttc_s: [1.0, 2.0]
    mu: [0.5, 1.0]
)";

/// The caption of figure `stem` in report.html (empty when it has none).
std::string caption_of(const std::string& html, const std::string& stem) {
  const auto at = html.find("<figure id=\"fig-" + stem + "\">");
  if (at == std::string::npos) return "";
  const auto from = html.find("<figcaption>", at), to = html.find("</figcaption>", at);
  return from == std::string::npos || to == std::string::npos ? "" : html.substr(from, to - from);
}

bool is_png(const fs::path& file) {
  const std::string bytes = read_text(file);
  return bytes.size() > 1000 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

// A results folder and its report.html, made once for a suite (each suite sets them up in turn).
class ReportFolder : public ::testing::Test {
 protected:
  /// Runs `emrm report` on `out` and keeps the folder and its report.html for the suite's tests.
  static void report(const fs::path& out) {
    out_ = new fs::path(out);
    const auto r = run_emrm("report " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    html_ = new std::string(read_text(out / "report.html"));
  }
  static void TearDownTestSuite() {
    delete out_;
    delete html_;
    out_ = nullptr;
    html_ = nullptr;
  }
  static fs::path* out_;
  static std::string* html_;
};
fs::path* ReportFolder::out_ = nullptr;
std::string* ReportFolder::html_ = nullptr;

// One sweep of the wet campaign.
class ReportMapsOfAGrid : public ReportFolder {
 protected:
  static void SetUpTestSuite() {
    const auto example_dir = small_example("report_maps_grid");
    write_text(example_dir / "wet.yaml", kWetCampaign);
    const fs::path out = example_dir.parent_path() / "out";
    const auto sweep = run_emrm("sweep " + quoted(example_dir / "wet.yaml") + " -o " + quoted(out) + " --threads 2");
    ASSERT_EQ(sweep.exit_code, 0) << sweep.out << sweep.err;
    report(out);
  }
};

TEST_F(ReportMapsOfAGrid, AGridOfItsOwnNameGetsAMapInTheReport) {
  EXPECT_THAT(figure_ids(*html_, "map_wet"), ::testing::Contains("map_wet"));
  EXPECT_TRUE(is_png(*out_ / "figures" / "map_wet.png"));
  EXPECT_THAT(caption_of(*html_, "map_wet"),
              HasSubstr("Mitigability regions of grid &#39;wet&#39;: 2 speeds × 2 TTCs, μ = 0.5"));
  // Not the paper's map and its complaint: the store holds none of the paper's grids.
  EXPECT_THAT(*html_, Not(HasSubstr("none of the grids")));
  EXPECT_TRUE(figure_ids(*html_, "mitigability_map").empty());

  // Every cell of the grid on the map, in the region the store gives it.
  const auto regions = csv_rows(*out_ / "regions.csv");
  std::map<std::string, std::string> region_of;  // "speed ttc" -> region
  for (std::size_t i = 1; i < regions.size(); ++i)
    if (regions[i][column_of(regions[0], "grid")] == "wet")
      region_of[regions[i][column_of(regions[0], "speed_kph")] + " " + regions[i][column_of(regions[0], "ttc_s")]] =
          regions[i][column_of(regions[0], "region")];
  const auto map = csv_rows(*out_ / "figures" / "map_wet.csv");
  ASSERT_EQ(map.size(), 1 + region_of.size());
  for (std::size_t i = 1; i < map.size(); ++i) {
    const std::string key = map[i][column_of(map[0], "speed_kph")] + " " + map[i][column_of(map[0], "ttc_s")];
    EXPECT_EQ(map[i][column_of(map[0], "region")], region_of[key]) << key;
    EXPECT_EQ(map[i][column_of(map[0], "mu")], "0.5");
  }
}

TEST_F(ReportMapsOfAGrid, AThreeFactorGridGetsOneNamedMapPerSlice) {
  EXPECT_EQ(figure_ids(*html_, "map_wet3"), (std::vector<std::string>{"map_wet3_mu_0.5", "map_wet3_mu_1"}));
  for (const auto& [stem, mu] :
       std::map<std::string, std::string>{{"map_wet3_mu_0.5", "0.5"}, {"map_wet3_mu_1", "1"}}) {
    EXPECT_TRUE(is_png(*out_ / "figures" / (stem + ".png"))) << stem;
    EXPECT_THAT(caption_of(*html_, stem), HasSubstr("grid &#39;wet3&#39;, slice μ = " + mu + ": 2 speeds × 2 TTCs"));
    const auto map = csv_rows(*out_ / "figures" / (stem + ".csv"));
    ASSERT_EQ(map.size(), 5u) << stem;  // the slice's four cells, none of the other's
    for (std::size_t i = 1; i < map.size(); ++i) {
      EXPECT_EQ(map[i][column_of(map[0], "mu")], mu) << stem;
      EXPECT_EQ(map[i][column_of(map[0], "slice")], "μ = " + mu) << stem;
    }
  }
}

// One plan of the small ODD and one run of it.
class ReportOfAPlannedRun : public ReportFolder {
 protected:
  static void SetUpTestSuite() {
    const auto example_dir = small_example("report_maps_plan");
    const fs::path plan = example_dir.parent_path() / "plan", out = example_dir.parent_path() / "run";
    const auto p = run_emrm("plan " + quoted(example_dir / "odd.yaml") + " -o " + quoted(plan));
    ASSERT_EQ(p.exit_code, 0) << p.out << p.err;
    const auto r = run_emrm("run " + quoted(plan / "scenarios.csv") + " -o " + quoted(out) + " --threads 2");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    report(out);
  }
};

TEST_F(ReportOfAPlannedRun, APlannedRunGetsAMapPerPairOfOddFactors) {
  // The small ODD's factors with two levels or more: speed, TTC, passage (truck speed and μ are
  // constant), so three pairs, in the ODD's order.
  const std::vector<std::string> pairs{"plan_map_speed_kph_ttc_s", "plan_map_speed_kph_passage_m",
                                       "plan_map_ttc_s_passage_m"};
  EXPECT_EQ(figure_ids(*html_, "plan_map"), pairs);
  const auto outcomes = csv_rows(*out_ / "outcomes.csv");
  for (const auto& stem : pairs) {
    EXPECT_TRUE(is_png(*out_ / "figures" / (stem + ".png"))) << stem;
    const auto map = csv_rows(*out_ / "figures" / (stem + ".csv"));
    const auto& h = map.front();
    EXPECT_THAT(caption_of(*html_, stem), HasSubstr("Planned run, " + map[1][column_of(h, "factor_x")] + " × " +
                                                    map[1][column_of(h, "factor_y")]));
    // Each pair of levels once, and every scenario in exactly one of them.
    std::set<std::string> cells;
    std::size_t scenarios = 0;
    for (std::size_t i = 1; i < map.size(); ++i) {
      EXPECT_TRUE(cells.insert(map[i][column_of(h, "level_x")] + " " + map[i][column_of(h, "level_y")]).second);
      scenarios += std::stoul(map[i][column_of(h, "scenarios")]);
      EXPECT_LE(std::stoul(map[i][column_of(h, "successes")]), std::stoul(map[i][column_of(h, "feasible")]));
    }
    EXPECT_LE(cells.size(), 4u) << stem;  // 2 × 2 levels
    EXPECT_EQ(scenarios, outcomes.size() - 1) << stem;
  }
  // The run's scenarios are not mapped as if they were a grid.
  EXPECT_TRUE(figure_ids(*html_, "map_plan").empty());
}

TEST_F(ReportOfAPlannedRun, SweepCurvesHaveOnePointPerOddBinNotPerExactSpeed) {
  // The planned speeds are spread inside their bins: more distinct values than bins.
  const auto cells = csv_rows(*out_ / "regions.csv");
  std::set<std::string> speeds;
  std::size_t feasible = 0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    speeds.insert(cells[i][column_of(cells[0], "speed_kph")]);
    feasible += cells[i][column_of(cells[0], "feasible")] == "1";
  }
  ASSERT_GT(speeds.size(), 2u);

  const auto curves = csv_rows(*out_ / "figures" / "sweep_curves.csv");
  const auto& h = curves.front();
  ASSERT_EQ(h, (std::vector<std::string>{"level", "bin", "strategy", "cells", "collision_avoidance_rate_pct",
                                         "mitigability_success_pct"}));
  std::map<std::string, std::set<std::string>> bins_of;  // strategy -> its points' bins
  std::map<std::string, std::size_t> cells_of;
  for (std::size_t i = 1; i < curves.size(); ++i) {
    const std::string& strategy = curves[i][column_of(h, "strategy")];
    EXPECT_TRUE(bins_of[strategy].insert(curves[i][column_of(h, "bin")]).second) << "two points in one bin";
    cells_of[strategy] += std::stoul(curves[i][column_of(h, "cells")]);
  }
  ASSERT_FALSE(bins_of.empty());
  for (const auto& [strategy, bins] : bins_of) {
    EXPECT_EQ(bins, (std::set<std::string>{"[30, 51)", "[51, 72]"})) << strategy;  // the small ODD's speed bins
    EXPECT_EQ(cells_of[strategy], feasible) << strategy;                           // every feasible scenario in one bin
  }
  EXPECT_THAT(caption_of(*html_, "sweep_curves"), HasSubstr("by the ODD&#39;s 2 bins of speed_kph"));
}

TEST_F(ReportOfAPlannedRun, AMalformedOutcomesFileIsBadInputNamingIt) {
  const fs::path copy = out_->parent_path() / "run_broken";
  fs::remove_all(copy);
  fs::copy(*out_, copy, fs::copy_options::recursive);
  std::string text = read_text(copy / "outcomes.csv");
  const auto at = text.find(",c", text.find('\n'));  // the first scenario's cell key
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 2, ",x");
  write_text(copy / "outcomes.csv", text);
  const auto r = run_emrm("report " + quoted(copy));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_THAT(r.err, HasSubstr("outcomes.csv:2"));
  EXPECT_THAT(r.err, HasSubstr("is not a key of the plan's 5 factors"));
}

}  // namespace report_maps_cli_test
}  // namespace emrm::e2e
