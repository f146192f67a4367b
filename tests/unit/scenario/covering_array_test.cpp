// Covering arrays, verified by a brute-force checker written here from the definition, so a bug in
// the generator's tuple bookkeeping cannot hide itself.

#include "emrm/scenario/covering_array.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"

namespace emrm::scenario {
namespace covering_array_test {

using Rows = std::vector<std::vector<int>>;

std::vector<int> levels_of(std::initializer_list<std::pair<int, int>> groups) {
  std::vector<int> l;
  for (auto [levels, count] : groups) l.insert(l.end(), static_cast<std::size_t>(count), levels);
  return l;
}

// Can `row` (with -1 for free entries) be completed into a row no constraint rejects?
bool extendable(const std::vector<int>& levels, std::vector<int> row, const RowViolates& violates, std::size_t c = 0) {
  if (c == row.size()) return !violates || !violates(row);
  if (row[c] >= 0) return extendable(levels, row, violates, c + 1);
  for (int v = 0; v < levels[c]; ++v) {
    row[c] = v;
    if (extendable(levels, row, violates, c + 1)) return true;
  }
  return false;
}

// Empty when `rows` is a valid covering array, else the first problem found.
std::string independent_check(const std::vector<int>& levels, int t, const Rows& rows,
                              const RowViolates& violates = {}) {
  const std::size_t n = levels.size();
  for (const auto& r : rows) {
    if (r.size() != n) return "row of wrong length";
    for (std::size_t c = 0; c < n; ++c)
      if (r[c] < 0 || r[c] >= levels[c]) return "entry out of range";
    if (violates && violates(r)) return "row violates a constraint";
  }
  std::vector<std::vector<std::size_t>> combos;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      if (t == 2) combos.push_back({a, b});
      for (std::size_t c = b + 1; t == 3 && c < n; ++c) combos.push_back({a, b, c});
    }
  for (const auto& cols : combos) {
    std::set<std::vector<int>> seen;
    for (const auto& r : rows) {
      std::vector<int> key;
      for (auto c : cols) key.push_back(r[c]);
      seen.insert(key);
    }
    std::vector<int> values(cols.size(), 0);
    while (true) {
      if (!seen.count(values)) {
        std::vector<int> partial(n, -1);
        for (std::size_t i = 0; i < cols.size(); ++i) partial[cols[i]] = values[i];
        if (!violates || extendable(levels, partial, violates)) return "a t-tuple is not covered";
      }
      std::size_t i = cols.size();
      while (i > 0 && ++values[i - 1] == levels[cols[i - 1]]) values[--i] = 0;
      if (i == 0) break;
    }
  }
  return {};
}

// The reference models of the sizing issue, with the sizes it requires (best known and PICT in
// docs/covering-arrays.md), with default options; under the sanitizers all eight take about 15 s.
struct Reference {
  std::string name;
  std::vector<int> levels;
  int strength;
  std::size_t bound;
};

std::ostream& operator<<(std::ostream& out, const Reference& r) { return out << r.name; }

class ReferenceModel : public ::testing::TestWithParam<Reference> {};

TEST_P(ReferenceModel, MeetsTheRequiredSizeAndCoversEveryTuple) {
  const Reference& ref = GetParam();
  CoveringArrayOptions options;
  options.strength = ref.strength;
  const auto ca = generate_covering_array(ref.levels, options);
  EXPECT_LE(ca.rows.size(), ref.bound);
  EXPECT_EQ(independent_check(ref.levels, ref.strength, ca.rows), "");
  EXPECT_TRUE(check_covering_array(ref.levels, ref.strength, ca.rows).ok());
}

INSTANTIATE_TEST_SUITE_P(
    Issue, ReferenceModel,
    ::testing::Values(
        Reference{"t2_3pow4", levels_of({{3, 4}}), 2, 9}, Reference{"t2_3pow13", levels_of({{3, 13}}), 2, 17},
        Reference{"t2_2pow100", levels_of({{2, 100}}), 2, 14}, Reference{"t2_10pow20", levels_of({{10, 20}}), 2, 200},
        Reference{"t2_4pow15_3pow17_2pow29", levels_of({{4, 15}, {3, 17}, {2, 29}}), 2, 35},
        Reference{"t2_4pow1_3pow39_2pow35", levels_of({{4, 1}, {3, 39}, {2, 35}}), 2, 26},
        Reference{"t3_3pow4", levels_of({{3, 4}}), 3, 30}, Reference{"t3_5pow10", levels_of({{5, 10}}), 3, 260}),
    [](const ::testing::TestParamInfo<Reference>& model) { return model.param.name; });

TEST(CoveringArray, FindsTheOrthogonalArrayOfSmallModelsThatHaveOne) {
  // v^t rows are a lower bound (every t-tuple of one t-subset needs its own row); an orthogonal
  // array meets it, and these small ones are within the search's reach.
  struct Case {
    int levels;
    int factors;
    int strength;
  };
  for (const Case c : {Case{3, 4, 2}, Case{4, 5, 2}, Case{5, 6, 2}, Case{3, 4, 3}}) {
    CoveringArrayOptions options;
    options.strength = c.strength;
    const std::vector<int> levels(static_cast<std::size_t>(c.factors), c.levels);
    const auto ca = generate_covering_array(levels, options);
    std::size_t lower_bound = 1;
    for (int i = 0; i < c.strength; ++i) lower_bound *= static_cast<std::size_t>(c.levels);
    EXPECT_EQ(ca.rows.size(), lower_bound) << c.levels << "^" << c.factors << " t=" << c.strength;
    EXPECT_EQ(independent_check(levels, c.strength, ca.rows), "");
  }
}

TEST(CoveringArray, OptimisationNeverLengthensTheGreedyArray) {
  for (const auto& levels : {levels_of({{3, 13}}), levels_of({{4, 3}, {3, 5}, {2, 4}}), levels_of({{6, 7}})}) {
    CoveringArrayOptions greedy;
    greedy.improvement_effort = 0.0;
    CoveringArrayOptions optimised;
    const auto before = generate_covering_array(levels, greedy);
    const auto after = generate_covering_array(levels, optimised);
    EXPECT_LE(after.rows.size(), before.rows.size());
    EXPECT_EQ(independent_check(levels, 2, before.rows), "");
    EXPECT_EQ(independent_check(levels, 2, after.rows), "");
  }
}

TEST(CoveringArray, RandomConstrainedModelsAreCoveredAndValid) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + static_cast<int>(rng() % 7);
    const int t = (trial % 2 == 0 || n < 3) ? 2 : 3;
    std::vector<int> levels;
    for (int i = 0; i < n; ++i) levels.push_back(2 + static_cast<int>(rng() % 4));
    // Forbid a few random value pairs; some models end up forbidding a whole value.
    std::vector<std::array<int, 4>> forbidden;
    const int count = static_cast<int>(rng() % 4);
    for (int k = 0; k < count; ++k) {
      const int a = static_cast<int>(rng() % static_cast<unsigned>(n));
      const int b = (a + 1 + static_cast<int>(rng() % static_cast<unsigned>(n - 1))) % n;
      forbidden.push_back({a, static_cast<int>(rng() % static_cast<unsigned>(levels[static_cast<std::size_t>(a)])), b,
                           static_cast<int>(rng() % static_cast<unsigned>(levels[static_cast<std::size_t>(b)]))});
    }
    RowViolates violates;
    if (!forbidden.empty())
      violates = [forbidden](std::span<const int> row) {
        for (const auto& f : forbidden)
          if (row[static_cast<std::size_t>(f[0])] == f[1] && row[static_cast<std::size_t>(f[2])] == f[3]) return true;
        return false;
      };
    CoveringArrayOptions options;
    options.strength = t;
    options.seed = static_cast<std::uint64_t>(trial);
    const auto ca = generate_covering_array(levels, options, violates);
    EXPECT_EQ(independent_check(levels, t, ca.rows, violates), "") << "trial " << trial;
    EXPECT_TRUE(check_covering_array(levels, t, ca.rows, violates).ok()) << "trial " << trial;
    if (forbidden.empty()) {
      EXPECT_EQ(ca.forbidden_tuples, 0U) << "trial " << trial;
    }
  }
}

