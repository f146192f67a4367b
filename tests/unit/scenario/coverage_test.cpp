// The coverage checker against hand-built ODDs whose answers follow from their definitions:
// grids over cell centres, an orthogonal array, points placed on or next to boundaries, and
// malfunction regions drawn by hand.

#include "emrm/scenario/coverage.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "emrm/scenario/plan.hpp"

namespace emrm::scenario {
namespace coverage_test {

using Points = std::vector<std::vector<double>>;

Odd odd_from(const std::string& yaml) { return parse_odd(yaml, "odd.yaml", "."); }

std::set<std::string> as_set(const std::vector<std::string>& v) { return {v.begin(), v.end()}; }

// Three ranged bins × two bins × three classes, no relevance predicate: 18 cells.
const char* const kGridOdd = R"(
name: grid
factors:
  - {name: a, bins: [0, 1, 2, 3]}
  - {name: b, bins: [0, 10, 20]}
  - {name: road, type: categorical, classes: [dry, wet, ice], values: [1.0, 0.6, 0.2]}
coverage: {strength: 2, n_c: 1, n_m: 1}
)";

Points cell_centres(const Odd& odd) {
  Points points;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 2; ++b)
      for (int r = 0; r < 3; ++r) {
        const auto& fa = odd.factors[0];
        const auto& fb = odd.factors[1];
        points.push_back(
            {0.5 * (fa.lower(a) + fa.upper(a)), 0.5 * (fb.lower(b) + fb.upper(b)), odd.factors[2].lower(r)});
      }
  return points;
}

TEST(CellCoverage, FullGridOfCellCentresMeetsC1) {
  const Odd odd = odd_from(kGridOdd);
  const CoverageReport r = measure_coverage(odd, cell_centres(odd), "grid");
  EXPECT_EQ(r.name, "grid");
  EXPECT_EQ(r.scenarios, 18U);
  EXPECT_EQ(r.inadmissible, 0U);
  EXPECT_EQ(r.cells.total, 18U);
  EXPECT_EQ(r.cells.covered, 18U);
  EXPECT_TRUE(r.cells.missing.empty());
  EXPECT_DOUBLE_EQ(r.cells.fraction(), 1.0);
  EXPECT_TRUE(r.c1);
  // Every pair of levels is in some cell, so the full grid is also 2-wise complete.
  EXPECT_EQ(r.twise.total, 3U * 2 + 3U * 3 + 2U * 3);
  EXPECT_TRUE(r.c3);
  // Centres sit on no bin edge, but they are every class: 4 + 3 edges, 3 classes hit.
  EXPECT_EQ(r.boundaries.total, 4U + 3U + 3U);
  EXPECT_EQ(r.boundaries.covered, 3U);
  EXPECT_FALSE(r.c2);
  // No malfunction modes: C4 holds vacuously.
  EXPECT_EQ(r.malfunctions.total, 0U);
  EXPECT_TRUE(r.c4);
}

TEST(CellCoverage, RemovingOnePointBreaksC1AtExactlyThatCell) {
  const Odd odd = odd_from(kGridOdd);
  Points points = cell_centres(odd);
  const std::vector<double> removed = points[7];  // a in [1, 2), b in [0, 10), road wet
  points.erase(points.begin() + 7);
  const CoverageReport r = measure_coverage(odd, points, "grid minus one");
  EXPECT_FALSE(r.c1);
  EXPECT_EQ(r.cells.covered, 17U);
  ASSERT_EQ(r.cells.missing.size(), 1U);
  EXPECT_EQ(r.cells.missing[0], cell_key(odd.cell_of(removed)));
  EXPECT_EQ(r.cells.missing[0], "c1.0.1");
}

TEST(CellCoverage, NcCountsTestsPerCell) {
  Odd odd = odd_from(kGridOdd);
  odd.n_c = 2;
  Points points = cell_centres(odd);
  EXPECT_FALSE(measure_coverage(odd, points, "once").c1);
  const Points again = points;
  for (auto p : again) {
    p[0] += 0.25;  // a second, different point in the same cell
    points.push_back(p);
  }
  const CoverageReport r = measure_coverage(odd, points, "twice");
  EXPECT_TRUE(r.c1);
  EXPECT_EQ(r.cells.covered, 18U);
}

