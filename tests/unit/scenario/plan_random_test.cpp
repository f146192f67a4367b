#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "emrm/scenario/plan.hpp"
#include "plan_support.hpp"

namespace emrm::scenario {
namespace plan_random_test {

using namespace test_support;  // NOLINT(google-build-using-namespace)
using ::testing::HasSubstr;

// ---- seeded random ODDs -----------------------------------------------------------------------------

TEST(PlanRandom, EveryPlanSatisfiesTheCheckerAndItsInvariants) {
  constexpr std::uint64_t kOdds = 24;
  int checked = 0;
  int met = 0;
  int strength3 = 0;
  for (std::uint64_t seed = 1; seed <= kOdds; ++seed) {
    const RandomOddText r = random_odd(seed);
    SCOPED_TRACE(fmt::format("random ODD {}:\n{}", seed, r.yaml));
    Odd odd;
    try {
      odd = parse_odd(r.yaml, fmt::format("random{}.yaml", seed), fs::temp_directory_path());
    } catch (const InputError& e) {
      ADD_FAILURE() << "the generator wrote an ODD the loader rejects: " << e.what();
      continue;
    }
    const Plan plan = build_plan(odd);
    expect_plan_invariants(odd, plan);
    if (plan.shortfalls.empty()) ++checked;
    if (odd.strength == 3) ++strength3;
    EXPECT_EQ(plan.tests_per_tracked_cell, std::max<std::size_t>(wilson_sample_size(odd.epsilon, 1.0 - odd.delta),
                                                                 static_cast<std::size_t>(odd.n_c)));
    if (!plan.targets_met && plan.shortfalls.empty()) {
      // Short of the precision target without a shortfall: the budget is spent, or tracked cells
      // (of discrete factors) hold fewer distinct points than the target; the reason says which.
      const bool spent = plan.scenarios.size() >= odd.budget;
      EXPECT_THAT(plan.stop_reason, HasSubstr(spent ? "budget" : "too few distinct admissible points"))
          << describe(plan);
    }
    if (plan.targets_met) ++met;
    if (seed % 6 == 0) {
      EXPECT_TRUE(same_scenarios(plan, build_plan(odd))) << "not deterministic";
      Odd other = odd;
      other.seed += 1000;
      EXPECT_FALSE(same_scenarios(plan, build_plan(other))) << "the seed changes nothing";
    }
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("random ODDs: %d of %llu checked against C1-C4 (no shortfall), %d met every target, %d of strength 3\n",
              checked, static_cast<unsigned long long>(kOdds), met, strength3);
  // The random ODDs are mostly feasible: the C1–C4 check above ran on most of them.
  EXPECT_GE(checked, 18);
  EXPECT_GE(strength3, 2);
}

// Two ODDs whose relevance holds on a sliver that the relevant-cell probes miss (docs/odd-yaml.md:
// "choose bins so that regions are not thinner than that"). The plan must still be consistent
// with itself and with the independent checker.

// Cell (x [0, 1), y [0, 1)) is admissible only on the line y = 0.3 (a kink), which its probes miss.
const char* kSliverBehindAKink = R"X(name: sliver behind a kink
factors:
  - name: x
    bins: [0, 1, 2]
  - name: y
    bins: [0, 1, 2]
    kinks: [0.3]
relevance: "x >= 1 || abs(y - 0.3) < 0.0005"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, budget: 100}
)X";

TEST(PlanSliver, BoundaryPointsStayInRelevantCellsAndAreNotCalledInfeasible) {
  const Odd odd = parse_odd(kSliverBehindAKink, "sliver.yaml", fs::temp_directory_path());
  const Plan plan = build_plan(odd);
  std::set<std::vector<int>> relevant;
  for (const auto& c : relevant_cells(odd)) relevant.insert(c.levels);
  double sum = 0.0;
  for (const auto& s : plan.scenarios) {
    sum += s.weight;
    EXPECT_TRUE(relevant.count(s.cell)) << s.id << " (" << s.values[0] << ", " << s.values[1] << ") in "
                                        << cell_key(s.cell) << ", which is not a relevant cell; weight " << s.weight;
  }
  EXPECT_NEAR(sum, static_cast<double>(plan.scenarios.size()), 1e-9) << "weights must sum to N";
  // A target some scenario hits is not infeasible.
  for (const auto& s : plan.scenarios) {
    if (s.values[0] != 0.0) continue;
    for (const auto& note : plan.infeasible)
      EXPECT_THAT(note, ::testing::Not(HasSubstr("x = 0"))) << s.id << " hits x = 0";
  }
  EXPECT_TRUE(measure_coverage(odd, points_of(plan), "plan").all());
}

// Target x = 1 is reachable only at x = 1, |y - 0.3| < 0.05: the lower edge of a cell whose probes
// all miss it. The checker finds the point from the neighbouring cell (x [0, 1), y [0, 1)).
const char* kTargetOnAnEdgeSegment = R"X(name: target on an edge segment
factors:
  - name: x
    bins: [0, 1, 2]
  - name: y
    bins: [0, 1, 2]
relevance: "x < 1 || (x == 1 && abs(y - 0.3) < 0.05)"
coverage: {strength: 2, n_c: 1, n_m: 1, epsilon: 0.45, budget: 100}
)X";

TEST(PlanSliver, ReachableBoundaryIsNotDeclaredInfeasible) {
  const Odd odd = parse_odd(kTargetOnAnEdgeSegment, "edge.yaml", fs::temp_directory_path());
  ASSERT_TRUE(odd.admissible(std::vector<double>{1.0, 0.3}));  // x = 1 is reachable
  const Plan plan = build_plan(odd);
  for (const auto& note : plan.infeasible) EXPECT_THAT(note, ::testing::Not(HasSubstr("x = 1"))) << describe(plan);
  const auto report = measure_coverage(odd, points_of(plan), "plan");
  EXPECT_TRUE(report.c2) << describe(report) << "\n" << describe(plan);
}

}  // namespace plan_random_test
}  // namespace emrm::scenario
