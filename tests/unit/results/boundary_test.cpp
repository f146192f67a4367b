#include "emrm/results/boundary.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/vehicle.hpp"
#include "tjunction.hpp"

namespace emrm::results {
namespace boundary_test {

// A feasible cell of grid `grid` in `region`; the emergency stop avoids exactly in G, dodge in G
// and Y (a cell stored without outcomes has none: an adaptive sweep's inferred cell).
campaign::CellRecord cell(double speed, double ttc, std::string region, double mu = 1.0, std::string grid = "g",
                          bool with_outcomes = true) {
  campaign::CellRecord c;
  c.grid = std::move(grid);
  c.factors = sim::TJunctionCell{speed, ttc, mu, 3.0, 10.0};
  c.feasible = true;
  c.region = core::enum_from_name<sim::Region>(region).value();
  if (!with_outcomes) return c;
  campaign::OutcomeRecord stop, dodge;
  stop.strategy = "emergency_stop";
  stop.avoided = c.region == sim::Region::kG;
  dodge.strategy = "dodge";
  dodge.avoided = c.region == sim::Region::kG || c.region == sim::Region::kY;
  c.outcomes = {stop, dodge};
  return c;
}

campaign::CellRecord infeasible(double speed, double ttc, double mu = 1.0) {
  campaign::CellRecord c = cell(speed, ttc, "infeasible", mu);
  c.feasible = false;
  c.outcomes.clear();
  return c;
}

const BoundaryRow& row_of(const BoundaryReport& r, std::string_view boundary, double speed, double mu = 1.0) {
  for (const auto& row : r.rows)
    if (row.boundary == boundary && row.speed_kph == speed && row.held.front() == mu) return row;
  ADD_FAILURE() << "no row " << boundary << " at " << speed << " km/h, mu " << mu;
  static const BoundaryRow none;
  return none;
}

// --- the threshold of one line ------------------------------------------------------------------

TEST(TtcThreshold, AMonotoneLineIsBracketedByTheLastFailingAndTheFirstPassingLevel) {
  const TtcThreshold t = ttc_threshold({{1.5, true}, {0.5, false}, {2.0, true}, {1.0, false}});  // any order
  ASSERT_TRUE(t.below && t.at);
  EXPECT_DOUBLE_EQ(*t.below, 1.0);
  EXPECT_DOUBLE_EQ(*t.at, 1.5);
  EXPECT_EQ(t.exceptions, 0u);
  EXPECT_EQ(t.cells, 4u);
}

TEST(TtcThreshold, EveryLevelPassingHasNoLevelBelowAndNoneFailingHasNoThreshold) {
  const TtcThreshold all = ttc_threshold({{0.5, true}, {1.0, true}});
  EXPECT_FALSE(all.below);
  ASSERT_TRUE(all.at);
  EXPECT_DOUBLE_EQ(*all.at, 0.5);
  const TtcThreshold none = ttc_threshold({{0.5, false}, {1.0, false}});
  EXPECT_FALSE(none.at);
  ASSERT_TRUE(none.below);
  EXPECT_DOUBLE_EQ(*none.below, 1.0);
  EXPECT_EQ(none.exceptions, 0u);
  const TtcThreshold empty = ttc_threshold({});
  EXPECT_FALSE(empty.at || empty.below);
  EXPECT_EQ(empty.cells, 0u);
}

TEST(TtcThreshold, ANonMonotoneLineCountsItsPassingCellsBelowTheThreshold) {
  // Passes at 0.5 and 0.75, fails at 1.0, passes from 1.5: t* = 1.5, two exceptions.
  const TtcThreshold t = ttc_threshold({{0.5, true}, {0.75, true}, {1.0, false}, {1.5, true}, {2.0, true}});
  ASSERT_TRUE(t.below && t.at);
  EXPECT_DOUBLE_EQ(*t.below, 1.0);
  EXPECT_DOUBLE_EQ(*t.at, 1.5);
  EXPECT_EQ(t.exceptions, 2u);
  // The top level fails: no t*, and every passing cell is an exception.
  const TtcThreshold top = ttc_threshold({{0.5, true}, {1.0, false}});
  EXPECT_FALSE(top.at);
  EXPECT_DOUBLE_EQ(*top.below, 1.0);
  EXPECT_EQ(top.exceptions, 1u);
}

TEST(TtcThreshold, ALevelPassesOnlyWhenEveryCellAtItPasses) {
  // Two cells at 1.5 (a grid listing one twice), one failing: the level fails, the other passes below t*.
  const TtcThreshold t = ttc_threshold({{1.0, false}, {1.5, true}, {1.5, false}, {2.0, true}});
  EXPECT_DOUBLE_EQ(*t.below, 1.5);
  EXPECT_DOUBLE_EQ(*t.at, 2.0);
  EXPECT_EQ(t.exceptions, 1u);
}

TEST(RegionRank, GYORInOrderAndAnythingElseIsAnError) {
  EXPECT_EQ(region_rank(sim::Region::kG), 0);
  EXPECT_EQ(region_rank(sim::Region::kY), 1);
  EXPECT_EQ(region_rank(sim::Region::kO), 2);
  EXPECT_EQ(region_rank(sim::Region::kR), 3);
  EXPECT_THROW((void)region_rank(sim::Region::kInfeasible), Error);
}

// --- boundaries of records ----------------------------------------------------------------------

// Grid g at mu 1: at 30 km/h Y G G G (stop from 1.0, avoid and mitigate from 0.5); at 50 km/h
// R O Y G, then an infeasible cell at 2.5 s (stop from 2.0, avoid from 1.5, mitigate from 1.0).
std::vector<campaign::CellRecord> known_grid() {
  return {cell(30, 0.5, "Y"), cell(30, 1.0, "G"), cell(30, 1.5, "G"), cell(30, 2.0, "G"), cell(50, 0.5, "R"),
          cell(50, 1.0, "O"), cell(50, 1.5, "Y"), cell(50, 2.0, "G"), infeasible(50, 2.5)};
}

void expect_bracket(const BoundaryRow& r, std::optional<double> below, std::optional<double> at, std::size_t exceptions,
                    std::size_t used) {
  EXPECT_EQ(r.threshold.below, below) << r.boundary << " at " << r.speed_kph;
  EXPECT_EQ(r.threshold.at, at) << r.boundary << " at " << r.speed_kph;
  EXPECT_EQ(r.threshold.exceptions, exceptions) << r.boundary << " at " << r.speed_kph;
  EXPECT_EQ(r.threshold.cells, used) << r.boundary << " at " << r.speed_kph;
}

TEST(ComputeBoundaries, EachRegionBoundaryIsTheKnownThreshold) {
  const BoundaryReport r = compute_boundaries(known_grid(), test::tjunction_factors(), sim::ActuationConfig{});
  EXPECT_EQ(r.grids, (std::vector<std::string>{"g"}));
  EXPECT_EQ(r.boundaries,
            (std::vector<std::string>{"stop", "avoid", "mitigate", "strategy:emergency_stop", "strategy:dodge"}));
  ASSERT_EQ(r.slices.size(), 1u);
  EXPECT_EQ(r.lines, 2u);
  EXPECT_EQ(r.rows.size(), 10u);  // 5 boundaries × 2 speeds
  expect_bracket(row_of(r, "stop", 30), 0.5, 1.0, 0, 4);
  expect_bracket(row_of(r, "avoid", 30), std::nullopt, 0.5, 0, 4);
  expect_bracket(row_of(r, "mitigate", 30), std::nullopt, 0.5, 0, 4);
  // The infeasible cell at 2.5 s is skipped: it neither fails nor counts.
  expect_bracket(row_of(r, "stop", 50), 1.5, 2.0, 0, 4);
  expect_bracket(row_of(r, "avoid", 50), 1.0, 1.5, 0, 4);
  expect_bracket(row_of(r, "mitigate", 50), 0.5, 1.0, 0, 4);
  // The strategies agree with the regions they define.
  expect_bracket(row_of(r, "strategy:emergency_stop", 50), 1.5, 2.0, 0, 4);
  expect_bracket(row_of(r, "strategy:dodge", 50), 1.0, 1.5, 0, 4);
  EXPECT_EQ(r.non_monotone(), 0u);
}

TEST(ComputeBoundaries, RowsComeBySliceThenBoundaryThenSpeed) {
  auto records = known_grid();
  for (const auto& c : known_grid()) {  // the same cells at mu 0.5, stored after mu 1
    records.push_back(c);
    records.back().factors[sim::kFrictionFactor] = 0.5;
  }
  const BoundaryReport r = compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
  ASSERT_EQ(r.slices.size(), 2u);
  EXPECT_DOUBLE_EQ(r.slices[0].held.front(), 0.5);  // ascending μ, whatever the store's order
  EXPECT_EQ(r.lines, 4u);
  ASSERT_EQ(r.rows.size(), 20u);
  EXPECT_DOUBLE_EQ(r.rows[0].held.front(), 0.5);
  EXPECT_EQ(r.rows[0].boundary, "stop");
  EXPECT_DOUBLE_EQ(r.rows[0].speed_kph, 30);
  EXPECT_DOUBLE_EQ(r.rows[1].speed_kph, 50);
  EXPECT_EQ(r.rows[2].boundary, "avoid");
  EXPECT_DOUBLE_EQ(r.rows[10].held.front(), 1.0);
}

TEST(ComputeBoundaries, ANonMonotoneLineIsReportedWithItsExceptions) {
  // At 40 km/h: G at 0.5 s, Y at 1.0 s, G above: the stop boundary is 1.5 s with one exception.
  const std::vector<campaign::CellRecord> records{cell(40, 0.5, "G"), cell(40, 1.0, "Y"), cell(40, 1.5, "G"),
                                                  cell(40, 2.0, "G")};
  const BoundaryReport r = compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
  expect_bracket(row_of(r, "stop", 40), 1.0, 1.5, 1, 4);
  expect_bracket(row_of(r, "strategy:emergency_stop", 40), 1.0, 1.5, 1, 4);
  expect_bracket(row_of(r, "avoid", 40), std::nullopt, 0.5, 0, 4);
  EXPECT_EQ(r.non_monotone(), 2u);
  EXPECT_NE(summary(r).find("2 boundary lines are not monotone"), std::string::npos) << summary(r);
}

TEST(ComputeBoundaries, AStrategyUsesOnlyTheCellsWithItsOutcome) {
  // 1.0 s is an inferred cell without outcomes: the regions use it, the strategies do not.
  std::vector<campaign::CellRecord> records{cell(30, 0.5, "R"), cell(30, 1.0, "Y", 1.0, "g", false), cell(30, 1.5, "G"),
                                            cell(30, 2.0, "G")};
  // dodge was not run at 2.0 s either (a store of another strategy list there).
  records[3].outcomes.pop_back();
  const BoundaryReport r = compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
  expect_bracket(row_of(r, "avoid", 30), 0.5, 1.0, 0, 4);
  expect_bracket(row_of(r, "strategy:emergency_stop", 30), 0.5, 1.5, 0, 3);
  expect_bracket(row_of(r, "strategy:dodge", 30), 0.5, 1.5, 0, 2);
  EXPECT_NE(boundary_csv(r).find("g,1,3,10,strategy:dodge,30,0.5,1.5,0,2\n"), std::string::npos) << boundary_csv(r);
}

TEST(ComputeBoundaries, AGridOfOneTtcLevelIsSkippedNotAnError) {
  auto records = known_grid();
  records.push_back(cell(30, 1.0, "G", 1.0, "one"));
  records.push_back(cell(50, 1.0, "R", 1.0, "one"));
  const BoundaryReport r = compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
  EXPECT_EQ(r.grids, (std::vector<std::string>{"g"}));
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].grid, "one");
  EXPECT_EQ(r.skipped[0].ttc_levels, 1u);
  for (const auto& row : r.rows) EXPECT_EQ(row.grid, "g");
  EXPECT_NE(summary(r).find("grid 'one' skipped: 1 TTC level"), std::string::npos) << summary(r);
  // A store holding only such grids has no boundary at all.
  const BoundaryReport only =
      compute_boundaries(records_of_grid(records, "one"), test::tjunction_factors(), sim::ActuationConfig{});
  EXPECT_TRUE(only.rows.empty());
  EXPECT_TRUE(only.analytic.empty());
}