// a + b/10 <= 2.5 leaves cell (a = [2, 3], b = [10, 20]) without an admissible point.
const char* const kRelevanceOdd = R"(
name: relevance
factors:
  - {name: a, bins: [0, 1, 2, 3]}
  - {name: b, bins: [0, 10, 20]}
relevance: "a + b / 10 <= 2.5"
constraints: ["a != 0.25"]
coverage: {strength: 2, n_c: 1, n_m: 1}
)";

TEST(CellCoverage, InadmissiblePointsAreCountedButCoverNothing) {
  const Odd odd = odd_from(kRelevanceOdd);
  const Points points{
      {0.5, 5},    // c0.0
      {1.2, 12},   // c1.1, admissible
      {1.5, 15},   // c1.1 centre, outside R_f
      {0.25, 15},  // c0.1, breaks the constraint
      {2.9, 19},   // c2.1, outside R_f
      {-1.0, 5},   // outside a's domain (though inside R_f)
      {0.5, -1},   // outside b's domain
  };
  const CoverageReport r = measure_coverage(odd, points, "mixed");
  EXPECT_EQ(r.scenarios, 7U);
  EXPECT_EQ(r.inadmissible, 5U);
  EXPECT_EQ(r.cells.total, 5U);  // every cell but c2.1
  EXPECT_EQ(r.cells.covered, 2U);
  EXPECT_EQ(as_set(r.cells.missing), (std::set<std::string>{"c0.1", "c1.0", "c2.0"}));
  EXPECT_FALSE(r.c1);
}

// The L9 orthogonal array: strength 2 over four 3-level factors in 9 rows, every pair exactly once.
const std::vector<std::vector<int>> kL9{{0, 0, 0, 0}, {0, 1, 1, 2}, {0, 2, 2, 1}, {1, 0, 1, 1}, {1, 1, 2, 0},
                                        {1, 2, 0, 2}, {2, 0, 2, 2}, {2, 1, 0, 1}, {2, 2, 1, 0}};

const char* const kFourFactorOdd = R"(
name: four
factors:
  - {name: x1, bins: [0, 1, 2, 3]}
  - {name: x2, bins: [0, 1, 2, 3]}
  - {name: x3, bins: [0, 1, 2, 3]}
  - {name: x4, bins: [0, 1, 2, 3]}
  - {name: wind, bins: [0, 5, 10], influential: false}
  - {name: truck_kph, type: constant, value: 10}
coverage: {strength: 2, n_c: 1, n_m: 1}
)";

Points at_bin_centres(const std::vector<std::vector<int>>& rows) {
  Points points;
  for (const auto& row : rows) {
    std::vector<double> p;
    p.reserve(row.size() + 2);
    for (int level : row) p.push_back(level + 0.5);
    p.push_back(2.5);  // wind, not influential
    p.push_back(10);   // the constant
    points.push_back(std::move(p));
  }
  return points;
}

TEST(TwiseCoverage, OrthogonalArrayCoversEveryPair) {
  const Odd odd = odd_from(kFourFactorOdd);
  ASSERT_EQ(odd.influential().size(), 4U);
  const CoverageReport r = measure_coverage(odd, at_bin_centres(kL9), "L9");
  EXPECT_EQ(r.twise.total, 6U * 9U);
  EXPECT_EQ(r.twise.covered, 6U * 9U);
  EXPECT_TRUE(r.twise.missing.empty());
  EXPECT_TRUE(r.c3);
  // ... but nowhere near every cell.
  EXPECT_EQ(r.cells.total, 81U * 2U);
  EXPECT_EQ(r.cells.covered, 9U);
  EXPECT_FALSE(r.c1);
}

TEST(TwiseCoverage, AnyEightRowsOfTheOrthogonalArrayMissTheirSixPairs) {
  const Odd odd = odd_from(kFourFactorOdd);
  for (std::size_t drop = 0; drop < kL9.size(); ++drop) {
    auto rows = kL9;
    rows.erase(rows.begin() + static_cast<std::ptrdiff_t>(drop));
    const CoverageReport r = measure_coverage(odd, at_bin_centres(rows), "L9 minus one");
    EXPECT_FALSE(r.c3) << "without row " << drop;
    EXPECT_EQ(r.twise.covered, 6U * 8U) << "without row " << drop;
    EXPECT_EQ(r.twise.missing.size(), 6U) << "without row " << drop;
  }
}

