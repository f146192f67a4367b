// The data figures: loss comparison, sweep curves, coverage, traceability, a whole campaign, the brakes.

#include "figures_support.hpp"

namespace emrm::report {
namespace figures_test {

// --- loss comparison --------------------------------------------------------------------------

using FigureLoss = FigureTest;

TEST_F(FigureLoss, RatesAreThoseOfTheFeasibleCellsOfTheGrid) {
  const auto f = draw_loss_comparison(campaign_records(), "fine", out());
  expect_drawn(f, out(), "loss_comparison");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"strategy", "cells", "collision_avoidance_rate_pct", "mean_impact_speed_kph"}));
  ASSERT_EQ(csv.size(), 1 + kStrategies.size());
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  for (std::size_t i = 0; i < kStrategies.size(); ++i) {
    const auto& row = csv[i + 1];
    EXPECT_EQ(row[0], kStrategies[i]);  // the fixed order, whatever the records' order
    const Rates r = rates_of(fine, kStrategies[i]);
    EXPECT_EQ(row[1], std::to_string(r.cells));
    EXPECT_NEAR(num(row[2]), r.car_pct, 1e-4) << kStrategies[i];
    EXPECT_NEAR(num(row[3]), r.impact_kph, 1e-4) << kStrategies[i];
  }
  // Sanity of the synthetic data: the rates differ, so a mix-up of strategies would show.
  EXPECT_LT(num(csv[1][2]), num(csv[2][2]));
}

TEST_F(FigureEmpty, LossComparisonOfAMissingGridWritesNothing) {
  const auto f = draw_loss_comparison(campaign_records(), "no_such_grid", out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

TEST_F(FigureEmpty, LossComparisonOfAGridWithoutFeasibleCellsWritesNothing) {
  std::vector<CellRecord> records{synthetic_cell("far", 0, 72.0, 2.95, 1.0)};
  ASSERT_FALSE(records.front().feasible);
  const auto f = draw_loss_comparison(records, "far", out());
  expect_nothing_written(f, out());
}

// --- sweep curves -----------------------------------------------------------------------------

using FigureSweep = FigureTest;

TEST_F(FigureSweep, OneRowPerSpeedAndStrategyWithTheRatesAtThatSpeed) {
  const auto f = draw_sweep_curves(campaign_records(), test::tjunction_factors(), "fine", out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"speed_kph", "strategy", "cells", "collision_avoidance_rate_pct", "mitigability_success_pct"}));
  ASSERT_EQ(csv.size(), 1 + 43 * kStrategies.size());  // every speed has a feasible cell
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  std::size_t line = 1;
  for (int s = 0; s < 43; ++s) {
    const double speed = 30.0 + s;
    for (const auto& strategy : kStrategies) {
      const auto& row = csv[line++];
      EXPECT_NEAR(num(row[0]), speed, 1e-9);
      EXPECT_EQ(row[1], strategy);
      const Rates r = rates_of(fine, strategy, speed);
      EXPECT_EQ(row[2], std::to_string(r.cells));
      EXPECT_NEAR(num(row[3]), r.car_pct, 1e-4) << strategy << " at " << speed;
      EXPECT_NEAR(num(row[4]), r.mitigated_pct, 1e-4) << strategy << " at " << speed;
    }
  }
}

TEST_F(FigureSweep, LeavesOutSpeedsWithoutAFeasibleCell) {
  // Only 30 km/h is feasible here; 70 km/h cells are all beyond the initial distance.
  std::vector<CellRecord> records;
  for (int t = 0; t < 4; ++t) {
    records.push_back(synthetic_cell("g", 2 * t, 30.0, 0.5 + 0.5 * t, 1.0));
    records.push_back(synthetic_cell("g", 2 * t + 1, 70.0, 2.5 + 0.1 * t, 1.0));
  }
  const auto f = draw_sweep_curves(records, test::tjunction_factors(), "g", out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + kStrategies.size());
  for (std::size_t i = 1; i < csv.size(); ++i) EXPECT_EQ(csv[i][0], "30");
}