// A constrained model with forced seed rows, large enough that the optimisation removes rows.
struct ConstrainedModel {
  std::vector<int> levels = levels_of({{4, 2}, {3, 8}});
  RowViolates violates = [](std::span<const int> r) {
    // p1 = 3 rules out p2 = 3; p3 = 0 and p4 = 0 never meet; p5 = 2 needs p6 = 1 (known or not).
    return (r[0] == 3 && r[1] == 3) || (r[2] == 0 && r[3] == 0) || (r[4] == 2 && r[5] != kDontCare && r[5] != 1);
  };
  Rows seed_rows = {{3, kDontCare, 1, kDontCare, 2, kDontCare, 0, 0, 0, 0}, {0, 1, 2, 2, 1, 0, 1, 2, 0, 1}};
};

TEST(CoveringArray, SeedRowsAndConstraintsSurviveTheOptimisation) {
  const ConstrainedModel model;
  CoveringArrayOptions options;
  options.seed_rows = model.seed_rows;
  CoveringArrayOptions greedy = options;
  greedy.improvement_effort = 0.0;
  const auto before = generate_covering_array(model.levels, greedy, model.violates);
  const auto ca = generate_covering_array(model.levels, options, model.violates);
  ASSERT_LT(ca.rows.size(), before.rows.size()) << "the optimisation should have removed rows";
  ASSERT_GE(ca.rows.size(), 2U);
  for (std::size_t r = 0; r < model.seed_rows.size(); ++r)
    for (std::size_t c = 0; c < model.levels.size(); ++c)
      if (model.seed_rows[r][c] != kDontCare) {
        EXPECT_EQ(ca.rows[r][c], model.seed_rows[r][c]) << "row " << r << ", column " << c;
      }
  EXPECT_EQ(ca.rows[0][5], 1);  // the don't-care was filled validly
  EXPECT_EQ(independent_check(model.levels, 2, ca.rows, model.violates), "");
  EXPECT_TRUE(check_covering_array(model.levels, 2, ca.rows, model.violates).ok());
  // 1 pair (p1, p2) + 1 pair (p3, p4) + 2 pairs (p5 = 2 with p6 = 0 or 2).
  EXPECT_EQ(ca.forbidden_tuples, 4U);
}