TEST(TwiseCoverage, MissingTuplesAreNamedByFactorAndLevel) {
  const Odd odd = odd_from(kFourFactorOdd);
  auto rows = kL9;
  rows.erase(rows.begin());  // the all-zero row
  const CoverageReport r = measure_coverage(odd, at_bin_centres(rows), "L9 minus row 0");
  ASSERT_EQ(r.twise.missing.size(), 6U);
  EXPECT_EQ(r.twise.missing[0], "x1 [0, 1), x2 [0, 1)");
  EXPECT_EQ(r.twise.missing[5], "x3 [0, 1), x4 [0, 1)");
}

TEST(TwiseCoverage, StrengthThreeCountsTriples) {
  Odd odd = odd_from(kFourFactorOdd);
  odd.strength = 3;
  const CoverageReport r = measure_coverage(odd, at_bin_centres(kL9), "L9 at t = 3");
  EXPECT_EQ(r.twise.total, 4U * 27U);
  EXPECT_EQ(r.twise.covered, 4U * 9U);  // each row realises one triple of each of the 4 column sets
  EXPECT_FALSE(r.c3);
}

TEST(TwiseCoverage, TuplesNoRelevantCellRealisesAreNotAdmissible) {
  Odd odd = odd_from(std::string(kFourFactorOdd) + "constraints: [\"!(x1 >= 2 && x2 >= 2)\"]\n");
  const CoverageReport r = measure_coverage(odd, at_bin_centres(kL9), "L9 with a constraint");
  EXPECT_EQ(r.twise.total, 6U * 9U - 1U);  // (x1 = 2, x2 = 2) is impossible
  // Row (2, 2, 1, 0) breaks the constraint: its five other pairs go uncovered.
  EXPECT_EQ(r.inadmissible, 1U);
  EXPECT_EQ(r.twise.covered, 6U * 9U - 6U);
  EXPECT_EQ(as_set(r.twise.missing),
            (std::set<std::string>{"x1 [2, 3], x3 [1, 2)", "x1 [2, 3], x4 [0, 1)", "x2 [2, 3], x3 [1, 2)",
                                   "x2 [2, 3], x4 [0, 1)", "x3 [1, 2), x4 [0, 1)"}));
}

// x has edges 0, 1, 2 and a kink at 1.5; R_f cuts x at 1.5, so x = 2 is infeasible.
const char* const kBoundaryOdd = R"(
name: boundaries
factors:
  - {name: x, bins: [0, 1, 2], kinks: [1.5]}
  - {name: y, bins: [0, 1]}
  - {name: road, type: categorical, classes: [dry, wet, ice]}
relevance: "x <= 1.5"
constraints: ["road != 2 || y < 0.5"]
coverage: {strength: 2, n_c: 1, n_m: 1}
)";

TEST(BoundaryCoverage, CountsOnlyPointsExactlyOnTheTarget) {
  const Odd odd = odd_from(kBoundaryOdd);
  ASSERT_EQ(boundary_targets(odd).size(), 4U + 2U + 3U);
  const Points points{{0, 0, 0}, {1, 1, 1}, {1.5, 0.25, 2}};
  const CoverageReport r = measure_coverage(odd, points, "on the edges");
  EXPECT_EQ(r.boundaries.total, 8U);  // every target but x = 2
  EXPECT_EQ(r.boundaries.covered, 8U);
  EXPECT_TRUE(r.c2);

  // Next to an edge is not on it; within a relative 1e-9 is.
  const Points near{{0, 0, 0}, {1.000001, 1, 1}, {1.5 * (1 - 1e-12), 0.25, 2}};
  const CoverageReport n = measure_coverage(odd, near, "near the edges");
  EXPECT_EQ(n.boundaries.total, 8U);
  EXPECT_EQ(n.boundaries.covered, 7U);
  EXPECT_EQ(n.boundaries.missing, std::vector<std::string>{"x = 1"});
  EXPECT_FALSE(n.c2);
}

TEST(BoundaryCoverage, InfeasibleTargetsAreNotCounted) {
  const Odd odd = odd_from(kBoundaryOdd);
  // A point at x = 2 would be outside R_f: it neither hits x = 2 nor makes it count.
  const Points points{{2, 0, 0}};
  const CoverageReport r = measure_coverage(odd, points, "beyond R_f");
  EXPECT_EQ(r.inadmissible, 1U);
  EXPECT_EQ(r.boundaries.total, 8U);
  EXPECT_EQ(r.boundaries.covered, 0U);
  EXPECT_EQ(std::count(r.boundaries.missing.begin(), r.boundaries.missing.end(), "x = 2"), 0);
  EXPECT_EQ(std::count(r.boundaries.missing.begin(), r.boundaries.missing.end(), "x = 1.5"), 1);
  EXPECT_EQ(std::count(r.boundaries.missing.begin(), r.boundaries.missing.end(), "road = ice"), 1);
}

