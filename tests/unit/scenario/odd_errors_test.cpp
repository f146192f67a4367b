#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "emrm/scenario/odd.hpp"
#include "odd_support.hpp"

namespace emrm::scenario {
namespace odd_errors_test {

using namespace test_support;  // NOLINT(google-build-using-namespace)
using ::testing::HasSubstr;

// ---- bad input: each error names its line and column ----------------------------------------

TEST(OddErrors, MalformedYaml) {
  const std::string text = replace_once(kGood, "    bins: [10, 20, 40]\n", "    bins: [10, 20, 40\n");
  const InputError e = parse_error(text);
  EXPECT_EQ(e.where().file, "odd.yaml");
  EXPECT_GT(e.where().line, 0);
  EXPECT_GT(e.where().column, 0);
  // A mapping key that is not closed by a colon, on line 4.
  const std::string text2 = replace_once(kGood, "  - name: v\n", "  - name: v: w\n");
  const InputError e2 = parse_error(text2);
  EXPECT_EQ(e2.where().line, pos_of(text2, "name: v: w").line) << e2.what();
  EXPECT_GT(e2.where().column, 0);
}

TEST(OddErrors, UnknownTopLevelField) {
  const std::string text = replace_once(kGood, "seed: 7\n", "seed: 7\ncolour: red\n");
  expect_error_at(text, "colour:", 0, "unknown field 'colour'");
}

TEST(OddErrors, UnknownFactorField) {
  const std::string text = replace_once(kGood, "    unit: km/h\n", "    unit: km/h\n    colour: red\n");
  expect_error_at(text, "colour:", 0, "colour");
}

TEST(OddErrors, WrongTypes) {
  expect_error_at(replace_once(kGood, "    type: integer\n", "    type: fuzzy\n"), "fuzzy", 0, "fuzzy");
  expect_error_at(replace_once(kGood, "  budget: 100\n", "  budget: lots\n"), "lots", 0, "lots");
  expect_error_at(replace_once(kGood, "  n_c: 1\n", "  n_c: 1.5\n"), "1.5", 0, "1.5");
  expect_error_at(replace_once(kGood, "    influential: false\n", "    influential: maybe\n"), "maybe", 0, "maybe");
}

TEST(OddErrors, MissingBins) {
  const std::string text = replace_once(kGood, "    bins: [10, 20, 40]\n    kinks: [15]\n", "");
  // At the factor's mapping, which starts at its first key.
  expect_error_at(text, "name: v", 0, "bins");
}

TEST(OddErrors, UnsortedBinEdges) {
  expect_error_at(replace_once(kGood, "bins: [10, 20, 40]", "bins: [10, 40, 20]"), "[10, 40, 20]", 0, "increase");
}

TEST(OddErrors, OverlappingBinEdges) {
  expect_error_at(replace_once(kGood, "bins: [0, 1, 2, 3]", "bins: [0, 1, 1, 3]"), "[0, 1, 1, 3]", 0, "increase");
}

TEST(OddErrors, OneEdgeIsNoBin) {
  expect_error_at(replace_once(kGood, "bins: [0, 2, 5]", "bins: [2]"), "[2]", 0, "two edges");
}

TEST(OddErrors, IntegerFactorNeedsIntegerEdges) {
  expect_error_at(replace_once(kGood, "bins: [0, 2, 5]", "bins: [0, 2.5, 5]"), "[0, 2.5, 5]", 0, "integer");
}

TEST(OddErrors, KinkOutsideTheDomain) {
  expect_error_at(replace_once(kGood, "kinks: [15]", "kinks: [45]"), "[45]", 0, "45");
  expect_error_at(replace_once(kGood, "kinks: [15]", "kinks: [10]"), "[10]", 0, "outside");  // on the edge
}

TEST(OddErrors, PriorOfTheWrongLength) {
  expect_error_at(replace_once(kGood, "prior: [0.2, 0.5, 0.3]", "prior: [0.5, 0.5]"), "[0.5, 0.5]", 0,
                  "2 probabilities for 3 levels");
}

TEST(OddErrors, PriorThatDoesNotNormalise) {
  expect_error_at(replace_once(kGood, "prior: [0.2, 0.5, 0.3]", "prior: [0.2, 0.5, 0.4]"), "[0.2, 0.5, 0.4]", 0,
                  "normalise");
}

TEST(OddErrors, NegativePrior) {
  expect_error_at(replace_once(kGood, "prior: [0.2, 0.5, 0.3]", "prior: [-0.2, 0.9, 0.3]"), "[-0.2", 0, ">= 0");
}

TEST(OddErrors, NanInBins) {
  const std::string text = replace_once(kGood, "bins: [10, 20, 40]", "bins: [10, .nan, 40]");
  const InputError e = parse_error(text);
  EXPECT_EQ(e.where().line, pos_of(text, ".nan").line) << e.what();
  EXPECT_EQ(e.where().column, pos_of(text, ".nan").column) << e.what();
}

TEST(OddErrors, UnknownFactorInRelevancePointsIntoThePredicate) {
  const std::string text = std::string(kGood) + "relevance: \"v < 30 && bogus > 1\"\n";
  expect_error_at(text, "bogus", 0, "bogus");
}

TEST(OddErrors, UnknownFactorInAConstraintPointsIntoThePredicate) {
  const std::string text = std::string(kGood) + "constraints:\n  - \"v >= 10\"\n  - \"n + speed < 3\"\n";
  expect_error_at(text, "speed <", 0, "speed");
}

TEST(OddErrors, UnknownFactorInTrackedPointsIntoThePredicate) {
  const std::string text = std::string(kGood) + "tracked: \"n > 0 || zz\"\n";
  expect_error_at(text, "zz", 0, "zz");
}

TEST(OddErrors, UnknownFactorInAMalfunctionRegionPointsIntoThePredicate) {
  const std::string text = std::string(kGood) + "malfunctions:\n  - id: M1\n    region: \"v > 15 && qq < 1\"\n";
  expect_error_at(text, "qq", 0, "qq");
}

TEST(OddErrors, StrengthLargerThanTheInfluentialFactors) {
  // Only v and n stay influential.
  const std::string text = replace_once(
      replace_once(kGood, "    values: [1.0, 0.6, 0.2]\n", "    values: [1.0, 0.6, 0.2]\n    influential: false\n"),
      "  strength: 2\n", "  strength: 3\n");
  expect_error_at(text, "strength: 3", 10, "strength 3");
  EXPECT_NO_THROW((void)parse(replace_once(text, "  strength: 3\n", "  strength: 2\n")));
  // Strength 3 is fine with three influential factors.
  EXPECT_NO_THROW((void)parse(replace_once(kGood, "  strength: 2\n", "  strength: 3\n")));
}

TEST(OddErrors, DefaultStrengthNeedsTwoInfluentialFactors) {
  std::string text =
      replace_once(kGood, "    values: [1.0, 0.6, 0.2]\n", "    values: [1.0, 0.6, 0.2]\n    influential: false\n");
  text = replace_once(text, "    type: integer\n", "    type: integer\n    influential: false\n");
  text = text.substr(0, text.find("coverage:"));
  EXPECT_THAT(parse_error(text).what(), HasSubstr("strength"));
}

TEST(OddErrors, StrengthFour) {
  expect_error_at(replace_once(kGood, "  strength: 2\n", "  strength: 4\n"), "strength: 4", 10, "2 or 3");
}

TEST(OddErrors, NcZero) { expect_error_at(replace_once(kGood, "  n_c: 1\n", "  n_c: 0\n"), "n_c: 0", 5, "n_c"); }

TEST(OddErrors, EpsilonAboveOneHalf) {
  expect_error_at(replace_once(kGood, "  epsilon: 0.3\n", "  epsilon: 0.6\n"), "epsilon: 0.6", 9, "epsilon");
}

TEST(OddErrors, DeltaAboveOne) {
  expect_error_at(replace_once(kGood, "  delta: 0.05\n", "  delta: 1.5\n"), "delta: 1.5", 7, "delta");
}

TEST(OddErrors, BudgetZero) {
  expect_error_at(replace_once(kGood, "  budget: 100\n", "  budget: 0\n"), "budget: 0", 8, "budget");
}

TEST(OddErrors, UnsatisfiableConstraintIsReportedAtThatConstraint) {
  // The relevance predicate alone is satisfiable (v <= 15); the second constraint contradicts it.
  const std::string text = std::string(kGood) +
                           "relevance: \"v <= 15\"\n"
                           "constraints:\n"
                           "  - \"n >= 0\"\n"
                           "  - \"v >= 30\"\n"
                           "  - \"w >= 0\"\n";
  const InputError e = parse_error(text);
  const Pos p = pos_of(text, "\"v >= 30\"");
  EXPECT_EQ(e.where().line, p.line) << e.what();
  // At the scalar: its opening quote or its first character.
  EXPECT_GE(e.where().column, p.column) << e.what();
  EXPECT_LE(e.where().column, p.column + 1) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("unsatisfiable"));
}

TEST(OddErrors, UnsatisfiableRelevanceIsReportedAtTheRelevance) {
  const std::string text = std::string(kGood) + "relevance: \"v > 40\"\n";
  const InputError e = parse_error(text);
  EXPECT_EQ(e.where().line, pos_of(text, "relevance:").line) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("relevance"));
}

