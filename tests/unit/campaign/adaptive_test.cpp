#include "adaptive_support.hpp"

namespace emrm::campaign::adaptive {
namespace adaptive_test {

TEST(AdaptiveSearch, FindsASmoothMonotoneMapExactlyFromAFewSimulations) {
  const SyntheticMap map = fine_map();
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, Options{});
  const Comparison c = compare(map, result);
  EXPECT_EQ(c.differ, 0U);
  EXPECT_EQ(result.feasible, c.feasible);
  EXPECT_EQ(result.simulated, oracle.total());
  EXPECT_LT(static_cast<double>(result.simulated), 0.2 * static_cast<double>(c.feasible));
  EXPECT_TRUE(result.violations.empty());
}

TEST(AdaptiveSearch, EveryInferredCellNamesItsGrounds) {
  const SyntheticMap map = fine_map();
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, Options{});
  for (std::size_t cell = 0; cell < result.cells.size(); ++cell) {
    const Cell& c = result.cells[cell];
    if (c.method == Method::kLine || c.method == Method::kBox) {
      ASSERT_FALSE(c.from.empty()) << cell;
      for (const auto from : c.from) EXPECT_EQ(result.cells[from].method, Method::kSimulated) << cell;
    }
    if (c.method == Method::kStop) {
      EXPECT_EQ(c.region, Region::kG);
    }
  }
}

// A synthetic map whose avoidance threshold moves with speed and friction more than the real one's
// (docs/adaptive.md measures the real one): a third factor still costs a smaller share of the cells.
TEST(AdaptiveSearch, ThreeFactorsCostAFractionOfTheTwoFactorGrid) {
  SyntheticMap map = fine_map();
  map.lattice.levels[0] = range(30, 72, 2);
  map.lattice.levels[2] = range(0.2, 1.0, 0.1);
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, Options{});
  const Comparison c = compare(map, result);
  EXPECT_GE(map.lattice.size(), 9000U);
  EXPECT_LE(static_cast<double>(c.differ), 0.01 * static_cast<double>(c.feasible));
  EXPECT_EQ(c.g_wrong, 0U);
  EXPECT_LT(static_cast<double>(result.simulated), 0.12 * static_cast<double>(c.feasible));
}

TEST(AdaptiveSearch, TheStopBoundaryIsExactInEveryDimensionCount) {
  std::mt19937_64 random(7);
  for (int trial = 0; trial < 6; ++trial) {
    SyntheticMap map;
    std::uniform_real_distribution<double> jitter(-0.03, 0.03);
    const double slope = 0.002 + 0.002 * trial;
    map.lattice.levels = {
        range(30, 72, 3), range(0.25, 2.95, 0.09), trial % 2 ? range(0.3, 1.0, 0.35) : std::vector{0.8},
        trial % 3 ? std::vector{2.0, 3.0} : std::vector{3.0}, trial > 3 ? std::vector{0.0, 10.0} : std::vector{10.0}};
    std::map<std::size_t, double> noise;
    map.avoid_ttc = [slope](double v, double mu, double passage, double) {
      return 0.5 + slope * v / mu + 0.1 / passage;
    };
    std::uniform_int_distribution<std::size_t> pick(0, map.lattice.size() - 1);
    for (int k = 0; k < 10; ++k) map.flipped.insert(pick(random));
    MapOracle oracle(map);
    const Result result = search(map.lattice, oracle, Options{});
    EXPECT_EQ(compare(map, result).g_wrong, 0U) << "trial " << trial;
  }
}

TEST(AdaptiveSearch, ResultsDoNotDependOnTheThreadCount) {
  SyntheticMap map = fine_map();
  map.flipped = {100, 400, 777, 1200};
  std::vector<Region> regions[2];
  for (int t = 0; t < 2; ++t) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t == 0 ? 1 : 4);
    MapOracle oracle(map);
    Options options;
    options.verify_sample = 30;
    const Result result = search(map.lattice, oracle, options);
    for (const Cell& c : result.cells) regions[t].push_back(c.region);
  }
  EXPECT_EQ(regions[0], regions[1]);
}

