#include "emrm/scenario/plan.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "plan_support.hpp"

namespace emrm::scenario {
namespace plan_test {

using namespace test_support;  // NOLINT(google-build-using-namespace)
using ::testing::HasSubstr;

// ---- the shipped example -------------------------------------------------------------------------

TEST(PlanShipped, SatisfiesC1ToC4AndMeetsItsTargets) {
  const Odd& odd = shipped_odd();
  const Plan& plan = shipped_plan();
  EXPECT_TRUE(plan.shortfalls.empty()) << describe(plan);
  EXPECT_TRUE(plan.targets_met) << describe(plan);
  EXPECT_THAT(plan.stop_reason, HasSubstr("targets met"));
  const auto report = measure_coverage(odd, points_of(plan), "plan");
  EXPECT_TRUE(report.all()) << describe(report);
  // All four modes, all eight hazards and every transition the modes name are exercised.
  EXPECT_EQ(report.malfunctions.covered, 4u);
  EXPECT_EQ(report.hazards.covered, report.hazards.total);
  EXPECT_EQ(report.hazards.total, 8u);
  EXPECT_LE(plan.scenarios.size(), odd.budget);
  expect_plan_invariants(odd, plan);
}

TEST(PlanShipped, TrackedCellsGetTheWilsonSampleSize) {
  const Odd& odd = shipped_odd();
  const Plan& plan = shipped_plan();
  const std::size_t n = wilson_sample_size(odd.epsilon, 1.0 - odd.delta);
  EXPECT_EQ(plan.tests_per_tracked_cell, std::max<std::size_t>(n, static_cast<std::size_t>(odd.n_c)));
  EXPECT_EQ(plan.tests_per_tracked_cell, n);  // n_c = 1 in the example
  // At n the worst case over every outcome (p̂ = ½) is within ε, at n − 1 it is not.
  const auto worst = [&](double trials) { return wilson_interval(0.5 * trials, trials, 1.0 - odd.delta).half_width(); };
  EXPECT_LE(worst(static_cast<double>(n)), odd.epsilon);
  EXPECT_GT(worst(static_cast<double>(n - 1)), odd.epsilon);
  EXPECT_GT(plan.tracked_cells, 0u);
  EXPECT_LT(plan.tracked_cells, plan.relevant_cells);
}

TEST(PlanShipped, IsDeterministicAndDependsOnTheSeed) {
  const Odd& odd = shipped_odd();
  const Plan again = build_plan(odd);
  EXPECT_TRUE(same_scenarios(shipped_plan(), again));
  EXPECT_EQ(again.stop_reason, shipped_plan().stop_reason);
  Odd other = odd;
  other.seed = odd.seed + 1;
  const Plan different = build_plan(other);
  EXPECT_FALSE(same_scenarios(shipped_plan(), different));
  // The points differ, not only the seeds.
  EXPECT_NE(points_of(shipped_plan()), points_of(different));
  expect_plan_invariants(other, different);
}

TEST(PlanShipped, IsMuchSmallerThanTheCartesianGridItAbstracts) {
  // The paper's fine-grid sweep (Table "coverage parameter ranges"): 43 speeds x 1 truck speed x
  // 46 TTCs x 10 frictions x 2 passage widths.
  const double grid = 43.0 * 1 * 46 * 10 * 2;
  const auto n = static_cast<double>(shipped_plan().scenarios.size());
  const double factor = grid / n;
  RecordProperty("grid_to_plan_factor", fmt::format("{:.1f}", factor));
  std::printf("shipped plan: %.0f scenarios against a %.0f-point grid: %.1fx smaller\n", n, grid, factor);
  EXPECT_GT(factor, 50.0);
  // It is also no larger than a test per abstract cell times the tracked sample size.
  EXPECT_LE(n, shipped_odd().cell_count() * static_cast<double>(shipped_plan().tests_per_tracked_cell));
}

TEST(PlanShipped, SmallBudgetStopsTheTopUpButKeepsCoverage) {
  const Plan& full = shipped_plan();
  std::size_t coverage_size = 0;
  for (const auto& step : full.steps)
    if (step.name != "top_up") coverage_size += step.added;
  ASSERT_GT(full.steps.back().added, 5u) << "the example needs a top-up for this test";
  Odd odd = shipped_odd();
  odd.budget = coverage_size + 5;
  const Plan plan = build_plan(odd);
  EXPECT_EQ(plan.scenarios.size(), odd.budget);
  EXPECT_FALSE(plan.targets_met);
  EXPECT_THAT(plan.stop_reason, HasSubstr("budget"));
  const auto report = measure_coverage(odd, points_of(plan), "plan");
  EXPECT_TRUE(report.all()) << describe(report);
  expect_plan_invariants(odd, plan);

  // A budget below what coverage alone needs: coverage still wins, the stop reason says so.
  odd.budget = coverage_size / 2;
  const Plan tight = build_plan(odd);
  EXPECT_EQ(tight.scenarios.size(), coverage_size);
  EXPECT_EQ(tight.steps.back().added, 0u);
  EXPECT_FALSE(tight.targets_met);
  EXPECT_THAT(tight.stop_reason, HasSubstr("budget"));
  EXPECT_THAT(tight.stop_reason, HasSubstr("coverage"));
  EXPECT_TRUE(measure_coverage(odd, points_of(tight), "plan").all());
}

// ---- a hand-made ODD with an unreachable boundary -------------------------------------------------

const char* kUnreachable = R"(name: unreachable edge
factors:
  - name: x
    bins: [0, 1, 2]
  - name: y
    bins: [0, 1, 2]
  - name: k
    type: categorical
    classes: [a, b, c]
constraints:
  - "x <= 1.5"
  - "k != 2 || y < 1"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, budget: 100}
malfunctions:
  - id: M1
    region: "x + y > 2"
)";