TEST(BoundaryCoverage, AClassExcludedByAConstraintIsInfeasible) {
  Odd odd = odd_from(kBoundaryOdd);
  odd.constraints.emplace_back("road != 2", odd.factor_names(), SourceLocation{});
  const CoverageReport r = measure_coverage(odd, {}, "nothing");
  EXPECT_EQ(r.boundaries.total, 7U);  // neither x = 2 nor road = ice
  EXPECT_EQ(std::count(r.boundaries.missing.begin(), r.boundaries.missing.end(), "road = ice"), 0);
}

// Hand-drawn regions: M1 at short TTC, M2 fast with long TTC, M3 everywhere.
const char* const kHazardOdd = R"(
name: hazards
factors:
  - {name: ttc_s, bins: [0, 1, 2, 3], nominal: 1.5}
  - {name: speed_kph, bins: [30, 50, 70], nominal: 40}
constraints: ["speed_kph < 68"]
malfunctions:
  - {id: M1, region: "ttc_s < 1", hazards: [H1, H2], transitions: ["S1 -a-> S2"]}
  - {id: M2, region: "speed_kph >= 60 && ttc_s >= 2", hazards: [H3], transitions: ["S2 -b-> S3", "S1 -a-> S2"]}
  - {id: M3, hazards: [H4], transitions: ["S3 -c-> S4"]}
hazards: [H1, H2, H3, H5]
coverage: {strength: 2, n_c: 1, n_m: 1}
)";

TEST(HazardCoverage, FollowsTheRegionsOfTheModesLeadingToEachHazard) {
  const Odd odd = odd_from(kHazardOdd);
  const Points points{{0.5, 40}, {2.5, 69}};  // the second breaks the constraint
  const CoverageReport r = measure_coverage(odd, points, "two points");
  EXPECT_EQ(r.inadmissible, 1U);
  EXPECT_EQ(r.hazards.total, 5U);    // H1–H5
  EXPECT_EQ(r.hazards.covered, 3U);  // H1, H2 (M1) and H4 (M3)
  EXPECT_EQ(as_set(r.hazards.missing), (std::set<std::string>{"H3", "H5"}));

  EXPECT_EQ(r.malfunctions.total, 3U);
  EXPECT_EQ(r.malfunctions.covered, 2U);
  EXPECT_EQ(r.malfunctions.missing, std::vector<std::string>{"M2"});
  EXPECT_FALSE(r.c4);

  EXPECT_EQ(r.transitions.total, 3U);  // the union of the modes' transitions
  EXPECT_EQ(r.transitions.covered, 2U);
  EXPECT_EQ(r.transitions.missing, std::vector<std::string>{"S2 -b-> S3"});
}

TEST(HazardCoverage, C4NeedsNmPointsInEveryRegion) {
  Odd odd = odd_from(kHazardOdd);
  const Points points{{0.5, 40}, {2.5, 65}};
  CoverageReport r = measure_coverage(odd, points, "one each");
  EXPECT_EQ(r.malfunctions.covered, 3U);
  EXPECT_EQ(r.hazards.missing, std::vector<std::string>{"H5"});  // no mode leads to H5
  EXPECT_TRUE(r.transitions.missing.empty());
  EXPECT_TRUE(r.c4);  // n_m = 1; M3 (no region) holds at both points

  odd.n_m = 2;
  EXPECT_FALSE(measure_coverage(odd, points, "one each, n_m = 2").c4);
  const Points more{{0.5, 40}, {0.2, 55}, {2.5, 65}, {2.1, 60}};
  EXPECT_TRUE(measure_coverage(odd, more, "two each, n_m = 2").c4);
}

TEST(HazardCoverage, TransitionsAreMeasuredAgainstTheFsmWhenGiven) {
  Odd odd = odd_from(kHazardOdd);
  odd.fsm_transitions = {"S0 -start-> S1", "S1 -a-> S2", "S2 -b-> S3", "S3 -c-> S4"};
  const CoverageReport r = measure_coverage(odd, {{0.5, 40}}, "one point");
  EXPECT_EQ(r.transitions.total, 4U);
  EXPECT_EQ(r.transitions.covered, 2U);
  EXPECT_EQ(r.transitions.missing, (std::vector<std::string>{"S0 -start-> S1", "S2 -b-> S3"}));
}

