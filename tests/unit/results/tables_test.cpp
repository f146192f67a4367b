#include "emrm/results/tables.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "emrm/results/aggregate.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::results {
namespace tables_test {

using ::testing::HasSubstr;

PaperReference shipped() {
  return load_paper_reference(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/paper_reference.yaml");
}

campaign::OutcomeRecord outcome(std::string strategy, bool avoided, double impact_kph, int level, int unmitigated) {
  campaign::OutcomeRecord o;
  o.strategy = std::move(strategy);
  o.avoided = avoided;
  o.contact = !avoided;
  o.impact_speed_kph = avoided ? 0.0 : impact_kph;
  o.loss_level = avoided ? 0 : level;
  o.delta_loss = unmitigated - o.loss_level;
  o.min_ttc_s = 0.5;
  return o;
}

// Two fine cells: 30 km/h avoided by everyone (G); 60 km/h avoided only by the evasive ones (Y).
std::vector<campaign::CellRecord> two_cells() {
  std::vector<campaign::CellRecord> cells(2);
  const std::vector<std::string> names{"emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident", "emrm"};
  for (int i = 0; i < 2; ++i) {
    auto& c = cells[static_cast<std::size_t>(i)];
    c.grid = "fine";
    c.index = i;
    c.factors = sim::CellInput{i == 0 ? 30.0 : 60.0, 1.0, 1.0, 3.0, 0.0};
    c.feasible = true;
    c.region = i == 0 ? sim::Region::kG : sim::Region::kY;
    c.unmitigated_loss_level = 7;
    for (const auto& n : names) c.outcomes.push_back(outcome(n, i == 0 || n != "emergency_stop", 40.0, 7, 7));
  }
  return cells;
}

TEST(Tables, EmrmVsBaselineShowsOursBesideThePapers) {
  const auto t = emrm_vs_baseline_table(two_cells(), shipped(), "fine");
  ASSERT_GE(t.rows.size(), 4u);
  EXPECT_EQ(t.rows[0][0], "Collision Avoidance Rate (%)");
  EXPECT_EQ(t.rows[0][1], "50.0 (paper 45)");   // emergency stop
  EXPECT_EQ(t.rows[0][2], "100.0 (paper 81)");  // dodge
  EXPECT_EQ(t.rows[1][1], "20.0 (paper 18.9)");
  EXPECT_EQ(t.rows[3][1], "3.50 (paper 3.29)");
  const auto md = core::to_markdown(t);
  EXPECT_THAT(md, HasSubstr("is our `drift_to_avoid`"));
  EXPECT_THAT(md, HasSubstr("Where ours differ"));
  const auto csv = core::to_csv(t);
  EXPECT_THAT(csv, HasSubstr("(paper 45)"));
}

TEST(Tables, ByParameterUsesThePapersLayout) {
  const auto t = by_parameter_table(two_cells(), shipped(), "fine", "", "", level_cuts(sim::SceneConfig{}));
  ASSERT_EQ(t.rows.size(), 4u);
  EXPECT_THAT(t.rows[0][0], HasSubstr("Ego speed"));
  // Emergency stop: 30 km/h avoided (low), 60 km/h not (high).
  EXPECT_EQ(t.rows[0][4], "100 / — / 0 (paper 65 / 46 / 18)");
  EXPECT_EQ(t.rows[0][5], "1 / 0 / 1 (paper 390 / 469 / 306)");
  EXPECT_EQ(t.rows[2][1], "100 (paper 81)");
  EXPECT_THAT(core::to_markdown(t), HasSubstr("collision-avoidance rates"));
}

TEST(Tables, RegionsShowThePapersFineGrid) {
  const auto t = regions_table(two_cells(), shipped());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (core::Row{"fine", "2", "2", "0", "50.0", "50.0", "0.0", "0.0"}));
  EXPECT_EQ(t.rows[1][0], "fine (paper)");
  EXPECT_EQ(t.rows[1][4], "44.5");
  EXPECT_THAT(core::to_markdown(t), HasSubstr("TTC ≥ v/(2μg)"));
}

TEST(Tables, WritesEveryFile) {
  const auto dir = std::filesystem::temp_directory_path() / "emrm-tables-test";
  std::filesystem::remove_all(dir);
  TableOptions options;
  options.cuts = level_cuts(sim::SceneConfig{});
  const auto files = write_tables(dir, two_cells(), shipped(), options);
  EXPECT_EQ(files.size(), 13u);
  for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
  std::ifstream in(dir / "tables" / "kpis.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_THAT(header, HasSubstr("mitigability_success_pct"));
  std::filesystem::remove_all(dir);
}

// An example without a paper_reference.yaml: every table shows ours alone, and there are no claims.
// A family's categorical factor (the highway's obstacle) breaks the by-parameter table and kpis.csv
// down by its levels: here the emergency stop avoids the truck's cell and not the deer's.
TEST(Tables, ACategoricalFactorIsBrokenDownByItsLevels) {
  sim::SceneConfig highway;
  highway.family = "highway_obstacle";
  const LevelCuts cuts = level_cuts(highway);
  ASSERT_EQ(cuts.categorical.size(), 2u);
  EXPECT_EQ(cuts.categorical[0].key, "obstacle");
  EXPECT_EQ(cuts.categorical[0].levels, (std::vector<std::string>{"truck", "deer"}));
  EXPECT_EQ(cuts.categorical[1].key, "roadside");
  EXPECT_TRUE(level_cuts(sim::SceneConfig{}).categorical.empty());  // the T-junction has none

  auto cells = two_cells();
  for (auto& c : cells) c.factors = sim::CellInput{c.factors.ego_speed_kph(), 1.2, 0.8, double(c.index), 6.25, 0.0};
  const auto t = by_parameter_table(cells, PaperReference{}, "fine", "", "", cuts);
  const auto row = std::find_if(t.rows.begin(), t.rows.end(),
                                [](const core::Row& r) { return r.front() == "Obstacle: truck / deer"; });
  ASSERT_NE(row, t.rows.end());
  EXPECT_EQ((*row)[1], "100 / 0");    // the emergency stop
  EXPECT_EQ((*row)[2], "100 / 100");  // the dodge
  EXPECT_EQ(row->back(), "1 / 1");
  const std::string csv = kpis_csv(cells, cuts);
  EXPECT_THAT(csv, HasSubstr("fine,emergency_stop,obstacle,truck,truck,1,1,0,"));
  EXPECT_THAT(csv, HasSubstr("fine,emergency_stop,obstacle,deer,deer,1,0,1,"));
  EXPECT_THAT(csv, HasSubstr("fine,emergency_stop,roadside,guardrail,guardrail,2,1,1,"));
}

TEST(Tables, WithoutThePapersNumbersOursStandAlone) {
  const PaperReference none;
  ASSERT_TRUE(none.empty());
  EXPECT_FALSE(shipped().empty());
  const auto baseline = emrm_vs_baseline_table(two_cells(), none, "fine");
  EXPECT_EQ(baseline.rows[0][1], "50.0");   // emergency stop, without "(paper ...)"
  EXPECT_EQ(baseline.rows[0][2], "100.0");  // dodge
  EXPECT_EQ(baseline.header.size(), 1u + sim::registered_strategies().entries().size());
  const auto by_parameter = by_parameter_table(two_cells(), none, "fine", "", "", level_cuts(sim::SceneConfig{}));
  // Ego speed: the emergency stop avoids the low cell only, the evasive strategies both.
  EXPECT_THAT(by_parameter.rows[0], ::testing::Contains("100 / — / 0"));
  EXPECT_THAT(by_parameter.rows[0], ::testing::Contains("100 / — / 100"));
  EXPECT_EQ(by_parameter.rows[0].size(), by_parameter.header.size());
  const auto regions = regions_table(two_cells(), none);
  ASSERT_EQ(regions.rows.size(), 1u);
  for (const auto* t : {&baseline, &by_parameter, &regions})
    EXPECT_THAT(core::to_markdown(*t), ::testing::Not(HasSubstr("paper "))) << t->title;

  const auto dir = std::filesystem::temp_directory_path() / "emrm-tables-no-paper-test";
  std::filesystem::remove_all(dir);
  TableOptions options;
  options.cuts = level_cuts(sim::SceneConfig{});
  const auto files = write_tables(dir, two_cells(), none, options);
  EXPECT_EQ(files.size(), 10u);  // no claims.{md,csv,tex}
  EXPECT_FALSE(std::filesystem::exists(dir / "tables" / "claims.md"));
  std::filesystem::remove_all(dir);
}

}  // namespace tables_test
}  // namespace emrm::results
