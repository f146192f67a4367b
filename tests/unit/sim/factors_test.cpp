// The factor table (sim/factors.hpp): a scenario's factors named once, their order, roles, limits
// and defaults; and the T-junction's table as every command reads it.

#include "emrm/sim/factors.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace factors_test {

using ::testing::HasSubstr;

Factor factor(std::string key, FactorRole role, double low = 0.0, double high = 10.0) {
  Factor f;
  f.key = std::move(key);
  f.unit = "1";
  f.what = "value";
  f.role = role;
  f.limits.low = low;
  f.limits.high = high;
  f.default_value = (low + high) / 2.0;
  return f;
}

// A scenario of another shape: the method's three factors, then two of its own.
FactorTable toy_table() {
  return FactorTable({factor("v", FactorRole::kEgoSpeed), factor("t", FactorRole::kTtc),
                      factor("f", FactorRole::kFriction, 0.0, 2.0), factor("gap", FactorRole::kPassage),
                      factor("lateral", FactorRole::kOther, -1.0, 1.0)});
}

TEST(FactorTable, FindsFactorsByKeyAndRole) {
  const FactorTable t = toy_table();
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t.find("gap"), 3u);
  EXPECT_EQ(t.find("none"), std::nullopt);
  EXPECT_EQ(t.find(FactorRole::kPassage), 3u);
  EXPECT_EQ(t.find(FactorRole::kTtc), kTtcFactor);
  EXPECT_EQ(t.key_list(), "v, t, f, gap, lateral");
}

TEST(FactorTable, DefaultsSetAndValidateACell) {
  const FactorTable t = toy_table();
  CellInput c = t.defaults();
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[4], 0.0);
  EXPECT_TRUE(t.set(c, "lateral", -0.5));
  EXPECT_FALSE(t.set(c, "speed", 1.0));
  EXPECT_EQ(c[4], -0.5);
  EXPECT_NO_THROW(t.validate(c));
  t.set(c, "f", 3.0);
  try {
    t.validate(c);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& e) {
    EXPECT_THAT(e.what(), HasSubstr("f must be a finite value with 0 < f <= 2, got 3"));
  }
  t.set(c, "f", std::numeric_limits<double>::quiet_NaN());
  EXPECT_THROW(t.validate(c), UsageError);
  EXPECT_THROW(t.validate(CellInput{1.0, 1.0}), UsageError);  // too few values
}

TEST(FactorTable, RefusesATableWithoutTheMethodsFactorsFirst) {
  EXPECT_THROW(FactorTable({factor("t", FactorRole::kTtc), factor("v", FactorRole::kEgoSpeed),
                            factor("f", FactorRole::kFriction)}),
               std::logic_error);
  EXPECT_THROW(FactorTable({factor("v", FactorRole::kEgoSpeed), factor("t", FactorRole::kTtc)}), std::logic_error);
  EXPECT_THROW(FactorTable({factor("v", FactorRole::kEgoSpeed), factor("t", FactorRole::kTtc),
                            factor("f", FactorRole::kFriction), factor("v", FactorRole::kOther)}),
               std::logic_error);  // a key twice
  EXPECT_THROW(FactorTable({factor("v", FactorRole::kEgoSpeed), factor("t", FactorRole::kTtc),
                            factor("f", FactorRole::kFriction), factor("a", FactorRole::kPassage),
                            factor("b", FactorRole::kPassage)}),
               std::logic_error);  // a role twice
  std::vector<Factor> many{factor("v", FactorRole::kEgoSpeed), factor("t", FactorRole::kTtc),
                           factor("f", FactorRole::kFriction)};
  for (std::size_t i = many.size(); i <= kMaxFactors; ++i)
    many.push_back(factor("x" + std::to_string(i), FactorRole::kOther));
  EXPECT_THROW(FactorTable{many}, std::logic_error);
}