TEST(AdaptiveSearch, AViolationOfMonotonicityIsReportedAndItsLineSimulatedInFull) {
  SyntheticMap map = fine_map();
  // At 30 km/h (a corner of the domain, where the search always looks) the car avoids at the lowest
  // TTCs though not above them: a reversal the search must catch, then resolve the line and its
  // neighbours cell by cell.
  const std::size_t s = 0;
  map.avoid_ttc = [](double v, double mu, double, double) { return 0.6 + 0.004 * v / mu; };
  SyntheticMap broken = map;
  const std::size_t n_ttc = map.lattice.levels[1].size();
  std::set<std::size_t> y_cells;
  for (std::size_t t = 0; t < 6; ++t) y_cells.insert(s * n_ttc + t);  // Y at the lowest TTCs
  broken.unavoidable = [](double v, double ttc, double) { return v == 30.0 && ttc < 0.6 ? Region::kY : Region::kR; };
  MapOracle oracle(broken);
  Options options;
  options.stride = 2;
  const Result result = search(broken.lattice, oracle, options);
  ASSERT_FALSE(result.violations.empty());
  EXPECT_EQ(result.violations.front().what, "avoidance");
  EXPECT_GE(result.lines_fully_resolved, 1U);
  for (std::size_t cell : y_cells) EXPECT_EQ(result.cells[cell].region, Region::kY) << cell;
  for (std::size_t cell : y_cells) EXPECT_EQ(result.cells[cell].method, Method::kSimulated) << cell;
}

TEST(AdaptiveSearch, TheVerificationSampleCountsAndBoundsTheDisagreements) {
  SyntheticMap map = fine_map();
  std::mt19937_64 random(3);
  std::uniform_int_distribution<std::size_t> pick(0, map.lattice.size() - 1);
  for (int k = 0; k < 60; ++k) map.flipped.insert(pick(random));
  MapOracle oracle(map);
  Options options;
  options.verify_sample = 200;
  const Result result = search(map.lattice, oracle, options);
  EXPECT_EQ(result.verify_sampled, std::min<std::size_t>(200, result.verify_population));
  EXPECT_EQ(result.simulated, oracle.total());
  EXPECT_LE(result.disagreement.low, result.disagreement.high);
  const double rate =
      static_cast<double>(result.verify_disagreements.size()) / static_cast<double>(result.verify_sampled);
  EXPECT_LE(result.disagreement.low, rate);
  EXPECT_GE(result.disagreement.high, rate);
  // A sampled cell is simulated now, so it holds the truth.
  for (const auto cell : result.verify_disagreements) {
    EXPECT_EQ(result.cells[cell].method, Method::kSimulated);
    EXPECT_EQ(result.cells[cell].region, map.truth(cell));
  }
}

TEST(AdaptiveSearch, DegenerateGridsSimplyWork) {
  for (const auto& levels : std::vector<std::vector<std::vector<double>>>{
           {std::vector{50.0}, std::vector{1.0}, std::vector{1.0}, std::vector{3.0}, std::vector{10.0}},
           {std::vector{50.0}, range(0.25, 2.95, 0.06), std::vector{1.0}, std::vector{3.0}, std::vector{10.0}},
           {range(30, 72, 1), std::vector{1.0}, std::vector{1.0}, std::vector{3.0}, std::vector{10.0}},
           {range(30, 72, 1), std::vector{0.6}, range(0.1, 1.0, 0.1), std::vector{3.0}, std::vector{10.0}},
           {std::vector{200.0}, std::vector{2.9}, std::vector{1.0}, std::vector{3.0}, std::vector{10.0}}}) {
    SyntheticMap map = fine_map();
    map.lattice.levels = levels;
    MapOracle oracle(map);
    const Result result = search(map.lattice, oracle, Options{});
    EXPECT_EQ(compare(map, result).differ, 0U);
  }
}

