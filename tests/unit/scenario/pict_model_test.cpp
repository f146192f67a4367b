#include "emrm/scenario/pict_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace emrm::scenario {
namespace pict_model_test {

constexpr const char* kSample = R"(# Vehicle scenarios
Speed: 30, 50, 70
Road:  dry, wet, icy

Light: day, night
IF [Road] = "icy" THEN [Speed] <= 50;
IF [Light] = "night" AND NOT [Road] IN {"dry"}
  THEN [Speed] < 70 ELSE [Speed] >= 30;
[Speed] <> 70 OR [Road] = "dry";
)";

TEST(PictModel, ParsesParametersAndConstraints) {
  const PictModel m = parse_pict_model(kSample, "m.txt");
  ASSERT_EQ(m.parameters().size(), 3U);
  EXPECT_EQ(m.parameters()[1].name, "Road");
  EXPECT_EQ(m.parameters()[1].values, (std::vector<std::string>{"dry", "wet", "icy"}));
  EXPECT_EQ(m.levels(), (std::vector<int>{3, 3, 2}));
  EXPECT_EQ(m.constraint_count(), 3U);
  EXPECT_TRUE(m.violates(std::vector<int>{2, 2, 0}));           // 70 on ice
  EXPECT_FALSE(m.violates(std::vector<int>{2, kDontCare, 0}));  // not decided yet
  EXPECT_FALSE(m.violates(std::vector<int>{1, 2, 1}));
  EXPECT_TRUE(m.violates(std::vector<int>{2, 1, 0}));  // 70 on wet
}

TEST(PictModel, GeneratedArrayRespectsTheModel) {
  const PictModel m = parse_pict_model(kSample, "m.txt");
  const auto ca = generate_covering_array(m.levels(), {}, m.row_violates());
  EXPECT_TRUE(check_covering_array(m.levels(), 2, ca.rows, m.row_violates()).ok());
  EXPECT_GT(ca.forbidden_tuples, 0U);
}

void expect_error_at(const std::string& text, int line, int column, const std::string& what) {
  try {
    (void)parse_pict_model(text, "bad.txt");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "bad.txt");
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().column, column) << e.what();
    EXPECT_THAT(e.message(), ::testing::HasSubstr(what));
  }
}

TEST(PictModel, BadInputIsReportedAtLineAndColumn) {
  expect_error_at("# nothing\n\n", 2, 1, "no parameters");
  expect_error_at("A: 1, 2\nB:\n", 2, 3, "has no values");
  expect_error_at("A: 1, 2\nA: 3\n", 2, 1, "duplicate parameter");
  expect_error_at("A: x, y, x\n", 1, 10, "duplicate value");
  expect_error_at("A: 1, 2\nIF [B] = 1 THEN [A] = 2;\n", 2, 4, "unknown parameter [B]");
  expect_error_at("A: 1, 2\n[A] LIKE \"1*\";\n", 2, 5, "LIKE");
  expect_error_at("A: 1, 2\n[A] = 1\n", 3, 1, "expected ';'");
  expect_error_at("A: x, y\n[A] < 3;\n", 2, 5, "numeric");
  expect_error_at("A: 1, 2\nB: 1, 2\n[A] = 1;\n[A] = 2;\n", 4, 1, "unsatisfiable");
  expect_error_at("A: 1, 2\n{ A } @ 2\n", 2, 1, "sub-models");
  expect_error_at("A 1, 2\n", 1, 1, "expected a parameter line");
}

// 30 two-value parameters and two constraints that contradict each other only once the last one is
// set: proving that no row exists visits all 2^31 nodes of the search (a fuzzer's 28-parameter
// model like this took 41 s; this one would take minutes).
std::string hopeless_model() {
  std::string text = "# no row satisfies this, and only the last parameter shows it\n";
  for (int i = 1; i <= 30; ++i) text += "X" + std::to_string(i) + ": 0, 1\n";
  return text + "\n[X30] = [X1];\n[X30] <> [X1];\n";
}