TEST(CoverageReportAll, IsTheConjunctionOfC1ToC4) {
  CoverageReport r;
  r.c1 = r.c2 = r.c3 = r.c4 = true;
  EXPECT_TRUE(r.all());
  r.c3 = false;
  EXPECT_FALSE(r.all());
}

TEST(CoverageMeasure, RejectsPointsOfTheWrongLength) {
  const Odd odd = odd_from(kHazardOdd);
  EXPECT_THROW((void)measure_coverage(odd, {{0.5}}, "short"), std::invalid_argument);
}

TEST(CoverageMeasure, EmptySetCoversNothing) {
  const Odd odd = odd_from(kHazardOdd);
  const CoverageReport r = measure_coverage(odd, {}, "empty");
  EXPECT_EQ(r.cells.covered, 0U);
  EXPECT_EQ(r.cells.total, 6U);
  EXPECT_EQ(r.hazards.covered, 0U);
  EXPECT_FALSE(r.c1);
  EXPECT_FALSE(r.c4);
  EXPECT_DOUBLE_EQ(r.cells.fraction(), 0.0);
}

const char* const kBaselineOdd = R"(
name: baselines
factors:
  - {name: ttc_s, bins: [0, 1, 2, 3], nominal: 1.5}
  - {name: speed_kph, bins: [30, 50, 70], nominal: 50}
  - {name: road, type: categorical, classes: [dry, wet], values: [1.0, 0.5], nominal: dry}
  - {name: truck_kph, type: constant, value: 10}
malfunctions:
  - {id: LATE, region: "ttc_s <= 1", hazards: [H1]}
  - {id: WET, region: "road < 0.7 && speed_kph >= 50", hazards: [H2]}
  - {id: HERE, region: "ttc_s > 1", hazards: [H1]}
  - {id: NEVER, region: "ttc_s > 5", hazards: [H3]}
hazards: [H1, H2, H3]
coverage: {strength: 2, n_c: 1, n_m: 1}
baselines:
  manual:
    speed_kph: [30, 50, 70]
    ttc_s: {from: 0, to: 3, levels: 4}
)";

double normalised_distance(const Odd& odd, const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < odd.factors.size(); ++i) {
    const double w = odd.factors[i].domain_max() - odd.factors[i].domain_min();
    if (w > 0) d += std::pow((a[i] - b[i]) / w, 2);
  }
  return std::sqrt(d);
}

// Two lines of YAML could ask for 10⁸ × 10⁸ baseline scenarios: refused at the factor that
// passes the limit, before any is built.
TEST(CoverageBaselines, AManualGridTooLargeIsRefusedWhereItGrows) {
  std::string text = kBaselineOdd;
  const std::string small = "    ttc_s: {from: 0, to: 3, levels: 4}\n";
  text.replace(text.find(small), small.size(), "    ttc_s: {from: 0, to: 3, levels: 40000}\n");
  try {
    (void)odd_from(text);
    FAIL() << "a manual grid of 120 000 points was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("the manual grid has 120000 points, more than the 100000 it may have"));
    const std::string before = text.substr(0, text.find("ttc_s: {from: 0, to: 3, levels: 40000}"));
    EXPECT_EQ(e.where().line, 1 + std::count(before.begin(), before.end(), '\n'));
  }
}

TEST(CoverageBaselines, NominalPointTakesEveryFactorsNominal) {
  const Odd odd = odd_from(kBaselineOdd);
  EXPECT_EQ(nominal_point(odd), (std::vector<double>{1.5, 50, 1.0, 10}));
}

TEST(CoverageBaselines, HaraOnlyIsOneNominalScenarioPerHazard) {
  const Odd odd = odd_from(kBaselineOdd);
  const Points hara = hara_only_baseline(odd);
  ASSERT_EQ(hara.size(), 3U);
  for (const auto& p : hara) EXPECT_EQ(p, nominal_point(odd));
  const CoverageReport r = measure_coverage(odd, hara, "HARA only");
  EXPECT_EQ(r.cells.covered, 1U);
  EXPECT_EQ(r.malfunctions.missing, (std::vector<std::string>{"LATE", "WET", "NEVER"}));
}

