#include "emrm/scenario/odd.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "odd_support.hpp"

namespace emrm::scenario {
namespace odd_test {

using namespace test_support;  // NOLINT(google-build-using-namespace)
using ::testing::HasSubstr;

TEST(OddLoad, PosHelperCountsFromOne) {
  // The helper the error tests rely on.
  const Pos a = pos_of("ab\ncd", "a");
  const Pos d = pos_of("ab\ncd", "d");
  EXPECT_EQ(a.line, 1);
  EXPECT_EQ(a.column, 1);
  EXPECT_EQ(d.line, 2);
  EXPECT_EQ(d.column, 2);
}

TEST(OddLoad, FactorsKeepTheirKindsLevelsAndLabels) {
  const Odd odd = parse(kGood);
  EXPECT_EQ(odd.name, "unit odd");
  EXPECT_EQ(odd.seed, 7u);
  ASSERT_EQ(odd.factors.size(), 5u);
  EXPECT_EQ(odd.factor_names(), (std::vector<std::string>{"v", "n", "road", "lanes", "w"}));
  EXPECT_EQ(odd.factor_index("road"), 2u);
  EXPECT_FALSE(odd.factor_index("nope").has_value());
  const auto& v = odd.factors[0];
  const auto& n = odd.factors[1];
  const auto& road = odd.factors[2];
  const auto& lanes = odd.factors[3];
  const auto& w = odd.factors[4];
  EXPECT_EQ(v.type, FactorType::kContinuous);
  EXPECT_EQ(n.type, FactorType::kInteger);
  EXPECT_EQ(road.type, FactorType::kCategorical);
  EXPECT_EQ(lanes.type, FactorType::kConstant);
  EXPECT_EQ(v.unit, "km/h");
  EXPECT_EQ(v.levels(), 2);
  EXPECT_EQ(n.levels(), 2);
  EXPECT_EQ(road.levels(), 3);
  EXPECT_EQ(lanes.levels(), 1);
  EXPECT_EQ(w.levels(), 3);
  EXPECT_EQ(v.level_label(0), "[10, 20)");
  EXPECT_EQ(v.level_label(1), "[20, 40]");  // the last bin is closed
  EXPECT_EQ(n.level_label(0), "[0, 2)");
  EXPECT_EQ(road.level_label(1), "wet");
  EXPECT_EQ(lanes.level_label(0), "2");
  EXPECT_DOUBLE_EQ(v.domain_min(), 10.0);
  EXPECT_DOUBLE_EQ(v.domain_max(), 40.0);
  EXPECT_DOUBLE_EQ(road.domain_min(), 0.2);
  EXPECT_DOUBLE_EQ(road.domain_max(), 1.0);
  EXPECT_DOUBLE_EQ(lanes.domain_min(), 2.0);
  EXPECT_DOUBLE_EQ(lanes.domain_max(), 2.0);
  EXPECT_THAT(v.kinks, ElementsAre(15.0));
  EXPECT_DOUBLE_EQ(odd.cell_count(), 2.0 * 2 * 3 * 1 * 3);
  EXPECT_EQ(odd.strength, 2);
  EXPECT_EQ(odd.n_m, 2);
  EXPECT_DOUBLE_EQ(odd.epsilon, 0.3);
  EXPECT_EQ(odd.budget, 100u);
}

TEST(OddLoad, LevelOfUsesHalfOpenBinsAClosedLastBinAndClamps) {
  const Odd odd = parse(kGood);
  const auto& v = odd.factors[0];
  EXPECT_EQ(v.level_of(10.0), 0);
  EXPECT_EQ(v.level_of(19.999999), 0);
  EXPECT_EQ(v.level_of(20.0), 1);  // an edge starts the next bin
  EXPECT_EQ(v.level_of(40.0), 1);  // the top edge belongs to the last bin
  EXPECT_EQ(v.level_of(-5.0), 0);  // clamped
  EXPECT_EQ(v.level_of(1e9), 1);
  const auto& n = odd.factors[1];
  EXPECT_EQ(n.level_of(0.0), 0);
  EXPECT_EQ(n.level_of(1.0), 0);
  EXPECT_EQ(n.level_of(2.0), 1);
  EXPECT_EQ(n.level_of(5.0), 1);
  const auto& w = odd.factors[4];
  EXPECT_EQ(w.level_of(1.0), 1);
  EXPECT_EQ(w.level_of(2.0), 2);
  EXPECT_EQ(w.level_of(3.0), 2);
  // Every bin's lower edge maps to the bin, every value just below an inner edge to the one before.
  for (int k = 0; k < w.levels(); ++k) {
    EXPECT_EQ(w.level_of(w.lower(k)), k);
    if (k > 0) {
      EXPECT_EQ(w.level_of(std::nextafter(w.lower(k), -1.0)), k - 1);
    }
  }
  const auto& road = odd.factors[2];
  EXPECT_EQ(road.level_of(1.0), 0);
  EXPECT_EQ(road.level_of(0.6), 1);
  EXPECT_EQ(road.level_of(0.2), 2);
  EXPECT_EQ(road.level_of(0.55), 1);  // nearest class number
  EXPECT_EQ(road.level_of(-3.0), 2);
  EXPECT_EQ(odd.factors[3].level_of(123.0), 0);
}

TEST(OddLoad, DefaultPriorsFollowBinWidthIntegerCountOrUniform) {
  const Odd odd = parse(kGood);
  // Continuous: proportional to bin width, 10 and 20 of 30.
  EXPECT_THAT(odd.factors[0].prior,
              ElementsAre(::testing::DoubleNear(1.0 / 3, 1e-12), ::testing::DoubleNear(2.0 / 3, 1e-12)));
  // Integer [0, 2) holds {0, 1}, the closed [2, 5] holds {2, 3, 4, 5}: 2 and 4 of 6.
  EXPECT_THAT(odd.factors[1].prior,
              ElementsAre(::testing::DoubleNear(2.0 / 6, 1e-12), ::testing::DoubleNear(4.0 / 6, 1e-12)));
  // Categorical: uniform.
  for (double p : odd.factors[2].prior) EXPECT_NEAR(p, 1.0 / 3, 1e-12);
  EXPECT_THAT(odd.factors[3].prior, ElementsAre(::testing::DoubleNear(1.0, 1e-12)));
  // Given: kept.
  EXPECT_THAT(odd.factors[4].prior, ElementsAre(0.2, 0.5, 0.3));
  for (const auto& f : odd.factors) {
    ASSERT_EQ(static_cast<int>(f.prior.size()), f.levels()) << f.name;
    double sum = 0.0;
    for (double p : f.prior) sum += p;
    EXPECT_NEAR(sum, 1.0, 1e-12) << f.name;
  }
}

TEST(OddLoad, DefaultNominalIsTheCentreOfTheMostProbableBin) {
  const Odd odd = parse(kGood);
  EXPECT_DOUBLE_EQ(odd.factors[0].nominal, 30.0);  // [20, 40] has 2/3
  EXPECT_DOUBLE_EQ(odd.factors[1].nominal, 3.0);   // [2, 5]: an integer near its centre 3.5
  EXPECT_DOUBLE_EQ(odd.factors[2].nominal, 1.0);   // uniform: the first class, dry = 1.0
  EXPECT_DOUBLE_EQ(odd.factors[3].nominal, 2.0);   // the constant
  EXPECT_DOUBLE_EQ(odd.factors[4].nominal, 1.5);   // [1, 2) has 0.5
  // A given nominal wins; a categorical nominal is a class name.
  const Odd given =
      parse(replace_once(replace_once(kGood, "    kinks: [15]\n", "    kinks: [15]\n    nominal: 12.5\n"),
                         "    values: [1.0, 0.6, 0.2]\n", "    values: [1.0, 0.6, 0.2]\n    nominal: icy\n"));
  EXPECT_DOUBLE_EQ(given.factors[0].nominal, 12.5);
  EXPECT_DOUBLE_EQ(given.factors[2].nominal, 0.2);
}

TEST(OddLoad, ClassesWithoutValuesAreNumberedFromZero) {
  const Odd odd = parse(replace_once(kGood, "    values: [1.0, 0.6, 0.2]\n", ""));
  EXPECT_THAT(odd.factors[2].class_values, ElementsAre(0.0, 1.0, 2.0));
  EXPECT_EQ(odd.factors[2].level_of(2.0), 2);
}

TEST(OddLoad, InfluentialFactorsExcludeOptOutsAndSingleLevels) {
  const Odd odd = parse(kGood);
  // lanes is constant (one level), w says influential: false.
  EXPECT_THAT(odd.influential(), ElementsAre(0u, 1u, 2u));
  EXPECT_TRUE(odd.factors[0].influential);
  EXPECT_FALSE(odd.factors[3].influential);
  EXPECT_FALSE(odd.factors[4].influential);
  // A constant declared influential still has one level and is no part of Q_f.
  const Odd forced = parse(replace_once(kGood, "    value: 2\n", "    value: 2\n    influential: true\n"));
  EXPECT_THAT(forced.influential(), ElementsAre(0u, 1u, 2u));
}

TEST(OddLoad, CellOfMapsEveryFactorToItsLevel) {
  const Odd odd = parse(kGood);
  EXPECT_THAT(odd.cell_of(std::vector<double>{25.0, 1.0, 0.2, 2.0, 2.5}), ElementsAre(1, 0, 2, 0, 2));
  EXPECT_THAT(odd.cell_of(std::vector<double>{10.0, 5.0, 1.0, 2.0, 0.0}), ElementsAre(0, 1, 0, 0, 0));
  EXPECT_THAT(odd.cell_of(std::vector<double>{40.0, 2.0, 0.6, 2.0, 3.0}), ElementsAre(1, 1, 1, 0, 2));
}

TEST(OddLoad, PredicatesSeeClassValuesAndAllMustHold) {
  const std::string text = std::string(kGood) +
                           "relevance: \"v * road >= 12\"\n"
                           "constraints:\n"
                           "  - \"n <= 4 || road > 0.5\"\n"
                           "  - \"lanes == 2\"\n"
                           "tracked: \"road < 0.5\"\n";
  const Odd odd = parse(text);
  ASSERT_TRUE(odd.relevance.has_value());
  ASSERT_EQ(odd.constraints.size(), 2u);
  ASSERT_TRUE(odd.tracked.has_value());
  // dry = 1.0, wet = 0.6, icy = 0.2 are what the predicates see.
  EXPECT_TRUE(odd.admissible(std::vector<double>{15.0, 5.0, 1.0, 2.0, 1.0}));   // 15 >= 12, road > 0.5
  EXPECT_FALSE(odd.admissible(std::vector<double>{15.0, 1.0, 0.6, 2.0, 1.0}));  // 9 < 12
  EXPECT_TRUE(odd.admissible(std::vector<double>{20.0, 1.0, 0.6, 2.0, 1.0}));   // 12 >= 12
  EXPECT_FALSE(odd.admissible(std::vector<double>{40.0, 4.0, 0.2, 2.0, 1.0}));  // 40 * icy 0.2 = 8 < 12
}

TEST(OddLoad, ConstraintsExcludePointsThatRelevanceAdmits) {
  const std::string text = std::string(kGood) +
                           "relevance: \"v * road >= 6\"\n"
                           "constraints:\n"
                           "  - \"n <= 4 || road > 0.5\"\n";
  const Odd odd = parse(text);
  EXPECT_TRUE(odd.admissible(std::vector<double>{40.0, 4.0, 0.2, 2.0, 1.0}));           // 8 >= 6, n <= 4
  EXPECT_FALSE(odd.admissible(std::vector<double>{40.0, 5.0, 0.2, 2.0, 1.0}));          // n = 5 on ice
  EXPECT_TRUE(odd.admissible(std::vector<double>{40.0, 5.0, 0.6, 2.0, 1.0}));           // n = 5, wet
  EXPECT_FALSE(odd.admissible(std::vector<double>{20.0, 0.0, 0.2, 2.0, 1.0}));          // 4 < 6
  EXPECT_TRUE(parse(kGood).admissible(std::vector<double>{20.0, 0.0, 0.2, 2.0, 1.0}));  // no predicates
}

TEST(OddLoad, FileMalfunctionsCompileRegionsOverTheFactors) {
  const std::string text = std::string(kGood) +
                           "hazards: [H1, H9]\n"
                           "malfunctions:\n"
                           "  - id: M1\n"
                           "    region: \"v < 15 && road < 0.5\"\n"
                           "    hazards: [H1, H2]\n"
                           "    transitions: [\"S1 -a-> S2\"]\n"
                           "  - id: M2\n"
                           "    hazards: [H2]\n";
  const Odd odd = parse(text);
  ASSERT_EQ(odd.malfunctions.size(), 2u);
  EXPECT_EQ(odd.malfunctions[0].id, "M1");
  ASSERT_TRUE(odd.malfunctions[0].region.has_value());
  EXPECT_TRUE(odd.malfunctions[0].region->holds(std::vector<double>{12.0, 0.0, 0.2, 2.0, 0.0}));
  EXPECT_FALSE(odd.malfunctions[0].region->holds(std::vector<double>{12.0, 0.0, 0.6, 2.0, 0.0}));
  EXPECT_FALSE(odd.malfunctions[1].region.has_value());  // the whole relevant domain
  EXPECT_THAT(odd.malfunctions[0].transitions, ElementsAre("S1 -a-> S2"));
  // Declared hazards first, then those the modes name, without repeats.
  EXPECT_THAT(odd.hazards, ElementsAre("H1", "H9", "H2"));
}

TEST(OddLoad, ManualBaselineGridExpandsItsValues) {
  const std::string text = std::string(kGood) +
                           "baselines:\n"
                           "  manual:\n"
                           "    v: {from: 10, to: 40, levels: 4}\n"
                           "    w: [0.5, 2.5]\n";
  const Odd odd = parse(text);
  ASSERT_EQ(odd.manual_grid.size(), 2u);
  EXPECT_EQ(odd.manual_grid[0].first, 0u);
  EXPECT_THAT(odd.manual_grid[0].second, ElementsAre(10.0, 20.0, 30.0, 40.0));
  EXPECT_EQ(odd.manual_grid[1].first, 4u);
  EXPECT_THAT(odd.manual_grid[1].second, ElementsAre(0.5, 2.5));
}

// ---- the shipped example ------------------------------------------------------------------------

TEST(OddLoad, ShippedExampleTakesItsModesFromTheSafetyCase) {
  const Odd odd = load_odd(examples_dir() / "odd.yaml");
  ASSERT_EQ(odd.factors.size(), 5u);
  EXPECT_EQ(odd.factors[1].type, FactorType::kConstant);
  EXPECT_DOUBLE_EQ(odd.factors[1].nominal, 10.0);
  ASSERT_EQ(odd.malfunctions.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(odd.malfunctions[i].id, "UCA" + std::to_string(i + 1));
    EXPECT_TRUE(odd.malfunctions[i].region.has_value()) << odd.malfunctions[i].id;
    EXPECT_FALSE(odd.malfunctions[i].transitions.empty());
    EXPECT_FALSE(odd.malfunctions[i].hazards.empty());
  }
  EXPECT_EQ(odd.hazards.size(), 8u);
  EXPECT_EQ(odd.fsm_transitions.size(), 8u);
  ASSERT_TRUE(odd.safety_file.has_value());
  EXPECT_EQ(odd.safety_file->filename(), "safety.yaml");
  ASSERT_TRUE(odd.scene_file.has_value());
  EXPECT_TRUE(fs::is_regular_file(*odd.scene_file));
  // UCA regions were recompiled against the ODD's own factor order.
  const auto& uca1 = *odd.malfunctions[0].region;
  EXPECT_EQ(uca1.variables(), odd.factor_names());
  const double v = 72.0 / 3.6;
  const double stop_ttc = v / (2 * 1.0 * 9.81);  // braking alone just stops
  EXPECT_TRUE(uca1.holds(std::vector<double>{72, 10, stop_ttc - 0.01, 1.0, 3.0}));
  EXPECT_FALSE(uca1.holds(std::vector<double>{72, 10, stop_ttc + 0.01, 1.0, 3.0}));
  const auto& uca4 = *odd.malfunctions[3].region;  // passage < 2 or mu < 0.35
  EXPECT_TRUE(uca4.holds(std::vector<double>{50, 10, 1.5, 1.0, 1.5}));
  EXPECT_TRUE(uca4.holds(std::vector<double>{50, 10, 1.5, 0.2, 3.0}));
  EXPECT_FALSE(uca4.holds(std::vector<double>{50, 10, 1.5, 1.0, 3.0}));
  // The manual grid: 5 speeds x 6 TTCs.
  ASSERT_EQ(odd.manual_grid.size(), 2u);
  EXPECT_EQ(odd.manual_grid[0].second.size(), 5u);
  EXPECT_EQ(odd.manual_grid[1].second.size(), 6u);
  EXPECT_EQ(odd.strength, 2);
  EXPECT_EQ(odd.budget, 600u);
}

TEST(OddLoad, SafetyOverrideReplacesTheFilesEntry) {
  // A copy of the safety case whose UCAs are renamed; its FSM is found next to it.
  const fs::path dir = temp_dir() / "override";
  fs::create_directories(dir);
  std::string safety = read_text(examples_dir() / "safety.yaml");
  for (int i = 1; i <= 4; ++i) {
    const std::string from = "id: UCA" + std::to_string(i);
    const auto at = safety.find(from);
    ASSERT_NE(at, std::string::npos);
    safety.replace(at, from.size(), "id: ALT" + std::to_string(i));
  }
  write_text(dir / "other_safety.yaml", safety);
  fs::copy_file(examples_dir() / "emrm_fsm.yaml", dir / "emrm_fsm.yaml", fs::copy_options::overwrite_existing);
  const Odd odd = load_odd(examples_dir() / "odd.yaml", dir / "other_safety.yaml");
  ASSERT_EQ(odd.malfunctions.size(), 4u);
  EXPECT_EQ(odd.malfunctions[0].id, "ALT1");
  EXPECT_EQ(odd.malfunctions[3].id, "ALT4");
  EXPECT_EQ(*odd.safety_file, dir / "other_safety.yaml");
  EXPECT_EQ(odd.fsm_transitions.size(), 8u);
  // Without a `safety:` entry in the file, the override alone supplies the modes.
  std::string text = read_text(examples_dir() / "odd.yaml");
  text = replace_once(text, "safety: safety.yaml", "");
  const Odd bare = parse_odd(text, "odd.yaml", examples_dir(), examples_dir() / "safety.yaml");
  EXPECT_EQ(bare.malfunctions.size(), 4u);
  EXPECT_EQ(bare.hazards.size(), 8u);
  const Odd none = parse_odd(text, "odd.yaml", examples_dir());
  EXPECT_TRUE(none.malfunctions.empty());
  EXPECT_FALSE(none.safety_file.has_value());
}

TEST(OddLoad, MissingSafetyOverrideIsAUsageError) {
  EXPECT_THROW((void)load_odd(examples_dir() / "odd.yaml", temp_dir() / "no_such_safety.yaml"), UsageError);
}

TEST(OddLoad, MissingOddFileIsAnError) { EXPECT_THROW((void)load_odd(temp_dir() / "no_such_odd.yaml"), Error); }

TEST(OddLoad, UcaRegionNamingAFactorTheOddLacksIsAnErrorInTheSafetyCase) {
  // Without passage_m, UCA4's region "passage_m < 2.0 || mu < 0.35" cannot be recompiled.
  std::string text = read_text(examples_dir() / "odd.yaml");
  const auto from = text.find("  - name: passage_m");
  const auto to = text.find("\n\n", from);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  text.erase(from, to - from);
  try {
    (void)parse_odd(text, "odd.yaml", examples_dir());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string safety = read_text(examples_dir() / "safety.yaml");
    const Pos p = pos_of(safety, "passage_m < 2.0");
    EXPECT_EQ(fs::path(e.where().file).filename(), "safety.yaml") << e.what();
    EXPECT_EQ(e.where().line, p.line) << e.what();
    EXPECT_EQ(e.where().column, p.column) << e.what();
    EXPECT_THAT(e.what(), HasSubstr("passage_m"));
  }
}

// ---- ODDs built in code ----------------------------------------------------------------------------

// The message of the ConfigError validate() throws for `odd` ("" if none).
std::string validate_error(const Odd& odd) {
  try {
    validate(odd);
  } catch (const core::ConfigError& e) {
    return e.message();
  }
  return "";
}

TEST(OddValidate, TheLoadedOddsPass) {
  EXPECT_EQ(validate_error(parse(kGood)), "");
  EXPECT_EQ(validate_error(load_odd(examples_dir() / "odd.yaml")), "");
}

TEST(OddValidate, EachRuleNamesTheFieldPathAsTheFileWritesIt) {
  struct Bad {
    std::function<void(Odd&)> edit;
    std::string says;
  };
  const std::vector<Bad> cases{
      {[](Odd& o) { o.factors[0].name = "2v"; }, "odd: factors[0].name: factor name '2v' is not an identifier"},
      {[](Odd& o) { o.factors[1].name = "v"; }, "odd: factors[1].name: duplicate factor 'v'"},
      {[](Odd& o) {
         o.factors[0].edges = {10, 40, 20};
       },
       "odd: factors[0].bins: bin edges must increase strictly, but 20 follows 40 (position 3)"},
      {[](Odd& o) { o.factors[0].edges = {10}; },
       "odd: factors[0].bins: 'bins' needs at least two edges (one bin), got 1"},
      {[](Odd& o) {
         o.factors[1].edges = {0, 2.5, 5};
       },
       "odd: factors[1].bins: bin edges of an integer factor must be integers, got 2.5"},
      {[](Odd& o) { o.factors[0].kinks = {45}; },
       "odd: factors[0].kinks: kink 45 lies outside the open domain (10, 40)"},
      {[](Odd& o) { o.factors[2].classes.clear(); },
       "odd: factors[2]: a categorical factor needs 'classes': a list of names"},
      {[](Odd& o) { o.factors[2].classes[2] = "dry"; }, "odd: factors[2].classes: duplicate class 'dry'"},
      {[](Odd& o) { o.factors[2].class_values.pop_back(); },
       "odd: factors[2].values: 'values' has 2 numbers for 3 classes"},
      {[](Odd& o) {
         o.factors[4].prior = {0.5, 0.5};
       },
       "odd: factors[4].prior: 'prior' has 2 probabilities for 3 levels"},
      {[](Odd& o) {
         o.factors[4].prior = {0.2, 0.5, 0.4};
       },
       "odd: factors[4].prior: prior does not normalise: its probabilities sum to 1.1, expected 1"},
      {[](Odd& o) { o.factors[0].nominal = 50; },
       "odd: factors[0].nominal: nominal 50 lies outside the domain [10, 40]"},
      {[](Odd& o) { o.factors[1].nominal = 2.5; },
       "odd: factors[1].nominal: nominal of the integer factor 'n' must be a whole number, got 2.5"},
      {[](Odd& o) { o.factors[2].nominal = 0.5; },
       "odd: factors[2].nominal: nominal 0.5 is not the number of a class of 'road' (dry, wet, icy)"},
      {[](Odd& o) { o.factors.clear(); }, "odd: factors: an ODD needs at least one factor"},
      {[](Odd& o) { o.strength = 4; }, "odd: coverage.strength: strength must be 2 or 3, got 4"},
      {[](Odd& o) { o.n_c = 0; }, "odd: coverage.n_c: n_c must be >= 1, got 0"},
      {[](Odd& o) { o.n_m = -1; }, "odd: coverage.n_m: n_m must be >= 0, got -1"},
      {[](Odd& o) { o.epsilon = 0.6; }, "odd: coverage.epsilon: epsilon must lie in (0, 0.5), got 0.6"},
      {[](Odd& o) { o.delta = 1.5; }, "odd: coverage.delta: delta must lie in (0, 1), got 1.5"},
      {[](Odd& o) { o.budget = 0; }, "odd: coverage.budget: budget must be >= 1, got 0"},
      {[](Odd& o) {
         o.malfunctions = {Malfunction{"M1", "", {}, {}, {}, {}}, Malfunction{"M1", "", {}, {}, {}, {}}};
       },
       "odd: malfunctions[1].id: duplicate malfunction mode 'M1'"},
      {[](Odd& o) { o.relevance = core::Expression("v > 40", o.factor_names(), {}); },
       "odd: relevance: no point of the domain satisfies the relevance predicate"},
      {[](Odd& o) { o.constraints = {core::Expression("n > 9", o.factor_names(), {})}; },
       "odd: constraints[0]: the constraints are unsatisfiable"},
      {[](Odd& o) { o.tracked = core::Expression("v > 1", {"v"}, {}); },
       "odd: tracked: 'v > 1' is compiled over the factors (v), not over the ODD's (v, n, road, lanes, w)"},
  };
  for (const auto& bad : cases) {
    Odd odd = parse(kGood);
    bad.edit(odd);
    EXPECT_THAT(validate_error(odd), ::testing::StartsWith(bad.says));
  }
}

TEST(OddValidate, PlanBuildingAndTheCoverageCheckRejectABadOdd) {
  Odd odd = parse(kGood);
  odd.factors[4].prior = {0.5, 0.5, 0.5};
  for (const auto& run : std::vector<std::function<void()>>{[&] { (void)build_plan(odd); },
                                                            [&] { (void)measure_coverage(odd, {}, "none"); }}) {
    try {
      run();
      ADD_FAILURE() << "expected a ConfigError";
    } catch (const core::ConfigError& e) {
      EXPECT_EQ(e.path().str(), "factors[4].prior");
    }
  }
  odd = parse(kGood);
  odd.relevance = core::Expression("v > 40", odd.factor_names(), {});
  EXPECT_THROW((void)build_plan(odd), core::ConfigError);
  EXPECT_NO_THROW((void)build_plan(parse(kGood)));
}

}  // namespace odd_test
}  // namespace emrm::scenario