TEST(CoveringArray, SameInputsGiveTheSameArray) {
  const ConstrainedModel model;
  for (int t : {2, 3}) {
    CoveringArrayOptions options;
    options.strength = t;
    options.seed = 42;
    options.seed_rows = model.seed_rows;
    const auto first = generate_covering_array(model.levels, options, model.violates);
    const auto second = generate_covering_array(model.levels, options, model.violates);
    EXPECT_EQ(first.rows, second.rows) << "t=" << t;
    EXPECT_EQ(independent_check(model.levels, t, first.rows, model.violates), "") << "t=" << t;
  }
  const auto levels = levels_of({{4, 3}, {3, 5}, {2, 4}});
  CoveringArrayOptions options;
  options.seed = 42;
  EXPECT_EQ(generate_covering_array(levels, options).rows, generate_covering_array(levels, options).rows);
}

TEST(CoveringArray, SeedRowsComeFirstAndDontCaresAreFilled) {
  CoveringArrayOptions options;
  options.seed_rows = {{2, 2, 2, 2}, {0, kDontCare, 1, kDontCare}};
  const std::vector<int> levels(4, 3);
  const auto ca = generate_covering_array(levels, options);
  ASSERT_GE(ca.rows.size(), 2U);
  EXPECT_EQ(ca.rows[0], (std::vector<int>{2, 2, 2, 2}));
  EXPECT_EQ(ca.rows[1][0], 0);
  EXPECT_EQ(ca.rows[1][2], 1);
  EXPECT_NE(ca.rows[1][1], kDontCare);
  EXPECT_EQ(independent_check(levels, 2, ca.rows), "");
}

TEST(CoveringArray, ConstraintsAreRespectedAndForbiddenPairsNotRequired) {
  // p1 = 0 never goes with p2 = 0.
  const RowViolates violates = [](std::span<const int> r) { return r[0] == 0 && r[1] == 0; };
  const std::vector<int> levels{2, 2, 2};
  const auto ca = generate_covering_array(levels, {}, violates);
  EXPECT_EQ(ca.forbidden_tuples, 1U);
  EXPECT_EQ(independent_check(levels, 2, ca.rows, violates), "");
}

TEST(CoveringArray, RejectsBadArguments) {
  CoveringArrayOptions three;
  three.strength = 3;
  EXPECT_THROW((void)generate_covering_array({2, 2}, three), std::invalid_argument);
  CoveringArrayOptions four;
  four.strength = 4;
  EXPECT_THROW((void)generate_covering_array({2, 2, 2, 2}, four), std::invalid_argument);
  EXPECT_THROW((void)generate_covering_array({2, 0}, {}), std::invalid_argument);
  CoveringArrayOptions negative_effort;
  negative_effort.improvement_effort = -1.0;
  EXPECT_THROW((void)generate_covering_array({2, 2, 2}, negative_effort), std::invalid_argument);
  CoveringArrayOptions negative_moves;
  negative_moves.improvement_max_moves = -1;
  EXPECT_THROW((void)generate_covering_array({2, 2, 2}, negative_moves), std::invalid_argument);
  const RowViolates everything = [](std::span<const int> r) { return r[0] != kDontCare; };
  EXPECT_THROW((void)generate_covering_array({2, 2}, {}, everything), std::domain_error);
}

// 30 two-level factors where x1 = 1 is impossible, but only the last factor shows it: the search
// has to try all 2^28 values of the factors in between before it can tell.
constexpr int kHopelessFactors = 30;
bool hopeless_violates(std::span<const int> r) { return r[0] == 1 && r.back() != kDontCare; }