InputError input_error_of(const std::string& text, std::uint64_t max_search_steps) {
  try {
    (void)parse_pict_model(text, "m.txt", max_search_steps);
  } catch (const InputError& e) {
    return e;
  }
  return InputError({}, "no InputError");
}

TEST(PictModel, HopelessConstraintsStopAtTheSearchBudget) {
  for (const std::uint64_t steps : {std::uint64_t{1000}, kDefaultMaxSearchSteps}) {
    const InputError e = input_error_of(hopeless_model(), steps);
    EXPECT_EQ(e.where().file, "m.txt");
    EXPECT_EQ(e.where().line, 33);  // the first constraint
    EXPECT_EQ(e.where().column, 1);
    EXPECT_EQ(e.message(), "the constraints took more than " + std::to_string(steps) +
                               " search steps to satisfy (ca --max-search-steps raises it)");
  }
}

// One step is one node of the search. kSample's first row, 30 dry day, is valid: the root and three
// parameters take four steps. An unsatisfiable pair takes 3 steps to refute, the culprit search 3
// for [A] = 1 alone (satisfiable) and 3 more for both: nine in all, from one budget.
TEST(PictModel, SmallBudgetsSufficeForEasyModels) {
  EXPECT_EQ(parse_pict_model(kSample, "m.txt", 4).constraint_count(), 3U);
  EXPECT_THAT(input_error_of(kSample, 3).message(), ::testing::HasSubstr("more than 3 search steps"));
  EXPECT_EQ(input_error_of(kSample, 3).where().line, 6);

  const std::string unsatisfiable = "A: 1, 2\nB: 1, 2\n[A] = 1;\n[A] = 2;\n";
  const InputError culprit = input_error_of(unsatisfiable, 9);
  EXPECT_EQ(culprit.where().line, 4);
  EXPECT_EQ(culprit.message(), "the constraints are unsatisfiable: no row satisfies them all");
  // Refuted, but the budget ends in the search for the culprit: unsatisfiable, at the first one.
  const InputError no_culprit = input_error_of(unsatisfiable, 8);
  EXPECT_EQ(no_culprit.where().line, 3);
  EXPECT_EQ(no_culprit.message(),
            "the constraints are unsatisfiable: no row satisfies them all (finding the first constraint to blame "
            "took more than 8 search steps; ca --max-search-steps raises it)");
  const InputError undecided = input_error_of(unsatisfiable, 2);
  EXPECT_EQ(undecided.where().line, 3);
  EXPECT_EQ(undecided.message(),
            "the constraints took more than 2 search steps to satisfy (ca --max-search-steps raises it)");
}

// Hostile constraints: 50 000 nested parentheses (overflowed the stack) are refused at the depth
// limit; 300 000 ORs in a row (a tree as deep, overflowed it when evaluated and destroyed) are one
// flat node that evaluates like the short form.
TEST(PictModel, DeepNestingIsRefusedAndLongChainsStayFlat) {
  const std::string head = "A: 1, 2\nB: 1, 2\n\n";
  const std::string deep =
      head + "IF " + std::string(50000, '(') + "[A] = 1" + std::string(50000, ')') + " THEN [B] = 2;\n";
  EXPECT_THROW((void)parse_pict_model(deep, "deep.txt"), InputError);
  const std::string ok = head + "IF " + std::string(150, '(') + "[A] = 1" + std::string(150, ')') + " THEN [B] = 2;\n";
  EXPECT_NO_THROW((void)parse_pict_model(ok, "ok.txt"));

  std::string ors = head + "IF [A] = 2";
  for (int i = 0; i < 300000; ++i) ors += " OR [A] = 2";
  ors += " THEN [B] = 2;\n";
  const PictModel chain = parse_pict_model(ors, "ors.txt");
  const PictModel shortest = parse_pict_model(head + "IF [A] = 2 THEN [B] = 2;\n", "short.txt");
  for (const std::vector<int>& row : {std::vector{0, 0}, std::vector{0, 1}, std::vector{1, 0}, std::vector{1, 1}})
    EXPECT_EQ(chain.violates(row), shortest.violates(row)) << row[0] << row[1];
}

}  // namespace pict_model_test
}  // namespace emrm::scenario