TEST(PlanBoundary, UnreachableEdgesAreListedAndExemptFromC2) {
  const Odd odd = parse_odd(kUnreachable, "u.yaml", fs::temp_directory_path());
  const Plan plan = build_plan(odd);
  // x = 2 breaks x <= 1.5; y = 2 with class c breaks the second constraint but y = 2 is reachable.
  ASSERT_EQ(plan.infeasible.size(), 1u) << describe(plan);
  EXPECT_THAT(plan.infeasible[0], HasSubstr("x = 2"));
  const auto report = measure_coverage(odd, points_of(plan), "plan");
  EXPECT_TRUE(report.c2) << describe(report);
  EXPECT_TRUE(report.all()) << describe(report);
  // x = 0, 1 and y = 0, 1, 2 and the three classes count; x = 2 does not.
  EXPECT_EQ(report.boundaries.total, 2u + 3u + 3u);
  EXPECT_EQ(report.boundaries.covered, report.boundaries.total);
  // The tuple (y [1, 2], k = c) is inadmissible and not required (C3 over admissible tuples only).
  for (const auto& s : plan.scenarios) EXPECT_FALSE(s.values[2] == 2.0 && s.values[1] >= 1.0) << s.id;
  expect_plan_invariants(odd, plan);
}

// ---- modes whose region is empty inside the ODD ---------------------------------------------------

const char* kEmptyRegions = R"(name: empty regions
factors:
  - {name: x, bins: [0, 1, 2]}
  - {name: y, bins: [0, 1, 2]}
relevance: "x + y <= 3"
constraints:
  - "x <= 1.5"
coverage: {strength: 2, n_c: 1, n_m: 2, epsilon: 0.45, budget: 100}
malfunctions:
  - {id: M1, region: "x + y > 1"}
  - {id: M2, region: "x > 5"}
  - {id: M3, region: "x + y > 3.5"}
  - {id: M4, region: "x > 1.8"}
)";

const Shortfall* shortfall_of(const Plan& plan, const std::string& subject) {
  for (const auto& s : plan.shortfalls)
    if (s.subject == subject) return &s;
  return nullptr;
}

TEST(PlanShortfalls, AnEmptyRegionSaysSoAndWhy) {
  const Odd odd = parse_odd(kEmptyRegions, "e.yaml", fs::temp_directory_path());
  const Plan plan = build_plan(odd);
  EXPECT_EQ(shortfall_of(plan, "M1"), nullptr) << describe(plan);
  // Outside the factors' domains, outside R_f, outside a constraint: each named.
  const std::vector<std::pair<std::string, std::string>> expected{
      {"M2", "'x > 5' holds nowhere in the factors' domains (x in [0, 2])"},
      {"M3", "'x + y > 3.5' holds only where the relevance rule 'x + y <= 3' fails"},
      {"M4", "'x > 1.8' holds only where the constraint 'x <= 1.5' fails"}};
  for (const auto& [id, why] : expected) {
    const Shortfall* s = shortfall_of(plan, id);
    ASSERT_NE(s, nullptr) << id << "\n" << describe(plan);
    EXPECT_EQ(s->kind, ShortfallKind::kEmptyRegion) << id;
    EXPECT_EQ(s->found, 0u);
    EXPECT_EQ(s->needed, 2u);
    EXPECT_THAT(s->message, HasSubstr("malfunction " + id + ": its region is empty inside the ODD: " + why));
    EXPECT_THAT(plan.stop_reason, HasSubstr(s->message));
  }
  EXPECT_FALSE(plan.targets_met);
  EXPECT_FALSE(measure_coverage(odd, points_of(plan), "plan").c4);  // C4 still fails: the checker is not told
}

}  // namespace plan_test
}  // namespace emrm::scenario
