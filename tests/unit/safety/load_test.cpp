#include "emrm/safety/load.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "example_case.hpp"
#include "input_error.hpp"

namespace emrm::safety {
namespace load_test {

using testing::example_text;
using ::testing::HasSubstr;
using testing::line_of;
using testing::replace_once;

// Parses `text` and returns the InputError it must raise.
InputError parse_error(const std::string& text) {
  return emrm::testing::input_error_of([&] { (void)parse_safety_case(text, "case.yaml"); }, text);
}

TEST(SafetyLoad, ShippedExampleLoadsWithEveryEntity) {
  const auto sc = parse_safety_case(example_text(), "safety.yaml");
  EXPECT_EQ(sc.losses.size(), 7u);
  EXPECT_EQ(sc.hazards.size(), 8u);
  EXPECT_EQ(sc.control_actions.size(), 1u);
  EXPECT_EQ(sc.ucas.size(), 4u);
  EXPECT_FALSE(sc.find_loss("L6")->reversible);
  EXPECT_TRUE(sc.find_loss("L5")->reversible);
  EXPECT_EQ(sc.find_uca("UCA3")->type, UcaType::kWrongTimingOrOrder);
  EXPECT_EQ(sc.find_hazard("H7")->mitigability, Mitigability::kMT2);
  ASSERT_TRUE(sc.smil.has_value());
  EXPECT_EQ(sc.smil->rules.size(), 6u);
}

TEST(SafetyLoad, EntitiesRememberWhereTheyWereWritten) {
  const std::string text = example_text();
  const auto sc = parse_safety_case(text, "safety.yaml");
  EXPECT_EQ(sc.find_hazard("H8")->where.line, line_of(text, "id: H8"));
  EXPECT_EQ(sc.find_uca("UCA2")->hazards[0].where.line, line_of(text, "hazards: [H2, H6]"));
}

TEST(SafetyLoad, RegionsCompileAndEvaluateOverTheDeclaredFactors) {
  const auto sc = parse_safety_case(example_text(), "safety.yaml");
  const auto& region = *sc.find_uca("UCA1")->region_expression;
  ASSERT_EQ(region.variables(), sc.factor_names());
  // speed_kph, truck_speed_kph, ttc_s, mu, passage_m. At 72 km/h on mu 1 braking needs 1.02 s.
  const double v = 72.0 / 3.6;
  const double stop_ttc = v / (2 * 1.0 * 9.81);
  EXPECT_TRUE(region.holds(std::vector<double>{72, 10, stop_ttc - 0.01, 1.0, 3.0}));
  EXPECT_FALSE(region.holds(std::vector<double>{72, 10, stop_ttc + 0.01, 1.0, 3.0}));
  EXPECT_EQ(region.used_variables(), (std::vector<std::string>{"speed_kph", "ttc_s", "mu"}));
}

TEST(SafetyLoad, SavedCaseLoadsBackToTheSameCase) {
  const auto original = parse_safety_case(example_text(), "safety.yaml");
  const std::string saved = to_yaml(original);
  const auto again = parse_safety_case(saved, "saved.yaml");
  EXPECT_EQ(to_yaml(again), saved);
  ASSERT_EQ(again.ucas.size(), original.ucas.size());
  for (std::size_t i = 0; i < again.ucas.size(); ++i) {
    EXPECT_EQ(again.ucas[i].region, original.ucas[i].region);
    EXPECT_EQ(again.ucas[i].fsm_transitions.size(), original.ucas[i].fsm_transitions.size());
  }
  EXPECT_EQ(again.hazards[3].smil, original.hazards[3].smil);
}

TEST(SafetyLoad, MalformedYamlNamesLineAndColumn) {
  const auto e = parse_error("name: x\nlosses: [L1, L2\nhazards: []\n");
  EXPECT_EQ(e.where().file, "case.yaml");
  EXPECT_GT(e.where().line, 0);
  EXPECT_GT(e.where().column, 0);
  EXPECT_THAT(e.message(), HasSubstr("malformed YAML"));
}

TEST(SafetyLoad, EmptyFileIsAnError) { EXPECT_THAT(parse_error("# nothing here\n").message(), HasSubstr("empty")); }

TEST(SafetyLoad, WrongTypeNamesTheField) {
  const std::string text = replace_once(example_text(), "reversible: false", "reversible: sometimes");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "reversible: sometimes"));
  EXPECT_THAT(e.message(), HasSubstr("expected true or false"));
}

TEST(SafetyLoad, ListExpectedWhereAScalarWasGiven) {
  const std::string text = replace_once(example_text(), "losses: [L6, L7]", "losses: L6");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "losses: L6"));
  EXPECT_THAT(e.message(), HasSubstr("expected a list"));
}

TEST(SafetyLoad, MissingFieldNamesTheFieldAndTheEntity) {
  const std::string text = replace_once(example_text(), "    controllability: C2\n    asil: A\n", "    asil: A\n");
  const auto e = parse_error(text);
  EXPECT_THAT(e.message(), HasSubstr("missing required field 'controllability'"));
  EXPECT_EQ(e.where().line, line_of(text, "id: H7"));
}

