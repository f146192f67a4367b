#include "emrm/results/aggregate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace emrm::results {
namespace aggregate_test {

campaign::OutcomeRecord outcome(std::string strategy, bool avoided, double impact_kph, int level, int unmitigated,
                                double min_ttc = 1.0) {
  campaign::OutcomeRecord o;
  o.strategy = std::move(strategy);
  o.avoided = avoided;
  o.contact = !avoided;
  o.impact_speed_kph = avoided ? 0.0 : impact_kph;
  o.loss_level = avoided ? 0 : level;
  o.delta_loss = unmitigated - o.loss_level;
  o.min_ttc_s = min_ttc;
  return o;
}

campaign::CellRecord cell(std::string grid, std::int64_t index, double speed, double ttc, double mu, double passage,
                          std::string region, int unmitigated) {
  campaign::CellRecord c;
  c.grid = std::move(grid);
  c.index = index;
  c.factors = sim::CellInput{speed, ttc, mu, passage, 0.0};
  c.feasible = region != "infeasible";
  c.region = core::enum_from_name<sim::Region>(region).value();
  c.unmitigated_loss_level = unmitigated;
  return c;
}

// Four feasible cells and one infeasible one, with hand-chosen outcomes:
//   cell 0: 40 km/h, TTC 0.7: stop avoids; dodge avoids.                         unmitigated L7
//   cell 1: 41 km/h, TTC 1.3: stop hits at 20 km/h (L6); dodge avoids.           unmitigated L7
//   cell 2: 56 km/h, TTC 1.31: stop hits at 30 km/h (L7); dodge hits 10 (L4).    unmitigated L7
//   cell 3: 57 km/h, TTC 0.2: stop hits at 50 km/h (L7); dodge hits 40 (L7).     unmitigated L7
std::vector<campaign::CellRecord> four_cells() {
  std::vector<campaign::CellRecord> cells;
  cells.push_back(cell("fine", 0, 40, 0.7, 1.0, 3.0, "G", 7));
  cells.back().outcomes = {outcome("emergency_stop", true, 0, 0, 7, 0.5), outcome("dodge", true, 0, 0, 7, 0.9)};
  cells.push_back(cell("fine", 1, 41, 1.3, 1.0, 3.0, "Y", 7));
  cells.back().outcomes = {outcome("emergency_stop", false, 20, 6, 7, 0.0), outcome("dodge", true, 0, 0, 7, 0.7)};
  cells.push_back(cell("fine", 2, 56, 1.31, 1.0, 3.0, "O", 7));
  cells.back().outcomes = {outcome("emergency_stop", false, 30, 7, 7, 0.0), outcome("dodge", false, 10, 4, 7, 0.0)};
  cells.push_back(cell("fine", 3, 57, 0.2, 1.0, 3.0, "R", 7));
  cells.back().outcomes = {outcome("emergency_stop", false, 50, 7, 7, 0.0),
                           outcome("dodge", false, 40, 7, 7, std::numeric_limits<double>::infinity())};
  cells.push_back(cell("fine", 4, 72, 2.9, 1.0, 3.0, "infeasible", 0));
  return cells;
}

TEST(HeadlineGrid, IsTheWantedGridWhenPresentElseTheLargest) {
  std::vector<campaign::CellRecord> records{cell("coarse", 0, 30, 1, 1, 3, "G", 7),
                                            cell("wide", 0, 30, 1, 1, 3, "G", 7), cell("wide", 1, 50, 1, 1, 3, "Y", 7),
                                            cell("coarse", 1, 50, 1, 1, 3, "Y", 7),
                                            cell("wide", 2, 70, 1, 1, 3, "R", 7)};
  EXPECT_EQ(headline_grid(records), "wide");  // no "fine": the grid with the most cells
  EXPECT_EQ(headline_grid(records, "coarse"), "coarse");
  records.push_back(cell("fine", 0, 30, 1, 1, 3, "G", 7));
  EXPECT_EQ(headline_grid(records), "fine");
  EXPECT_EQ(headline_grid({}), "");
}

TEST(RegionCounts, CountsFeasibleCellsOnlyAndPercentOfFeasible) {
  auto cells = four_cells();
  cells.push_back(cell("coarse", 0, 30, 1.0, 1.0, 3.0, "G", 7));
  const auto c = count_regions(cells, "fine");
  EXPECT_EQ(c.cells, 5u);
  EXPECT_EQ(c.feasible, 4u);
  EXPECT_EQ(c.infeasible, 1u);
  EXPECT_EQ(c.g, 1u);
  EXPECT_EQ(c.y, 1u);
  EXPECT_EQ(c.o, 1u);
  EXPECT_EQ(c.r, 1u);
  EXPECT_DOUBLE_EQ(c.pct(c.g), 25.0);
  EXPECT_TRUE(std::isnan(count_regions(cells, "none").pct(0)));
  EXPECT_EQ(grid_names(cells), (std::vector<std::string>{"fine", "coarse"}));
}

TEST(RegionCounts, RejectsAFeasibleCellWithoutRegion) {
  std::vector<campaign::CellRecord> cells{cell("fine", 0, 40, 1.0, 1.0, 3.0, "G", 7)};
  cells[0].region = sim::Region::kInfeasible;  // feasible, yet without a region of the map
  EXPECT_THROW((void)count_regions(cells, "fine"), Error);
}

TEST(StrategyKpis, EmergencyStopByHand) {
  const auto k = strategy_kpis(four_cells(), "emergency_stop", "fine");
  EXPECT_EQ(k.cells, 4u);
  EXPECT_EQ(k.avoided, 1u);
  EXPECT_EQ(k.collisions, 3u);
  EXPECT_DOUBLE_EQ(k.collision_avoidance_rate_pct, 25.0);
  EXPECT_DOUBLE_EQ(k.mean_impact_speed_kph, (0 + 20 + 30 + 50) / 4.0);
  EXPECT_DOUBLE_EQ(k.mean_impact_speed_collisions_kph, (20 + 30 + 50) / 3.0);
  // Levels 0, 6, 7, 7 against 7: cells 0 and 1 are mitigated.
  EXPECT_EQ(k.mitigated, 2u);
  EXPECT_DOUBLE_EQ(k.mitigability_success_pct, 50.0);
  EXPECT_DOUBLE_EQ(k.mean_delta_loss, (7 + 1 + 0 + 0) / 4.0);
  EXPECT_DOUBLE_EQ(k.mean_min_ttc_s, 0.5 / 4.0);
}

TEST(StrategyKpis, DodgeByHandSkipsInfiniteMinimumTtc) {
  const auto k = strategy_kpis(four_cells(), "dodge");
  EXPECT_DOUBLE_EQ(k.collision_avoidance_rate_pct, 50.0);
  EXPECT_DOUBLE_EQ(k.mean_impact_speed_kph, (10 + 40) / 4.0);
  EXPECT_DOUBLE_EQ(k.mean_impact_speed_collisions_kph, 25.0);
  EXPECT_DOUBLE_EQ(k.mitigability_success_pct, 75.0);  // levels 0, 0, 4 below 7; 7 is not
  EXPECT_DOUBLE_EQ(k.mean_delta_loss, (7 + 7 + 3 + 0) / 4.0);
  EXPECT_EQ(k.finite_min_ttc, 3u);
  EXPECT_DOUBLE_EQ(k.mean_min_ttc_s, (0.9 + 0.7 + 0.0) / 3.0);
}

TEST(StrategyKpis, AvoidedCellWithoutUnmitigatedLossIsNoMitigation) {
  std::vector<campaign::CellRecord> cells{cell("g", 0, 40, 1.0, 1.0, 3.0, "G", 0)};
  cells[0].outcomes = {outcome("dodge", true, 0, 0, 0)};
  const auto k = strategy_kpis(cells, "dodge");
  EXPECT_DOUBLE_EQ(k.collision_avoidance_rate_pct, 100.0);
  EXPECT_DOUBLE_EQ(k.mitigability_success_pct, 0.0);
  EXPECT_TRUE(std::isnan(k.mean_impact_speed_collisions_kph));
}

TEST(StrategyKpis, NoCellsGiveNaN) {
  const auto k = strategy_kpis({}, "dodge");
  EXPECT_EQ(k.cells, 0u);
  EXPECT_TRUE(std::isnan(k.collision_avoidance_rate_pct));
  EXPECT_TRUE(std::isnan(k.mean_delta_loss));
}

TEST(Levels, EdgesAreWhereTheDesignPutsThem) {
  const LevelCuts cuts = level_cuts(sim::SceneConfig{});
  const auto at = [&](Breakdown f, double speed, double ttc, double mu, double passage) {
    return level_of(f, cell("g", 0, speed, ttc, mu, passage, "G", 7), cuts);
  };
  EXPECT_EQ(at(sim::FactorRole::kEgoSpeed, 30, 1, 1, 3), "low");
  EXPECT_EQ(at(sim::FactorRole::kEgoSpeed, 40, 1, 1, 3), "low");
  EXPECT_EQ(at(sim::FactorRole::kEgoSpeed, 41, 1, 1, 3), "med");
  EXPECT_EQ(at(sim::FactorRole::kEgoSpeed, 56, 1, 1, 3), "med");
  EXPECT_EQ(at(sim::FactorRole::kEgoSpeed, 57, 1, 1, 3), "high");
  EXPECT_EQ(at(sim::FactorRole::kTtc, 50, 0.7, 1, 3), "low");
  EXPECT_EQ(at(sim::FactorRole::kTtc, 50, 0.25 + 7 * 0.06, 1, 3), "low");  // 0.67
  EXPECT_EQ(at(sim::FactorRole::kTtc, 50, 0.73, 1, 3), "med");
  EXPECT_EQ(at(sim::FactorRole::kTtc, 50, 1.3, 1, 3), "med");
  EXPECT_EQ(at(sim::FactorRole::kTtc, 50, 1.31, 1, 3), "high");
  EXPECT_EQ(at(sim::FactorRole::kFriction, 50, 1, 0.3, 3), "low");
  EXPECT_EQ(at(sim::FactorRole::kFriction, 50, 1, 0.35, 3), "med");
  EXPECT_EQ(at(sim::FactorRole::kFriction, 50, 1, 0.7, 3), "high");
  EXPECT_EQ(at(sim::FactorRole::kPassage, 50, 1, 1, 1.0), "narrow");
  EXPECT_EQ(at(sim::FactorRole::kPassage, 50, 1, 1, 1.61), "wide");
}

// Without the paper's cuts, speed and TTC are cut into thirds of the grid's feasible range.
TEST(Levels, ThirdsOfTheGridsRangeWithoutThePapersCuts) {
  std::vector<campaign::CellRecord> cells{cell("h", 0, 60, 0.5, 0.8, 3, "G", 7), cell("h", 1, 150, 2.0, 0.8, 3, "R", 7),
                                          cell("other", 0, 10, 9.0, 0.8, 3, "G", 7)};
  const LevelCuts cuts = level_cuts_by_thirds(sim::SceneConfig{}, cells, "h");
  EXPECT_DOUBLE_EQ(cuts.speed_low_max_kph, 90.0);
  EXPECT_DOUBLE_EQ(cuts.speed_med_max_kph, 120.0);
  EXPECT_DOUBLE_EQ(cuts.ttc_low_max_s, 1.0);
  EXPECT_DOUBLE_EQ(cuts.ttc_med_max_s, 1.5);
  EXPECT_DOUBLE_EQ(cuts.mu_med_min, LevelCuts{}.mu_med_min);
  EXPECT_EQ(level_of(sim::FactorRole::kEgoSpeed, cells[0], cuts), "low");
  EXPECT_EQ(level_of(sim::FactorRole::kEgoSpeed, cells[1], cuts), "high");
  // A grid without a feasible cell keeps the defaults.
  const LevelCuts none = level_cuts_by_thirds(sim::SceneConfig{}, cells, "missing");
  EXPECT_DOUBLE_EQ(none.speed_low_max_kph, LevelCuts{}.speed_low_max_kph);
}

TEST(GridKpis, SplitsByLevelWithCounts) {
  const auto kpis = grid_kpis(four_cells(), "fine", level_cuts(sim::SceneConfig{}));
  // 2 strategies × (1 + 3 + 3 + 3 + 2) levels.
  EXPECT_EQ(kpis.size(), 24u);
  const auto* low = find_kpis(kpis, "emergency_stop", sim::FactorRole::kEgoSpeed, "low");
  const auto* med = find_kpis(kpis, "emergency_stop", sim::FactorRole::kEgoSpeed, "med");
  const auto* high = find_kpis(kpis, "emergency_stop", sim::FactorRole::kEgoSpeed, "high");
  ASSERT_TRUE(low && med && high);
  EXPECT_EQ(low->cells, 1u);   // 40 km/h
  EXPECT_EQ(med->cells, 2u);   // 41 and 56 km/h
  EXPECT_EQ(high->cells, 1u);  // 57 km/h
  EXPECT_DOUBLE_EQ(low->collision_avoidance_rate_pct, 100.0);
  EXPECT_DOUBLE_EQ(med->mean_impact_speed_kph, 25.0);
  const auto* ttc_low = find_kpis(kpis, "dodge", sim::FactorRole::kTtc, "low");
  const auto* ttc_med = find_kpis(kpis, "dodge", sim::FactorRole::kTtc, "med");
  const auto* ttc_high = find_kpis(kpis, "dodge", sim::FactorRole::kTtc, "high");
  EXPECT_EQ(ttc_low->cells, 2u);   // 0.7 and 0.2
  EXPECT_EQ(ttc_med->cells, 1u);   // 1.3
  EXPECT_EQ(ttc_high->cells, 1u);  // 1.31
  EXPECT_DOUBLE_EQ(ttc_low->collision_avoidance_rate_pct, 50.0);
  EXPECT_EQ(find_kpis(kpis, "dodge", sim::FactorRole::kPassage, "narrow")->cells, 0u);
  EXPECT_EQ(find_kpis(kpis, "dodge", sim::FactorRole::kFriction, "high")->cells, 4u);
}

}  // namespace aggregate_test
}  // namespace emrm::results