TEST(OddErrors, DuplicateFactor) {
  const std::string text = replace_once(kGood, "  - name: n\n", "  - name: v\n");
  // The second `name: v`.
  const auto first = text.find("name: v\n");
  const auto second = text.find("name: v\n", first + 1);
  ASSERT_NE(second, std::string::npos);
  const InputError e = parse_error(text);
  const Pos p = pos_of(text.substr(0, second) + "@@", "@@");
  EXPECT_EQ(e.where().line, p.line) << e.what();
  EXPECT_EQ(e.where().column, p.column + 6) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("duplicate factor 'v'"));
}

TEST(OddErrors, DuplicateClass) {
  expect_error_at(replace_once(kGood, "classes: [dry, wet, icy]", "classes: [dry, wet, dry]"), "[dry, wet, dry]", 0,
                  "duplicate class 'dry'");
}

TEST(OddErrors, FactorNameThatIsNotAnIdentifier) {
  expect_error_at(replace_once(kGood, "  - name: w\n", "  - name: 2w\n"), "2w", 0, "identifier");
  expect_error_at(replace_once(kGood, "  - name: w\n", "  - name: \"a b\"\n"), "\"a b\"", 0, "identifier");
}

TEST(OddErrors, UnknownBaselineFactor) {
  const std::string text = std::string(kGood) + "baselines:\n  manual:\n    v: [10, 20]\n    nope: [1, 2]\n";
  expect_error_at(text, "nope", 0, "unknown factor 'nope'");
}