// A categorical factor holds a level's index: whole numbers from 0 to its last level, and nothing
// else; its role is the scenario's own and its limits follow from its levels.
TEST(FactorTable, ACategoricalFactorTakesTheIndicesOfItsLevels) {
  std::vector<Factor> factors = method_factors(50.0, 1.0, 1.0);
  factors.push_back(categorical_factor("kind", "kind", {"car", "van", "bus"}));
  const FactorTable table(factors);
  const Factor& kind = table[3];
  for (const double v : {0.0, 1.0, 2.0}) EXPECT_TRUE(kind.accepts(v)) << v;
  for (const double v : {-1.0, 0.5, 3.0, std::nan("")}) EXPECT_FALSE(kind.accepts(v)) << v;
  EXPECT_EQ(kind.value_text(2.0), "bus");
  EXPECT_EQ(kind.parse("van"), 1.0);
  EXPECT_EQ(cell_text(table, {50.0, 1.0, 1.0, 2.0}), "50 km/h, TTC 1 s, mu 1, bus");
  EXPECT_THAT(kind.refusal(3.0), HasSubstr("kind must be one of the levels car (0), van (1), bus (2), got 3"));
  std::vector<Factor> passage = factors;
  passage[3].role = FactorRole::kPassage;
  EXPECT_THROW(FactorTable{passage}, std::logic_error);
  std::vector<Factor> wide = factors;
  wide[3].limits.high = 5.0;
  EXPECT_THROW(FactorTable{wide}, std::logic_error);
}

TEST(CellInput, ComparesValueByValueAndReadsTheMethodsFactors) {
  const CellInput a{50.0, 1.2, 0.8, 3.0};
  EXPECT_EQ(a, (CellInput{50.0, 1.2, 0.8, 3.0}));
  EXPECT_NE(a, (CellInput{50.0, 1.2, 0.8}));
  EXPECT_NE(a, (CellInput{50.0, 1.2, 0.8, 3.5}));
  EXPECT_EQ(a.ego_speed_kph(), 50.0);
  EXPECT_EQ(a.time_to_collision_s(), 1.2);
  EXPECT_EQ(a.friction(), 0.8);
  EXPECT_THROW((CellInput(std::vector<double>(kMaxFactors + 1, 1.0))), std::logic_error);
}

TEST(CellText, NamesEachFactorByItsBrief) {
  const FactorTable t = scenario_factors(SceneConfig{});
  EXPECT_EQ(cell_text(t, TJunctionCell{}), "50 km/h, TTC 1 s, mu 1, passage 3 m, truck 10 km/h");
}

// The T-junction's table: its keys in cell order, the roles the method reads, the scene's defaults.
TEST(TJunctionFactors, FollowTheScene) {
  SceneConfig config;
  config.truck.speed_kph = 25.0;
  config.road.shoulder_m = 0.5;
  const FactorTable t = scenario_factors(config);
  EXPECT_EQ(t.key_list(), "speed_kph, ttc_s, mu, passage_m, truck_speed_kph");
  EXPECT_EQ(t.find(FactorRole::kPassage), 3u);
  EXPECT_EQ(t.defaults()[4], 25.0);  // the scene's truck speed
  EXPECT_DOUBLE_EQ(t[3].limits.high, config.road.drivable_max_y_m() - config.road.drivable_min_y_m());
  const TJunctionCell named = TJunctionCell::of(TJunctionCell{60.0, 0.9, 0.5, 2.0, 5.0});
  EXPECT_EQ(named.passage_m, 2.0);
  EXPECT_EQ(named.truck_speed_kph, 5.0);
}

// validate_cell checks a cell without building the table's texts: it refuses exactly what the
// table refuses, with the table's message, at every limit and around it.
TEST(TJunctionFactors, ValidateCellRefusesWhatTheTableRefuses) {
  const SceneConfig config;
  const FactorTable table = scenario_factors(config);
  ASSERT_NO_THROW(table.validate(table.defaults()));
  const auto message = [](const auto& check) -> std::string {
    try {
      check();
    } catch (const UsageError& e) {
      return e.what();
    }
    return "";
  };
  std::size_t refused = 0, tried = 0;
  for (std::size_t f = 0; f < table.size(); ++f) {
    const FactorLimits& limits = table[f].limits;
    for (const double v : {limits.low - 1.0, limits.low, std::nextafter(limits.low, 1e300), limits.low + 0.5,
                           limits.high, std::nextafter(limits.high, 1e300), limits.high + 1.0,
                           std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      CellInput cell = table.defaults();
      cell[f] = v;
      const std::string by_table = message([&] { table.validate(cell); });
      EXPECT_EQ(message([&] { validate_cell(config, cell); }), by_table) << table[f].key << " = " << v;
      refused += !by_table.empty();
      ++tried;
    }
  }
  EXPECT_GT(refused, table.size());  // each factor refuses NaN, at least
  EXPECT_LT(refused, tried);
  const CellInput short_cell{50.0, 1.0, 0.8};
  EXPECT_EQ(message([&] { validate_cell(config, short_cell); }), message([&] { table.validate(short_cell); }));
  EXPECT_NE(message([&] { validate_cell(config, short_cell); }), "");
}

}  // namespace factors_test
}  // namespace emrm::sim
