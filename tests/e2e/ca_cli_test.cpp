// End-to-end: `emrm ca` as a user runs it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace ca_cli_test {

using ::testing::HasSubstr;

// A PICT model with one constraint, every row easy to complete.
const char* const kSmallModel =
    "Speed: 30, 50, 70\nRoad: dry, wet, icy\nLight: day, night\n"
    "IF [Road] = \"icy\" THEN [Speed] <= 50;\n";

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::istringstream l(line);
    for (std::string f; std::getline(l, f, ',');) fields.push_back(f);
    rows.push_back(fields);
  }
  return rows;
}

TEST(CaCli, LevelsGiveASmallPairwiseArray) {
  const auto r = run_emrm("ca --levels 3,3,3,3 --strength 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], (std::vector<std::string>{"p1", "p2", "p3", "p4"}));
  EXPECT_LE(rows.size() - 1, 9U);
  std::set<std::string> pairs;
  for (std::size_t i = 1; i < rows.size(); ++i)
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = a + 1; b < 4; ++b)
        pairs.insert(std::to_string(a) + rows[i][a] + std::to_string(b) + rows[i][b]);
  EXPECT_EQ(pairs.size(), 6U * 9U);
  EXPECT_THAT(r.err, HasSubstr("54 of 54 tuples covered"));
}

TEST(CaCli, PictModelWithCheck) {
  const auto dir = scratch_dir("ca-model");
  write_text(dir / "m.txt", kSmallModel);
  const auto r = run_emrm("ca " + quoted(dir / "m.txt") + " --check --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("Speed,Road,Light\n"));
  EXPECT_EQ(r.out.find("70,icy"), std::string::npos);
  EXPECT_THAT(r.err, HasSubstr("OK"));
  EXPECT_EQ(r.out, run_emrm("ca " + quoted(dir / "m.txt") + " --check --seed 3").out);
}

TEST(CaCli, BadInputExitsTwo) {
  for (const char* args : {"ca --levels 3,3,3 --strength 4", "ca --levels 3,3 --strength 3", "ca --levels 3,0,2",
                           "ca --levels 3,x", "ca"}) {
    const auto r = run_emrm(args);
    EXPECT_EQ(r.exit_code, 2) << args << r.out << r.err;
    EXPECT_FALSE(r.err.empty()) << args;
  }
  const auto dir = scratch_dir("ca-bad");
  write_text(dir / "bad.txt", "A: 1, 2\nIF [B] = 1 THEN [A] = 2;\n");
  const auto r = run_emrm("ca " + quoted(dir / "bad.txt"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("bad.txt:2:4: error: unknown parameter [B]"));
}

// 30 two-value parameters, then `constraints`.
std::string thirty_parameters(const std::string& constraints) {
  std::string text;
  for (int i = 1; i <= 30; ++i) text += "X" + std::to_string(i) + ": 0, 1\n";
  return text + constraints;
}

// Without the budget the first model's load check took minutes and the second's generation hours.
TEST(CaCli, HopelessConstraintsStopAtTheSearchBudget) {
  const auto dir = scratch_dir("ca-budget");
  write_text(dir / "unsat.txt", thirty_parameters("[X30] = [X1];\n[X30] <> [X1];\n"));
  const auto r = run_emrm("ca " + quoted(dir / "unsat.txt"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("unsat.txt:31:1: error: the constraints took more than 10000000 search steps "
                               "to satisfy (ca --max-search-steps raises it)"));
  EXPECT_TRUE(r.out.empty());
  const auto small = run_emrm("ca " + quoted(dir / "unsat.txt") + " --max-search-steps 5000");
  EXPECT_EQ(small.exit_code, 2);
  EXPECT_THAT(small.err, HasSubstr("more than 5000 search steps"));

  // Satisfiable (X1 = 0 works at once), but X1 = 1 is impossible and only X30 shows it.
  write_text(dir / "forbidden.txt", thirty_parameters("IF [X1] = 1 THEN [X30] = 0;\nIF [X1] = 1 THEN [X30] = 1;\n"));
  const auto gen = run_emrm("ca " + quoted(dir / "forbidden.txt"));
  EXPECT_EQ(gen.exit_code, 2) << gen.err;
  EXPECT_THAT(gen.err, HasSubstr("more than 10000000 search steps to satisfy (ca --max-search-steps raises it)"));
}

TEST(CaCli, MaxSearchStepsWithinReachChangesNothing) {
  const auto dir = scratch_dir("ca-budget-easy");
  write_text(dir / "m.txt", kSmallModel);
  const auto plain = run_emrm("ca " + quoted(dir / "m.txt") + " --check");
  const auto budget = run_emrm("ca " + quoted(dir / "m.txt") + " --check --max-search-steps 100000");
  ASSERT_EQ(budget.exit_code, 0) << budget.err;
  EXPECT_EQ(budget.out, plain.out);
  EXPECT_THAT(budget.err, HasSubstr("check OK"));
  const auto tiny = run_emrm("ca " + quoted(dir / "m.txt") + " --max-search-steps 10");
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_THAT(tiny.err, HasSubstr("more than 10 search steps"));
}

TEST(CaCli, MaxSearchStepsMustBeAPositiveInteger) {
  for (const char* value : {"0", "-1", "nan", "1.5", "1e6", "x", "18446744073709551616"}) {
    const auto r = run_emrm(std::string("ca --levels 3,3 --max-search-steps ") + value);
    EXPECT_EQ(r.exit_code, 2) << value << r.out << r.err;
    EXPECT_THAT(r.err, HasSubstr("--max-search-steps")) << value;
    EXPECT_TRUE(r.out.empty()) << value;
  }
  EXPECT_EQ(run_emrm("ca --levels 3,3 --max-search-steps 1").exit_code, 0);
}

}  // namespace ca_cli_test
}  // namespace emrm::e2e