TEST_F(FigureEmpty, SweepOfAMissingGridWritesNothing) {
  const auto f = draw_sweep_curves(campaign_records(), test::tjunction_factors(), "no_such_grid", out());
  expect_nothing_written(f, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

TEST_F(FigureSweep, ABinnedSweepHasOnePointPerBinAndStrategy) {
  // The fine grid's 43 speeds in three bins: below 40, 40 to 55, above.
  const auto fine = results::records_of_grid(campaign_records(), "fine");
  std::vector<int> levels;
  for (const auto& c : fine)
    levels.push_back(c.factors.ego_speed_kph() < 40.0 ? 0 : c.factors.ego_speed_kph() < 55.0 ? 1 : 2);
  const PlanFactor speed{"speed_kph", "km/h", {"[30, 40)", "[40, 55)", "[55, 72]"}};
  const auto f = draw_binned_sweep_curves(fine, levels, speed, out());
  expect_drawn(f, out(), "sweep_curves");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.size(), 1 + 3 * kStrategies.size());
  for (std::size_t line = 1; line < csv.size(); ++line) {
    const int level = std::stoi(csv[line][0]);
    EXPECT_EQ(csv[line][1], speed.levels[static_cast<std::size_t>(level)]);
    std::vector<CellRecord> in_bin;
    for (std::size_t i = 0; i < fine.size(); ++i)
      if (levels[i] == level) in_bin.push_back(fine[i]);
    const Rates r = rates_of(in_bin, csv[line][2]);
    EXPECT_EQ(csv[line][3], std::to_string(r.cells));
    EXPECT_NEAR(num(csv[line][4]), r.car_pct, 1e-4);
  }
}

// --- coverage comparison ----------------------------------------------------------------------

scenario::CoverageCount count(std::size_t covered, std::size_t total) {
  scenario::CoverageCount c;
  c.covered = covered;
  c.total = total;
  return c;
}

scenario::CoverageReport coverage_report(std::string name, std::size_t scenarios, std::size_t hazards, std::size_t ucas,
                                         std::size_t cells) {
  scenario::CoverageReport r;
  r.name = std::move(name);
  r.scenarios = scenarios;
  r.hazards = count(hazards, 8);
  r.malfunctions = count(ucas, 4);
  r.transitions = count(3, 6);
  r.cells = count(cells, 200);
  r.twise = count(10, 40);
  r.boundaries = count(0, 0);
  return r;
}

std::vector<scenario::CoverageReport> coverage_reports() {
  // The coverage.json `emrm plan` writes (scenario::coverage_json), read back as a report does.
  const std::vector<scenario::CoverageReport> reports{
      coverage_report("emrm plan", 212, 8, 4, 200), coverage_report("HARA only", 8, 6, 1, 1),
      coverage_report("STPA only", 4, 8, 4, 4), coverage_report("manual grid", 30, 5, 2, 30)};
  return scenario::parse_coverage_json(scenario::coverage_json(reports).dump(2), "coverage.json");
}

using FigureCoverage = FigureTest;

TEST_F(FigureCoverage, OneRowPerMethodWithItsPercentages) {
  const auto f = draw_coverage_comparison(coverage_reports(), out());
  expect_drawn(f, out(), "coverage_comparison");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(),
            (core::Row{"method", "scenarios", "hazard_pct", "uca_pct", "transition_pct", "cell_pct", "twise_pct"}));
  ASSERT_EQ(csv.size(), 5u);
  const std::vector<core::Row> expected{
      {"emrm plan", "212"}, {"HARA only", "8"}, {"STPA only", "4"}, {"manual grid", "30"}};
  const double hazard[] = {100.0, 75.0, 100.0, 62.5};
  const double uca[] = {100.0, 25.0, 100.0, 50.0};
  const double cell[] = {100.0, 0.5, 2.0, 15.0};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& row = csv[i + 1];
    EXPECT_EQ(row[0], expected[i][0]);
    EXPECT_EQ(row[1], expected[i][1]);
    EXPECT_NEAR(num(row[2]), hazard[i], 1e-9);
    EXPECT_NEAR(num(row[3]), uca[i], 1e-9);
    EXPECT_NEAR(num(row[4]), 50.0, 1e-9);
    EXPECT_NEAR(num(row[5]), cell[i], 1e-9);
    EXPECT_NEAR(num(row[6]), 25.0, 1e-9);
  }
}

TEST_F(FigureEmpty, CoverageWithoutReportsWritesNothing) {
  expect_nothing_written(draw_coverage_comparison({}, out()), out());
}

// --- traceability matrix ----------------------------------------------------------------------

safety::TraceRow trace(std::string uca, std::string hazard, std::string loss, std::vector<std::string> scenarios) {
  safety::TraceRow r;
  r.uca = std::move(uca);
  r.hazard = std::move(hazard);
  r.loss = std::move(loss);
  r.scenarios = std::move(scenarios);
  return r;
}

using FigureTraceability = FigureTest;