TEST(CoverageBaselines, StpaOnlyIsOnePointPerReachableModeInsideItsRegion) {
  const Odd odd = odd_from(kBaselineOdd);
  const Points stpa = stpa_only_baseline(odd);
  ASSERT_EQ(stpa.size(), 3U);  // NEVER has no admissible point
  const std::vector<std::size_t> modes{0, 1, 2};
  for (std::size_t k = 0; k < stpa.size(); ++k) {
    const Malfunction& m = odd.malfunctions[modes[k]];
    EXPECT_TRUE(odd.admissible(stpa[k])) << m.id;
    EXPECT_TRUE(m.region->holds(stpa[k])) << m.id;
  }
  // The nominal point is in HERE's region; LATE's nearest point is on its edge ttc = 1.
  EXPECT_EQ(stpa[2], nominal_point(odd));
  EXPECT_EQ(stpa[0], (std::vector<double>{1.0, 50, 1.0, 10}));
  // WET: only the road must change, across its whole width.
  EXPECT_EQ(stpa[1], (std::vector<double>{1.5, 50, 0.5, 10}));
  EXPECT_NEAR(normalised_distance(odd, stpa[1], nominal_point(odd)), 1.0, 1e-12);

  const CoverageReport r = measure_coverage(odd, stpa, "STPA only");
  EXPECT_EQ(r.malfunctions.covered, 3U);
  EXPECT_EQ(r.malfunctions.missing, std::vector<std::string>{"NEVER"});
  EXPECT_EQ(r.hazards.missing, std::vector<std::string>{"H3"});
}

TEST(CoverageBaselines, StpaOnlyIsDeterministic) {
  const Odd odd = odd_from(kBaselineOdd);
  EXPECT_EQ(stpa_only_baseline(odd), stpa_only_baseline(odd));
}

TEST(CoverageBaselines, ManualIsTheProductGridWithOtherFactorsNominal) {
  const Odd odd = odd_from(kBaselineOdd);
  const Points manual = manual_baseline(odd);
  ASSERT_EQ(manual.size(), 12U);
  std::size_t k = 0;
  for (const double speed : {30.0, 50.0, 70.0})
    for (const double ttc : {0.0, 1.0, 2.0, 3.0}) {
      EXPECT_NEAR(manual[k][0], ttc, 1e-12) << k;
      EXPECT_EQ(manual[k][1], speed) << k;
      EXPECT_EQ(manual[k][2], 1.0) << k;
      EXPECT_EQ(manual[k][3], 10.0) << k;
      ++k;
    }
  const CoverageReport r = measure_coverage(odd, manual, "manual grid");
  EXPECT_EQ(r.cells.covered, 6U);  // 3 TTC bins × 2 speed bins, all on dry road
  EXPECT_EQ(r.cells.total, 12U);
}

TEST(CoverageBaselines, ManualIsEmptyWithoutAGrid) { EXPECT_TRUE(manual_baseline(odd_from(kHazardOdd)).empty()); }

TEST(CoverageJson, ListsEveryCountAndConstraintInOrder) {
  const Odd odd = odd_from(kHazardOdd);
  const CoverageReport r = measure_coverage(odd, {{0.5, 40}, {2.5, 69}}, "two points");
  const nlohmann::ordered_json j = to_json(r);
  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"name", "scenarios", "inadmissible", "hazards", "malfunctions",
                                            "tests_per_malfunction", "transitions", "cells", "boundaries", "twise",
                                            "c1", "c2", "c3", "c4", "all"}));
  EXPECT_EQ(j["name"], "two points");
  EXPECT_EQ(j["scenarios"], 2);
  EXPECT_EQ(j["inadmissible"], 1);
  EXPECT_EQ(j["hazards"]["covered"], 3);
  EXPECT_EQ(j["hazards"]["total"], 5);
  EXPECT_DOUBLE_EQ(j["hazards"]["fraction"].get<double>(), 0.6);
  EXPECT_EQ(j["malfunctions"]["missing"], nlohmann::ordered_json::array({"M2"}));
  // Per mode, the admissible tests inside its region (M2 has none).
  EXPECT_EQ(j["tests_per_malfunction"]["M2"], 0);
  EXPECT_EQ(j["c4"], false);
  EXPECT_EQ(j["all"], r.all());
}

}  // namespace coverage_test
}  // namespace emrm::scenario