template <class F>
std::string usage_error_of(F&& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "no UsageError";
}

TEST(CoveringArray, SearchBudgetStopsAHopelessCompletion) {
  const std::vector<int> levels(kHopelessFactors, 2);
  std::vector<int> partial(kHopelessFactors, kDontCare);
  partial[0] = 1;
  SearchBudget budget(1000);
  const auto message = usage_error_of([&] { (void)complete_row(levels, partial, hopeless_violates, budget); });
  EXPECT_EQ(message, "the constraints took more than 1000 search steps to satisfy (ca --max-search-steps raises it)");
  EXPECT_EQ(budget.used(), 1000U);
  // The same budget is spent: a search that would fit a fresh one does not fit what is left.
  EXPECT_THROW((void)complete_row(levels, std::vector<int>(kHopelessFactors, kDontCare), hopeless_violates, budget),
               UsageError);
  SearchBudget fresh(kHopelessFactors + 1);  // one step per node: the root and one per factor
  EXPECT_TRUE(complete_row(levels, std::vector<int>(kHopelessFactors, kDontCare), hopeless_violates, fresh));
  EXPECT_EQ(fresh.used(), static_cast<std::uint64_t>(kHopelessFactors + 1));
}

// A valid row is found at once, but proving the tuples with x1 = 1 infeasible never ends: the
// generation stops at its budget, the default one too, instead of running for hours.
TEST(CoveringArray, GenerationStopsAtTheSearchBudget) {
  const std::vector<int> levels(kHopelessFactors, 2);
  EXPECT_TRUE(complete_row(levels, std::vector<int>(kHopelessFactors, kDontCare), hopeless_violates));
  CoveringArrayOptions small;
  small.max_search_steps = 5000;
  EXPECT_THAT(usage_error_of([&] { (void)generate_covering_array(levels, small, hopeless_violates); }),
              ::testing::HasSubstr("more than 5000 search steps to satisfy (ca --max-search-steps raises it)"));
  EXPECT_THAT(usage_error_of([&] { (void)generate_covering_array(levels, {}, hopeless_violates); }),
              ::testing::HasSubstr(std::to_string(kDefaultMaxSearchSteps) + " search steps"));
}

// The budget caps work and changes nothing else: a budget just large enough gives the same array
// as the default, and one step less fails. The builder's completions count too, not only the
// search for forbidden tuples.
TEST(CoveringArray, BudgetWithinReachLeavesTheArrayUnchanged) {
  const RowViolates violates = [](std::span<const int> r) { return r[0] == 0 && r[1] == 0; };
  const std::vector<int> levels{2, 2, 2, 3};
  const auto reference = generate_covering_array(levels, {}, violates);
  std::uint64_t low = 0;                        // fails
  std::uint64_t high = kDefaultMaxSearchSteps;  // works
  CoveringArrayOptions options;
  auto works = [&](std::uint64_t steps) {
    options.max_search_steps = steps;
    try {
      return generate_covering_array(levels, options, violates).rows == reference.rows;
    } catch (const UsageError&) {
      return false;
    }
  };
  while (high - low > 1) {  // works() is monotone: the search does not depend on the budget
    const std::uint64_t mid = low + (high - low) / 2;
    if (works(mid)) {
      high = mid;
    } else {
      low = mid;
    }
  }
  EXPECT_GT(high, 200U);  // far more than finding the forbidden tuple alone takes
  EXPECT_TRUE(works(high));
  EXPECT_FALSE(works(high - 1));
}

TEST(CoveringArray, CheckerStopsAtItsSearchBudget) {
  const std::vector<int> levels(kHopelessFactors, 2);
  const std::vector<std::vector<int>> rows{std::vector<int>(kHopelessFactors, 0)};
  EXPECT_THAT(usage_error_of([&] { (void)check_covering_array(levels, 2, rows, hopeless_violates, 2000); }),
              ::testing::HasSubstr("more than 2000 search steps"));
  const RowViolates easy = [](std::span<const int> r) { return r[0] == 0 && r[1] == 0; };
  const auto report = check_covering_array({2, 2}, 2, {{0, 1}, {1, 0}, {1, 1}}, easy, 20);
  EXPECT_TRUE(report.ok()) << report.first_problem;
  EXPECT_EQ(report.required_tuples, 3U);
}

TEST(CoveringArray, CheckerReportsAMissingPair) {
  const auto report = check_covering_array({2, 2}, 2, {{0, 0}, {1, 1}, {0, 1}});
  EXPECT_FALSE(report.ok());
  EXPECT_EQ(report.covered_tuples, 3U);
  EXPECT_EQ(report.required_tuples, 4U);
}

}  // namespace covering_array_test
}  // namespace emrm::scenario