// A misspelt required key is named at the misspelling with the field it stands for, not reported
// as the field missing (which sent a user hunting for a field they had written).
TEST(SafetyLoad, AMisspeltRequiredKeyIsNamedWhereItIsWritten) {
  const std::string text = replace_once(example_text(), "    severity: S3\n", "    severty: S3\n");
  const auto e = parse_error(text);
  EXPECT_THAT(e.message(), HasSubstr("unknown field 'severty' (did you mean 'severity'?)"));
  EXPECT_THAT(e.message(), HasSubstr("missing required field 'severity'"));
  EXPECT_EQ(e.where().line, line_of(text, "severty: S3"));
}

TEST(SafetyLoad, DuplicateIdPointsAtTheSecondAndNamesTheFirst) {
  const std::string text = replace_once(example_text(), "id: H9", "id: H4");
  const auto e = parse_error(text);
  EXPECT_THAT(e.message(), HasSubstr("duplicate id 'H4'"));
  EXPECT_THAT(e.message(), HasSubstr(std::to_string(line_of(text, "id: H4"))));
}

TEST(SafetyLoad, IdsAreUniqueAcrossKinds) {
  const std::string text = replace_once(example_text(), "id: CA1", "id: L1");
  EXPECT_THAT(parse_error(text).message(), HasSubstr("duplicate id 'L1'"));
}

TEST(SafetyLoad, UnknownUcaTypeListsTheFourTypes) {
  const std::string text = replace_once(example_text(), "type: provided", "type: provided_late");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "type: provided_late"));
  EXPECT_THAT(e.message(), HasSubstr("not_provided, provided, wrong_timing_or_order or "
                                     "stopped_too_soon_or_applied_too_long"));
}

TEST(SafetyLoad, RatingOutOfRangeIsAnError) {
  const std::string text = replace_once(example_text(), "severity: S2", "severity: S4");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "severity: S4"));
  EXPECT_THAT(e.message(), HasSubstr("expected S0, S1, S2 or S3, got 'S4'"));
  EXPECT_THAT(parse_error(replace_once(example_text(), "exposure: E1", "exposure: E5")).message(),
              HasSubstr("got 'E5'"));
  EXPECT_THAT(parse_error(replace_once(example_text(), "mitigability: MT3", "mitigability: MT4")).message(),
              HasSubstr("MT1, MT2 or MT3"));
}

TEST(SafetyLoad, UnknownFieldIsRejectedWithTheExpectedOnes) {
  const std::string text = replace_once(example_text(), "    severity: S3\n", "    severity: S3\n    severty: S3\n");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "severty"));
  EXPECT_THAT(e.message(), HasSubstr("unknown field 'severty'"));
  EXPECT_THAT(e.message(), HasSubstr("controllability"));
}

TEST(SafetyLoad, RegionNamingAnUndeclaredFactorPointsAtTheName) {
  const std::string text =
      replace_once(example_text(), "region: \"ttc_s < 0.7\"", "region: \"ttc_s < 0.7 && rain > 1\"");
  const auto e = parse_error(text);
  EXPECT_EQ(e.where().line, line_of(text, "rain > 1"));
  EXPECT_EQ(e.where().column, testing::column_of(text, "rain > 1"));
  EXPECT_THAT(e.message(), HasSubstr("unknown name 'rain'"));
}

TEST(SafetyLoad, RegionWithASyntaxErrorIsAnError) {
  const std::string text = replace_once(example_text(), "region: \"ttc_s < 0.7\"", "region: \"ttc_s < (0.7\"");
  EXPECT_THAT(parse_error(text).message(), HasSubstr("invalid expression"));
}

TEST(SafetyLoad, NanAndInfinityAreNotNumbers) {
  EXPECT_THAT(parse_error(replace_once(example_text(), "min: 30,", "min: .nan,")).message(),
              HasSubstr("expected a finite number"));
  EXPECT_THAT(parse_error(replace_once(example_text(), "max: 72,", "max: .inf,")).message(),
              HasSubstr("expected a finite number"));
}

TEST(SafetyLoad, FactorRangeMustNotBeReversed) {
  const std::string text = replace_once(example_text(), "min: 30, max: 72", "min: 72, max: 30");
  EXPECT_THAT(parse_error(text).message(), HasSubstr("expected min <= max"));
}

TEST(SafetyLoad, SmilLevelsMustBeDeclared) {
  EXPECT_THAT(
      parse_error(replace_once(example_text(), "mitigability: MT1, smil: F}", "mitigability: MT1, smil: Z}")).message(),
      HasSubstr("SMIL level 'Z' is not one of the declared levels"));
  EXPECT_THAT(parse_error(replace_once(example_text(), "    smil: B\n", "    smil: Q\n")).message(),
              HasSubstr("hazard 'H2': SMIL level 'Q'"));
}

TEST(SafetyLoad, MissingFileIsAnInputError) {
  EXPECT_THROW((void)load_safety_case("/nonexistent/safety.yaml"), InputError);
}

}  // namespace load_test
}  // namespace emrm::safety