TEST(ComputeBoundaries, AFeasibleCellWithoutARegionIsADamagedStore) {
  auto records = known_grid();
  records[2].region = sim::Region::kInfeasible;
  try {
    (void)compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cell 0 of grid 'g' is feasible but its region is 'infeasible'"),
              std::string::npos)
        << e.what();
  }
}

TEST(BoundaryCsv, HeaderAndEmptyFieldsForAnAbsentLevel) {
  const BoundaryReport r = compute_boundaries(known_grid(), test::tjunction_factors(), sim::ActuationConfig{});
  const std::string csv = boundary_csv(r);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "grid,mu,passage_m,truck_speed_kph,boundary,speed_kph,ttc_below_s,ttc_at_s,exceptions,cells_used");
  EXPECT_NE(csv.find("\ng,1,3,10,stop,30,0.5,1,0,4\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\ng,1,3,10,avoid,30,,0.5,0,4\n"), std::string::npos) << csv;
}

// --- the analytic stop boundary -----------------------------------------------------------------

TEST(AnalyticStop, OneRowPerGridMuAndSpeed) {
  auto records = known_grid();
  for (const auto& c : known_grid()) {
    records.push_back(c);
    records.back().factors[sim::kFrictionFactor] = 0.5;
  }
  const BoundaryReport r = compute_boundaries(records, test::tjunction_factors(), sim::ActuationConfig{});
  ASSERT_EQ(r.analytic.size(), 4u);  // μ 0.5, 1 × 30, 50 km/h
  EXPECT_DOUBLE_EQ(r.analytic[0].mu, 0.5);
  EXPECT_DOUBLE_EQ(r.analytic[0].speed_kph, 30);
  EXPECT_NEAR(r.analytic[0].ttc_s, 30 / 3.6 / (2 * 0.5 * sim::kGravity_mps2), 1e-12);
  EXPECT_NEAR(r.analytic[0].stopping_distance_m, r.analytic[0].ttc_s * 30 / 3.6, 1e-9);
  const std::string csv = analytic_stop_csv(r);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "grid,mu,speed_kph,stopping_distance_m,ttc_s");
}

TEST(WriteBoundaryFiles, WritesBothCsvFiles) {
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-boundary-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const BoundaryReport r = compute_boundaries(known_grid(), test::tjunction_factors(), sim::ActuationConfig{});
  const auto written = write_boundary_files(dir / "out", r);
  ASSERT_EQ(written.size(), 2u);
  std::ifstream in(dir / "out" / "boundary.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), boundary_csv(r));
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "analytic_stop.csv"));
  std::filesystem::remove_all(dir);
}

}  // namespace boundary_test
}  // namespace emrm::results