TEST_F(FigureTraceability, OneRowPerUcaAndHazardWithItsScenarioCount) {
  // As traceability_matrix gives them: a row per (UCA, hazard, loss), the UCA's scenarios on each.
  const std::vector<safety::TraceRow> rows{
      trace("UCA1", "H8", "L1", {"S001", "S002", "S003"}),
      trace("UCA1", "H8", "L2", {"S001", "S002", "S003"}),
      trace("UCA1", "H1", "L3", {"S001", "S002", "S003"}),
      trace("UCA2", "H2", "L3", {}),
      trace("UCA2", "H1", "L3", {}),
      trace("UCA3", "H9", "L7", {"S010"}),
  };
  const auto f = draw_traceability(rows, out());
  expect_drawn(f, out(), "traceability_matrix");
  const auto csv = csv_of(f.csv);
  const std::vector<core::Row> expected{
      {"uca", "hazard", "losses", "scenarios"},
      {"UCA1", "H8", "L1 L2", "3"},
      {"UCA1", "H1", "L3", "3"},
      {"UCA2", "H2", "L3", "0"},
      {"UCA2", "H1", "L3", "0"},
      {"UCA3", "H9", "L7", "1"},
  };
  EXPECT_EQ(csv, expected);
}

TEST_F(FigureEmpty, TraceabilityWithoutRowsWritesNothing) {
  expect_nothing_written(draw_traceability({}, out()), out());
}

// --- a whole campaign -------------------------------------------------------------------------

using FigureCampaign = FigureTest;

// The six figures of `emrm report` for a campaign the size of the shipped one (1978 + 430 + 260 + 30
// cells). The time is recorded for the record (docs/report.md), not asserted: speed claims belong
// to benchmarks.
TEST_F(FigureCampaign, DrawsAllSixFiguresOfAShippedSizeCampaign) {
  const auto& records = campaign_records();
  std::vector<safety::TraceRow> rows;
  for (int u = 1; u <= 4; ++u)
    for (int h = 1; h <= 9; h += u) {
      std::vector<std::string> scenarios;
      for (int s = 0; s < (u * h) % 7; ++s) scenarios.push_back("S" + std::to_string(100 * u + s));
      rows.push_back(trace("UCA" + std::to_string(u), "H" + std::to_string(h), "L7", scenarios));
    }
  const auto coverage = coverage_reports();

  const auto start = std::chrono::steady_clock::now();
  const std::vector<Figure> figures{draw_mitigability_map_t(records, out()),
                                    draw_harm_reduction_map_t(records, out()),
                                    draw_loss_comparison(records, "fine", out()),
                                    draw_sweep_curves(records, test::tjunction_factors(), "fine", out()),
                                    draw_coverage_comparison(coverage, out()),
                                    draw_traceability(rows, out())};
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("render_seconds", std::to_string(seconds));
  std::cout << "[ figures  ] six figures of " << records.size() << " cells rendered in " << seconds << " s\n";

  const std::vector<std::string> names{"mitigability_map", "harm_reduction_map",  "loss_comparison",
                                       "sweep_curves",     "coverage_comparison", "traceability_matrix"};
  for (std::size_t i = 0; i < figures.size(); ++i) {
    expect_drawn(figures[i], out(), names[i]);
    EXPECT_TRUE(figures[i].note.empty()) << figures[i].note;
  }
  // To look at them: EMRM_FIGURES_TEST_KEEP=DIR keeps a copy of the figures in DIR.
  if (const char* keep = std::getenv("EMRM_FIGURES_TEST_KEEP"))
    fs::copy(out(), keep, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

}  // namespace figures_test
}  // namespace emrm::report

namespace emrm::report {
namespace figures_test {

// --- the brakes' sensitivity ---------------------------------------------------------------------

using FigureBrakes = FigureTest;

TEST_F(FigureBrakes, GFallsAlongBothCurvesAndTheCsvHoldsThem) {
  const auto f = draw_brake_sensitivity(campaign_records(), "fine", sim::ActuationConfig{}, out());
  expect_drawn(f, out(), "brake_sensitivity");
  const auto csv = csv_of(f.csv);
  ASSERT_EQ(csv.front(), (core::Row{"parameter", "value", "g_pct"}));
  ASSERT_EQ(csv.size(), 1u + 7u + 7u);
  for (std::size_t k = 2; k <= 7; ++k) EXPECT_LT(std::stod(csv[k][2]), std::stod(csv[k - 1][2]));    // dead time up
  for (std::size_t k = 10; k <= 14; ++k) EXPECT_LT(std::stod(csv[k][2]), std::stod(csv[k - 1][2]));  // cap down
}

TEST_F(FigureBrakes, AGridWithoutCellsIsANoteNotAFigure) {
  const auto f = draw_brake_sensitivity(campaign_records(), "no_such_grid", sim::ActuationConfig{}, out());
  EXPECT_NE(f.note.find("no_such_grid"), std::string::npos) << f.note;
}

}  // namespace figures_test
}  // namespace emrm::report