TEST(OddErrors, SafetyFileThatDoesNotExist) {
  const std::string text = replace_once(kGood, "seed: 7\n", "seed: 7\nsafety: missing_safety.yaml\n");
  expect_error_at(text, "missing_safety.yaml", 0, "does not exist");
}

TEST(OddErrors, NominalOutsideTheDomainOrNotAClass) {
  expect_error_at(replace_once(kGood, "    kinks: [15]\n", "    kinks: [15]\n    nominal: 50\n"), "nominal: 50", 9,
                  "outside");
  expect_error_at(
      replace_once(kGood, "    values: [1.0, 0.6, 0.2]\n", "    values: [1.0, 0.6, 0.2]\n    nominal: snow\n"), "snow",
      0, "not a class");
}

TEST(OddErrors, InfiniteNumber) {
  const std::string text = replace_once(kGood, "prior: [0.2, 0.5, 0.3]", "prior: [0.2, .inf, 0.3]");
  const InputError e = parse_error(text);
  EXPECT_EQ(e.where().line, pos_of(text, ".inf").line) << e.what();
  EXPECT_EQ(e.where().column, pos_of(text, ".inf").column) << e.what();
}

TEST(OddErrors, DuplicateMalfunctionMode) {
  const std::string text = std::string(kGood) + "malfunctions:\n  - id: M1\n  - id: M2\n  - id: M1\n";
  const auto last = text.rfind("M1");
  const InputError e = parse_error(text);
  const Pos p = pos_of(text.substr(0, last) + "@@", "@@");
  EXPECT_EQ(e.where().line, p.line) << e.what();
  EXPECT_EQ(e.where().column, p.column) << e.what();
  EXPECT_THAT(e.what(), HasSubstr("duplicate malfunction mode 'M1'"));
}

TEST(OddErrors, DuplicateTopLevelKey) {
  const std::string text = replace_once(kGood, "seed: 7\n", "seed: 7\nseed: 8\n");
  const InputError e = parse_error(text);
  EXPECT_EQ(e.where().line, pos_of(text, "seed: 8").line) << e.what();
}

TEST(OddErrors, NegativeSeed) { expect_error_at(replace_once(kGood, "seed: 7\n", "seed: -7\n"), "-7", 0, "seed"); }

TEST(OddErrors, TooManyCells) {
  // 60 x 60 x 60 = 216 000 cells.
  std::string bins = "[0";
  for (int k = 1; k <= 60; ++k) bins += ", " + std::to_string(k);
  bins += "]";
  std::string text = "name: big\nfactors:\n";
  for (const char* name : {"a", "b", "c"}) text += std::string("  - name: ") + name + "\n    bins: " + bins + "\n";
  const InputError e = parse_error(text);
  EXPECT_THAT(e.what(), HasSubstr("216000 cells"));
  EXPECT_EQ(e.where().line, pos_of(text, "- name: a").line) << e.what();
}

TEST(OddErrors, IntegerNominalMustBeAWholeNumber) {
  // An integer factor takes whole numbers only; a nominal of 2.5 would put the HARA baseline's
  // nominal scenario outside the domain (the coverage checker then counts it as inadmissible).
  expect_error_at(replace_once(kGood, "    bins: [0, 2, 5]\n", "    bins: [0, 2, 5]\n    nominal: 2.5\n"),
                  "nominal: 2.5", 9, "2.5");
  EXPECT_NO_THROW((void)parse(replace_once(kGood, "    bins: [0, 2, 5]\n", "    bins: [0, 2, 5]\n    nominal: 4\n")));
}

}  // namespace odd_errors_test
}  // namespace emrm::scenario
