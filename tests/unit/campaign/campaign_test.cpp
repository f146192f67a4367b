#include "emrm/campaign/campaign.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "emrm/core/domain.hpp"
#include "emrm/core/yaml.hpp"
#include "tjunction.hpp"

namespace emrm::campaign {
namespace campaign_test {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

const std::string kShippedCampaign = std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/campaign.yaml";

std::vector<double> expand(const std::string& yaml) {
  return core::expand_values(core::YamlNode::parse(yaml, "f.yaml"));
}

Campaign parse(const std::string& text, bool force = false) {
  return parse_campaign(text, "c.yaml", std::string(EMRM_SOURCE_DIR) + "/examples/tjunction", force);
}

// The message of the InputError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text, bool force = false) {
  try {
    (void)parse(text, force);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ExpandFactor, AValueIsOneLevel) { EXPECT_THAT(expand("0.5"), ElementsAre(0.5)); }

TEST(ExpandFactor, AListKeepsItsOrder) { EXPECT_THAT(expand("[3, 1.0, 2]"), ElementsAre(3.0, 1.0, 2.0)); }

TEST(ExpandFactor, AStepRangeIncludesItsEndAndPrintsCleanly) {
  const auto v = expand("{from: 0.25, to: 2.95, step: 0.06}");
  ASSERT_EQ(v.size(), 46u);
  EXPECT_EQ(v.front(), 0.25);
  EXPECT_EQ(v[1], 0.31);  // exactly the number a reader sees, not 0.31000000000000005
  EXPECT_EQ(v[10], 0.85);
  EXPECT_EQ(v.back(), 2.95);
  EXPECT_EQ(expand("{from: 30, to: 72, step: 1}").size(), 43u);
  EXPECT_THAT(expand("{from: 1, to: 2.5, step: 1}"), ElementsAre(1.0, 2.0));  // `to` not on the step
}

TEST(ExpandFactor, LevelsAreEvenlySpacedFromTo) {
  EXPECT_THAT(expand("{from: 30, to: 72, levels: 5}"), ElementsAre(30.0, 40.5, 51.0, 61.5, 72.0));
  EXPECT_THAT(expand("{from: 0.25, to: 2.95, levels: 6}"), ElementsAre(0.25, 0.79, 1.33, 1.87, 2.41, 2.95));
  EXPECT_EQ(expand("{from: 0.1, to: 1.0, levels: 10}")[2], 0.3);
  EXPECT_THAT(expand("{from: 2, to: 2, levels: 1}"), ElementsAre(2.0));
}

// A categorical factor's values are its levels' names, read as their indices.
TEST(ExpandFactor, ACategoricalFactorTakesItsLevelsByName) {
  const std::vector<std::string> levels{"truck", "deer"};
  const auto expand_levels = [&](const std::string& yaml) {
    return core::expand_values(core::YamlNode::parse(yaml, "f.yaml"), levels);
  };
  EXPECT_THAT(expand_levels("deer"), ElementsAre(1.0));
  EXPECT_THAT(expand_levels("[deer, truck]"), ElementsAre(1.0, 0.0));
  for (const auto& [yaml, what] : std::vector<std::pair<std::string, std::string>>{
           {"moose", "f.yaml:1:1: error: expected one of the levels truck, deer, got 'moose'"},
           {"[truck, 1]", "f.yaml:1:9: error: expected one of the levels truck, deer, got '1'"},
           {"{from: 0, to: 1, step: 1}", "f.yaml:1:1: error: expected one of the levels truck, deer, got a mapping"},
           {"[]", "empty list of values"}}) {
    try {
      (void)expand_levels(yaml);
      ADD_FAILURE() << yaml << " was read";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(what)) << yaml;
    }
  }
  EXPECT_THAT(core::expand_values(core::YamlNode::parse("[1, 2]", "f.yaml"), {}), ElementsAre(1.0, 2.0));
}

TEST(ExpandFactor, RejectsBadRangesAtTheirPlace) {
  EXPECT_THROW(expand("{from: 2, to: 1, step: 0.5}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2, step: 0}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2, step: -1}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2, levels: 0}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2, step: 1, levels: 2}"), InputError);
  EXPECT_THROW(expand("{from: 1, to: 2, stride: 1}"), InputError);
  EXPECT_THROW(expand("[]"), InputError);
  EXPECT_THROW(expand("fast"), InputError);
}

TEST(LoadCampaign, TheShippedCampaignHasThePapersGrids) {
  const Campaign c = load_campaign(kShippedCampaign);
  std::vector<std::string> names;
  std::vector<std::size_t> sizes;
  for (const auto& g : c.grids) {
    names.push_back(g.name);
    sizes.push_back(g.cells.size());
  }
  EXPECT_THAT(names, ElementsAre("coarse", "fine", "speed_mu", "ttc_mu", "passage", "canonical"));
  EXPECT_THAT(sizes, ElementsAre(30u, 43u * 46u, 430u, 260u, 60u, 12u));
  EXPECT_EQ(c.strategies, sim::strategy_names());
  EXPECT_EQ(c.seed, 1u);
  ASSERT_TRUE(c.scene_file.has_value());
  EXPECT_EQ(*c.scene_file, "scene.yaml");
}

TEST(LoadCampaign, TheFineGridHas1165FeasibleCells) {
  const Campaign c = load_campaign(kShippedCampaign);
  const GridSpec& fine = c.grids[1];
  ASSERT_EQ(fine.cells.size(), 1978u);
  int feasible = 0;
  for (const auto& cell : fine.cells) feasible += sim::Scene(c.scene, cell).feasible() ? 1 : 0;
  EXPECT_EQ(feasible, 1165);
  // Factor order speed, TTC, …: TTC varies faster than speed.
  EXPECT_EQ(test::named(fine.cells[0]).speed_kph, 30.0);
  EXPECT_EQ(test::named(fine.cells[1]).speed_kph, 30.0);
  EXPECT_EQ(test::named(fine.cells[1]).ttc_s, 0.31);
  EXPECT_EQ(test::named(fine.cells[46]).speed_kph, 31.0);
  EXPECT_EQ(test::named(fine.cells[0]).truck_speed_kph, c.scene.truck.speed_kph);
}

TEST(LoadCampaign, CanonicalCellsTakeGridDefaults) {
  const Campaign c = load_campaign(kShippedCampaign);
  const GridSpec& canonical = c.grids.back();
  for (const auto& cell : canonical.cells) EXPECT_EQ(cell.time_to_collision_s(), 0.6);
  EXPECT_EQ(test::named(canonical.cells[0]).passage_m, 3.2);
  EXPECT_EQ(test::named(canonical.cells[7]).mu, 0.15);
  EXPECT_EQ(test::named(canonical.cells[8]).speed_kph, 57.6);
}

TEST(LoadCampaign, DefaultsWithoutSceneOrStrategies) {
  const Campaign c = parse("grids:\n  - name: g\n    speed_kph: [30, 40]\n");
  EXPECT_FALSE(c.scene_file.has_value());
  EXPECT_EQ(c.strategies, sim::strategy_names());
  ASSERT_EQ(c.grids[0].cells.size(), 2u);
  EXPECT_EQ(test::named(c.grids[0].cells[1]).ttc_s, 1.0);
  EXPECT_EQ(test::named(c.grids[0].cells[1]).truck_speed_kph, 10.0);
}

TEST(LoadCampaign, ReportsMistakesAtTheirLineAndColumn) {
  EXPECT_THAT(error_of("grids:\n  - name: g\n    speeed_kph: 30\n"),
              HasSubstr("c.yaml:3:5: error: unknown grid field"));
  EXPECT_THAT(error_of("strategies: [dodge, swerve]\ngrids:\n  - name: g\n"), HasSubstr("c.yaml:1:21:"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    ttc_s: {from: 2, to: 1, step: 0.1}\n"),
              HasSubstr("c.yaml:3:12: error: reversed range"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    ttc_s: {from: 1, to: 2, step: 0}\n"), HasSubstr("c.yaml:3:"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    ttc_s: []\n"), HasSubstr("c.yaml:3:12: error: empty"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    mu: [0.5, 3.0]\n"), HasSubstr("c.yaml:3:9: error: grid 'g': mu"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n  - name: g\n"), HasSubstr("c.yaml:3:5: error: duplicate grid name 'g'"));
  EXPECT_THAT(error_of("seeds: 1\ngrids: []\n"), HasSubstr("c.yaml:1:1: error: unknown campaign field"));
  // The nearest known field, as the scene's and the ODD's errors say it.
  EXPECT_THAT(error_of("seeds: 1\ngrids: []\n"), HasSubstr("'seeds' (did you mean 'seed'?)"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    muu: 0.5\n"),
              HasSubstr("c.yaml:3:5: error: unknown grid field 'muu' (did you mean 'mu'?)"));

  EXPECT_THAT(error_of("scene: nowhere.yaml\ngrids:\n  - name: g\n"), HasSubstr("c.yaml:1:8:"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    cells:\n      - {speed_kph: 30, ttc: 1}\n"),
              HasSubstr("c.yaml:4:25: error: unknown factor 'ttc'"));
  EXPECT_THAT(error_of("grids: [\n"), HasSubstr("c.yaml:"));
}

TEST(LoadCampaign, RefusesAGridAboveMaxCellsUnlessForced) {
  const std::string text = "max_cells: 10\ngrids:\n  - name: big\n    speed_kph: {from: 30, to: 40, step: 1}\n";
  EXPECT_THAT(error_of(text),
              HasSubstr("c.yaml:3:5: error: grid 'big' has 11 cells, more than the maximum 10; raise max_cells or "
                        "pass --force"));
  EXPECT_EQ(parse(text, /*force=*/true).grids[0].cells.size(), 11u);
}

// A file of a few lines must not make the loader allocate gigabytes: these limits hold with --force
// too, and are checked before anything is expanded.
TEST(LoadCampaign, HardLimitsHoldEvenWhenForced) {
  EXPECT_THAT(error_of("grids:\n  - name: big\n    speed_kph: {from: 30, to: 72, levels: 100000000}\n", true),
              HasSubstr("c.yaml:3:43: error: levels must be <= 1000000"));
  EXPECT_THAT(error_of("grids:\n  - name: big\n    speed_kph: {from: 0.001, to: 400, step: 0.0001}\n", true),
              HasSubstr("more than the 1000000 a factor may have"));
  // 2 000 × 3 000 = 6 million cells, each factor well inside its own limit.
  const std::string product =
      "grids:\n  - name: big\n    speed_kph: {from: 5, to: 100, levels: 2000}\n"
      "    ttc_s: {from: 0.1, to: 4, levels: 3000}\n";
  EXPECT_THAT(error_of(product, true), HasSubstr("c.yaml:2:5: error: the campaign's grids have 6000000 cells, "
                                                 "more than the 5000000 a campaign may hold even with --force"));
  // Three grids within max_cells each, too many together.
  std::string three = "max_cells: 5000000\ngrids:\n";
  for (const char* name : {"a", "b", "c"})
    three += std::string("  - name: ") + name +
             "\n    speed_kph: {from: 5, to: 100, levels: 1000}\n    ttc_s: {from: 0.1, to: 4, levels: 2000}\n";
  EXPECT_THAT(error_of(three), HasSubstr("c.yaml:9:5: error: the campaign's grids have 6000000 cells"));
  EXPECT_THAT(error_of("max_cells: 1000000000000\ngrids:\n  - name: g\n"),
              HasSubstr("c.yaml:1:12: error: max_cells must lie in [1, 5000000], got 1000000000000"));
}

// ---- campaigns built in code ----------------------------------------------------------------------

Campaign code_built() {
  Campaign c;
  c.strategies = {"emergency_stop", "dodge"};
  GridSpec grid;
  grid.name = "g";
  grid.cells = {{30.0, 1.0, 1.0, 3.0, 10.0}, {40.0, 1.5, 0.8, 2.0, 5.0}};
  c.grids.push_back(grid);
  return c;
}

// The message of the ConfigError validate() throws for `c` ("" if none).
std::string validate_error(const Campaign& c, bool force = false) {
  try {
    validate(c, force);
  } catch (const core::ConfigError& e) {
    return e.message();
  }
  return "";
}

TEST(ValidateCampaign, AGoodCodeBuiltCampaignAndTheShippedOnePass) {
  EXPECT_EQ(validate_error(code_built()), "");
  EXPECT_EQ(validate_error(load_campaign(kShippedCampaign)), "");
}

TEST(ValidateCampaign, EachRuleNamesTheFieldPath) {
  struct Bad {
    std::function<void(Campaign&)> edit;
    std::string says;
  };
  const std::vector<Bad> cases{
      {[](Campaign& c) { c.scene.road.lane_width_m = -1; },
       "campaign: scene.road.lane_width_m: expected a value > 0, got -1"},
      {[](Campaign& c) { c.strategies[1] = "swerve"; }, "campaign: strategies[1]: unknown strategy 'swerve'"},
      {[](Campaign& c) { c.strategies[1] = "emergency_stop"; },
       "campaign: strategies[1]: strategy 'emergency_stop' is listed twice"},
      {[](Campaign& c) { c.strategies.clear(); }, "campaign: strategies: the list of strategies is empty"},
      {[](Campaign& c) { c.max_cells = 0; }, "campaign: max_cells: max_cells must lie in [1, 5000000], got 0"},
      {[](Campaign& c) { c.grids.clear(); }, "campaign: grids: a campaign needs at least one grid"},
      {[](Campaign& c) { c.grids[0].name.clear(); }, "campaign: grids[0].name: a grid name must not be empty"},
      {[](Campaign& c) { c.grids.push_back(c.grids[0]); }, "campaign: grids[1]: duplicate grid name 'g'"},
      {[](Campaign& c) { c.grids[0].cells.clear(); }, "campaign: grids[0].cells: grid 'g' has an empty cells list"},
      {[](Campaign& c) { c.grids[0].cells[1][sim::kFrictionFactor] = 3.0; },
       "campaign: grids[0].cells[1]: grid 'g': mu must be"},
      {[](Campaign& c) { c.grids[0].seeds = {7}; }, "campaign: grids[0].seeds: grid 'g' has 1 seeds for 2 cells"},
      {[](Campaign& c) { c.max_cells = 1; },
       "campaign: grids[0]: grid 'g' has 2 cells, more than the maximum 1; raise max_cells or pass --force"},
  };
  for (const auto& bad : cases) {
    Campaign c = code_built();
    bad.edit(c);
    EXPECT_THAT(validate_error(c), ::testing::StartsWith(bad.says));
  }
}

TEST(ValidateCampaign, ForceLiftsOnlyTheCellLimit) {
  Campaign c = code_built();
  c.max_cells = 1;
  EXPECT_EQ(validate_error(c, /*force=*/true), "");
  c.grids[0].cells[0][sim::kEgoSpeedFactor] = 0;
  EXPECT_THAT(validate_error(c, /*force=*/true), HasSubstr("grids[0].cells[0]: grid 'g': speed_kph"));
}

TEST(ValidateCampaign, TheFileReportsTheSameRulesAtTheirNodes) {
  // An explicit cell: at its mapping. A product grid: at the first factor value that is bad alone,
  // even when another factor's bad value comes first in the expansion.
  EXPECT_THAT(error_of("grids:\n  - name: g\n    cells:\n      - {speed_kph: 30}\n      - {mu: 3}\n"),
              HasSubstr("c.yaml:5:9: error: grid 'g': mu must be"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    passage_m: [1, -1]\n    truck_speed_kph: [-1, 5]\n"),
              HasSubstr("c.yaml:3:16: error: grid 'g': passage_m must be"));
  EXPECT_THAT(error_of("grids:\n  - name: ''\n"), HasSubstr("c.yaml:2:11: error: a grid name must not be empty"));
  EXPECT_THAT(error_of("grids:\n  - name: g\n    cells: []\n"),
              HasSubstr("c.yaml:3:12: error: grid 'g' has an empty cells list"));
  EXPECT_THAT(error_of("strategies: [dodge, dodge]\ngrids:\n  - name: g\n"),
              HasSubstr("c.yaml:1:21: error: strategy 'dodge' is listed twice"));
  EXPECT_THAT(error_of("strategies: []\ngrids:\n  - name: g\n"),
              HasSubstr("c.yaml:1:13: error: the list of strategies is empty"));
  EXPECT_THAT(error_of("max_cells: 0\ngrids:\n  - name: g\n"),
              HasSubstr("c.yaml:1:12: error: max_cells must lie in [1, 5000000], got 0"));
  EXPECT_THAT(error_of("grids: []\n"), HasSubstr("c.yaml:1:8: error: a campaign needs at least one grid"));
}

TEST(CellSeed, IsTheDerivedSeedOfTheCellsKeyAndDistinctPerCell) {
  const Campaign c = load_campaign(kShippedCampaign);
  const sim::CellInput cell{50.0, 0.31, 1.0, 3.0, 10.0};
  EXPECT_EQ(cell_key("fine", cell), "fine 50 0.31 1 3 10");
  EXPECT_EQ(cell_seed(c, "fine", cell), sim::derive_seed(1, "fine 50 0.31 1 3 10"));
  // The canonical grid repeats its base cell in every row: equal keys, equal seeds, by design.
  std::set<std::string> keys;
  std::set<std::uint64_t> seeds;
  for (const auto& g : c.grids)
    for (const auto& x : g.cells) {
      keys.insert(cell_key(g.name, x));
      seeds.insert(cell_seed(c, g.name, x));
    }
  EXPECT_EQ(keys.size(), total_cells(c) - 2);
  EXPECT_EQ(seeds.size(), keys.size());
}

TEST(ConfigHash, ChangesWithWhatDecidesResultsOnly) {
  const std::string text = "seed: 1\ngrids:\n  - name: g\n    speed_kph: [30, 40]\n";
  const std::string h = config_hash(parse(text));
  EXPECT_EQ(h.size(), 16u);
  EXPECT_EQ(config_hash(parse(text + "# a comment\n")), h);
  EXPECT_NE(config_hash(parse("seed: 2\ngrids:\n  - name: g\n    speed_kph: [30, 40]\n")), h);
  EXPECT_NE(config_hash(parse("seed: 1\ngrids:\n  - name: g\n    speed_kph: [30, 41]\n")), h);
  EXPECT_NE(config_hash(parse("seed: 1\nstrategies: [dodge]\ngrids:\n  - name: g\n    speed_kph: [30, 40]\n")), h);
}

TEST(ToRecord, ConvertsSpeedsToKilometresPerHour) {
  const sim::SceneConfig scene;
  const sim::CellInput cell{40.0, 1.0, 1.0, 3.0, 10.0};
  const sim::CellResult result = sim::simulate_cell(scene, cell, {});
  const CellRecord r = to_record(sim::SceneConfig{}, "g", 7, 42, result);
  EXPECT_EQ(r.grid, "g");
  EXPECT_EQ(r.index, 7);
  EXPECT_EQ(r.seed, 42u);
  EXPECT_EQ(r.factors.ego_speed_kph(), 40.0);
  EXPECT_EQ(r.region, result.region);
  EXPECT_DOUBLE_EQ(r.unmitigated_impact_speed_kph, result.unmitigated.impact_speed_mps * 3.6);
  ASSERT_EQ(r.outcomes.size(), result.strategies.size());
  for (std::size_t i = 0; i < r.outcomes.size(); ++i) {
    EXPECT_EQ(r.outcomes[i].strategy, result.strategies[i].strategy);
    EXPECT_DOUBLE_EQ(r.outcomes[i].delta_v_kph, result.strategies[i].impact.delta_v_mps * 3.6);
    EXPECT_EQ(r.outcomes[i].loss_level, result.strategies[i].impact.loss_level);
    EXPECT_EQ(r.outcomes[i].fsm_trace, result.strategies[i].fsm_trace);
  }
}

}  // namespace campaign_test
}  // namespace emrm::campaign