TEST(AdaptiveSearch, UnsortedLevelsAreSearchedInOrderOfValue) {
  SyntheticMap map = fine_map();
  std::mt19937_64 random(11);
  std::shuffle(map.lattice.levels[1].begin(), map.lattice.levels[1].end(), random);
  std::shuffle(map.lattice.levels[0].begin(), map.lattice.levels[0].end(), random);
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, Options{});
  EXPECT_EQ(compare(map, result).differ, 0U);
  EXPECT_LT(static_cast<double>(result.simulated), 0.2 * static_cast<double>(result.feasible));
}

// Where the truck is still on its way, the car passes in front of it at the lowest TTCs (G, then
// Y), below the cells that cannot avoid: each line's early run is found by its own few simulations,
// exactly, without resolving lines in full, and a static truck's lines spend nothing on it.
TEST(AdaptiveSearch, FindsTheEarlyRunOfATruckStillOnItsWay) {
  SyntheticMap map;
  // Where the passage is wide, avoidance by swerving starts low enough to meet the early run: no
  // cell of the line is unavoidable, and a search that took a neighbour's early run for its own
  // would jump the gap of the lines that have one.
  map.lattice.levels = {range(30, 72, 2), range(0.25, 2.95, 0.06), range(0.3, 1.0, 0.1), {2.2, 3.4}, {0.0, 20.0}};
  map.avoid_ttc = [](double v, double mu, double passage, double) {
    return 0.6 + 0.004 * v / mu - 0.4 * (passage - 2.2);
  };
  map.early_g_ttc = [](double v, double mu) { return 0.2 + 4.0 / v + 0.05 * mu; };
  map.early_ttc = [](double v, double mu) { return 0.35 + 4.0 / v + 0.1 * mu; };
  // Each line searches its own threshold even between agreeing corners, so that what differs is
  // the early run's alone.
  Options options;
  options.brackets = Brackets::kSearch;
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, options);
  const Comparison c = compare(map, result);
  std::size_t early_g = 0, early_y = 0;
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {
    if (!map.feasible(cell) || !map.passes_early(cell)) continue;
    const double ttc = map.factors(cell)[1], v = map.factors(cell)[0], mu = map.factors(cell)[2];
    early_g += ttc < map.early_g_ttc(v, mu);
    early_y += ttc >= map.early_g_ttc(v, mu) && ttc < map.early_ttc(v, mu);
  }
  EXPECT_GT(early_g, 100U);
  EXPECT_GT(early_y, 100U);
  std::size_t lines_without_gap = 0;
  for (double v : map.lattice.levels[0])
    for (double mu : map.lattice.levels[2])
      lines_without_gap += map.avoid_ttc(v, mu, 3.4, 20.0) <= map.early_ttc(v, mu);
  EXPECT_GT(lines_without_gap, 10U);
  // Where a line's gap closes to one or two cells, the walk up the early run (steps of up to the
  // stride) can step over it: such cells are wrong, within the 0.5 % the search is held to.
  EXPECT_GT(c.differ, 0U);
  EXPECT_LE(c.differ, c.feasible / 200);
  EXPECT_EQ(c.g_wrong, 0U);
  EXPECT_TRUE(result.violations.empty());
  EXPECT_EQ(result.lines_fully_resolved, 0U);
  EXPECT_EQ(result.simulated, oracle.total());
  EXPECT_LT(static_cast<double>(result.simulated), 0.2 * static_cast<double>(c.feasible));

  // The static truck's lines alone: no early run, and none looked for (its lowest cells are
  // simulated only where the labels need them).
  SyntheticMap still = map;
  still.lattice.levels[3] = {2.2};
  still.lattice.levels[4] = {0.0};
  MapOracle still_oracle(still);
  const Result still_result = search(still.lattice, still_oracle, options);
  EXPECT_EQ(compare(still, still_result).differ, 0U);
  EXPECT_LT(still_result.simulated, result.simulated / 2);
}

}  // namespace adaptive_test
}  // namespace emrm::campaign::adaptive
