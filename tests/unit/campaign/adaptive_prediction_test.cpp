// The adaptive search from three factors on: thresholds, early runs and label changes predicted from
// the corners of boxes, and what keeps the predictions honest.

#include "adaptive_support.hpp"

namespace emrm::campaign::adaptive {
namespace adaptive_test {

// Where friction and passage are stepped coarsely, the avoidance threshold moves by more than a TTC
// level from one line to the next, so boxes of lines rarely agree and most lines search their own
// threshold. Each starts where its box's searched corners point (interpolated, not their median):
// about two simulations a line for the threshold, as when a bracket holds.
TEST(AdaptiveSearch, PredictsALinesThresholdFromItsNeighbours) {
  SyntheticMap map;
  map.lattice.levels = {range(30, 72, 6), range(0.25, 2.95, 0.06), range(0.1, 1.0, 0.1), range(1.0, 4.0, 0.6), {0.0}};
  map.avoid_ttc = [](double v, double mu, double passage, double) {
    return 0.45 + 0.004 * v / mu - 0.15 * (passage - 2.2);
  };
  MapOracle oracle(map);
  Options options;
  options.brackets = Brackets::kSearch;
  const Result result = search(map.lattice, oracle, options);
  const Comparison c = compare(map, result);
  EXPECT_EQ(c.differ, 0U);
  EXPECT_TRUE(result.violations.empty());
  const auto threshold_simulations = result.simulated_for[static_cast<std::size_t>(Purpose::kThresholdCorners)] +
                                     result.simulated_for[static_cast<std::size_t>(Purpose::kThresholdBrackets)];
  // From the median of the parent box's corners the same search took 3.7 simulations a line.
  EXPECT_LT(static_cast<double>(threshold_simulations), 3.4 * static_cast<double>(result.lines));
}

// The map searched with every bracket searched ([0]) and with the default predictions ([1]).
std::array<Result, 2> searched_and_predicted(const SyntheticMap& map) {
  std::array<Result, 2> results;
  for (int predict = 0; predict < 2; ++predict) {
    Options options;
    options.brackets = predict ? Brackets::kAuto : Brackets::kSearch;
    MapOracle oracle(map);
    results[predict] = search(map.lattice, oracle, options);
  }
  return results;
}

// From three factors on, a line between corners whose thresholds agree within a level takes the
// threshold predicted from them without a simulation (Brackets::kAuto): fewer simulations, and
// where the prediction is wrong the line is off by that one level, the cell at its threshold Y for
// O or R (never a G cell), within the 1 % the search is held to on three factors.
TEST(AdaptiveSearch, PredictedBracketsMissByOneLevelAtMost) {
  std::mt19937_64 random(5);
  for (int trial = 0; trial < 4; ++trial) {
    SyntheticMap map = fine_map();
    map.lattice.levels[0] = range(30, 72, 2);
    map.lattice.levels[2] = range(0.2, 1.0, 0.1);
    if (trial % 2) map.lattice.levels[3] = {1.6, 2.2, 2.8};
    std::uniform_real_distribution<double> slope(0.002, 0.006), base(0.45, 0.7);
    const double a = base(random), b = slope(random);
    map.avoid_ttc = [a, b](double v, double mu, double passage, double) {
      return a + b * v / mu - 0.1 * (passage - 2.2);
    };
    const std::array<Result, 2> results = searched_and_predicted(map);
    EXPECT_EQ(compare(map, results[0]).differ, 0U) << "trial " << trial;
    const Comparison c = compare(map, results[1]);
    EXPECT_LT(results[1].simulated, results[0].simulated) << "trial " << trial;
    EXPECT_LE(static_cast<double>(c.differ), 0.01 * static_cast<double>(c.feasible)) << "trial " << trial;
    EXPECT_EQ(c.g_wrong, 0U) << "trial " << trial;
    for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {
      if (!map.feasible(cell) || results[1].cells[cell].region == map.truth(cell)) continue;
      const auto f = map.factors(cell);
      const double step = 0.06;
      EXPECT_LT(std::abs(f[1] - map.avoid_ttc(f[0], f[2], f[3], f[4])), step + 1e-9)
          << "trial " << trial << " cell " << cell;
      EXPECT_TRUE(results[1].cells[cell].region == Region::kY || map.truth(cell) == Region::kY) << cell;
    }
  }
}

// Where the O/R label changes along TTC at a level that moves with speed, neighbouring lines differ
// at one level or two: boxes whose corners change alike (the same runs, each change within a level
// of the others) give the lines between them their runs, each change found by its own simulation.
TEST(AdaptiveSearch, LinesBetweenCornersWhoseLabelsChangeAlikeFindTheirOwnChange) {
  SyntheticMap map = fine_map();
  map.unavoidable = [](double v, double ttc, double) {
    return ttc >= 0.3 + 0.004 * (v - 30.0) ? Region::kO : Region::kR;
  };
  MapOracle oracle(map);
  const Result result = search(map.lattice, oracle, Options{});
  const Comparison c = compare(map, result);
  EXPECT_EQ(c.differ, 0U);
  EXPECT_TRUE(result.violations.empty());
  EXPECT_GT(result.simulated_for[static_cast<std::size_t>(Purpose::kLabelBrackets)], 0U);
  EXPECT_LT(static_cast<double>(result.simulated), 0.2 * static_cast<double>(c.feasible));
}

// From three factors on, a line between corners whose early runs end alike below the stop's run
// takes the end they predict instead of walking up to it (the walk ends at a cell that cannot
// avoid: a dear simulation). Its G part is still its own search, so G stays exact; the avoiding
// cells above it that it infers name the corners they came from.
TEST(AdaptiveSearch, PredictedEarlyRunsKeepTheStopExact) {
  SyntheticMap map;
  map.lattice.levels = {range(30, 72, 2), range(0.25, 2.95, 0.06), range(0.3, 1.0, 0.1), {2.2, 2.8}, {20.0}};
  map.avoid_ttc = [](double v, double mu, double passage, double) {
    return 0.7 + 0.004 * v / mu - 0.1 * (passage - 2.2);
  };
  map.early_g_ttc = [](double v, double mu) { return 0.2 + 4.0 / v + 0.05 * mu; };
  map.early_ttc = [](double v, double mu) { return 0.35 + 4.0 / v + 0.1 * mu; };
  Result results[2];
  for (int predict = 0; predict < 2; ++predict) {
    Options options;
    options.predict_early = predict == 1;
    MapOracle oracle(map);
    results[predict] = search(map.lattice, oracle, options);
    EXPECT_EQ(results[predict].simulated, oracle.total());
  }
  const Comparison walked = compare(map, results[0]), predicted = compare(map, results[1]);
  EXPECT_EQ(walked.g_wrong, 0U);
  EXPECT_EQ(predicted.g_wrong, 0U);
  EXPECT_LT(results[1].simulated, results[0].simulated);
  EXPECT_LE(static_cast<double>(predicted.differ), 0.01 * static_cast<double>(predicted.feasible));
  std::size_t inferred_early = 0;
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {
    const Cell& c = results[1].cells[cell];
    const auto f = map.factors(cell);
    if (c.method != Method::kBox || f[1] >= map.early_ttc(f[0], f[2])) continue;
    ++inferred_early;
    ASSERT_FALSE(c.from.empty()) << cell;
    for (const auto from : c.from) EXPECT_EQ(results[1].cells[from].method, Method::kSimulated) << cell;
  }
  EXPECT_GT(inferred_early, 0U);
}

// From four factors on, a line between corners whose O/R labels change alike (each change within a
// level of the others') takes the change they predict without simulating it, as it does its
// avoidance threshold; with brackets searched each such line simulates its own change. Where the
// predictions miss, they miss by one level, next to the boundary.
TEST(AdaptiveSearch, FromFourFactorsLabelChangesArePredictedToo) {
  SyntheticMap map = fine_map();
  map.lattice.levels[0] = range(30, 72, 2);
  map.lattice.levels[2] = range(0.2, 1.0, 0.1);
  map.lattice.levels[3] = {1.6, 2.2, 2.8};
  map.avoid_ttc = [](double v, double mu, double passage, double) {
    return 0.55 + 0.003 * v / mu - 0.1 * (passage - 2.2);
  };
  map.unavoidable = [](double v, double ttc, double) {
    return ttc >= 0.3 + 0.004 * (v - 30.0) ? Region::kO : Region::kR;
  };
  const std::array<Result, 2> results = searched_and_predicted(map);
  const auto label_brackets = [](const Result& r) {
    return r.simulated_for[static_cast<std::size_t>(Purpose::kLabelBrackets)];
  };
  EXPECT_GT(label_brackets(results[0]), 0U);
  EXPECT_EQ(label_brackets(results[1]), 0U);
  EXPECT_LT(results[1].simulated, results[0].simulated);
  const Comparison c = compare(map, results[1]);
  EXPECT_EQ(c.g_wrong, 0U);
  EXPECT_EQ(compare(map, results[0]).differ, 0U);
  EXPECT_LE(static_cast<double>(c.differ), 0.02 * static_cast<double>(c.feasible));
  // Where a prediction is wrong, the cell is next to the boundary it missed: the avoidance
  // threshold or the change of labels, within one TTC level.
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {
    if (!map.feasible(cell) || results[1].cells[cell].region == map.truth(cell)) continue;
    const auto f = map.factors(cell);
    const double to_threshold = std::abs(f[1] - map.avoid_ttc(f[0], f[2], f[3], f[4]));
    const double to_change = std::abs(f[1] - (0.3 + 0.004 * (f[0] - 30.0)));
    EXPECT_LT(std::min(to_threshold, to_change), 0.06 + 1e-9) << cell;
  }
}

// A cell that cannot avoid costs a threshold search the strengthened search (1 to 2 s), one that
// avoids a fraction of that: the avoidance threshold is searched from above, so a line whose Y run
// is shorter than six cells spends one simulation of a cell that cannot avoid on it, the cell just
// below its threshold, and a longer one two (bisecting, it spent two on each of these lines).
TEST(AdaptiveSearch, AThresholdSearchSimulatesAboutOneCellThatCannotAvoid) {
  for (const double avoid : {1.0, 0.85, 0.7, 0.55, 0.4}) {
    SyntheticMap map = fine_map();
    map.lattice.levels[0] = {50.0};
    map.lattice.levels[4] = {0.0};
    map.avoid_ttc = [avoid](double, double, double, double) { return avoid; };
    MapOracle oracle(map);
    const Result result = search(map.lattice, oracle, Options{});
    std::size_t dear = 0, y_run = 0;
    for (std::size_t cell = 0; cell < result.cells.size(); ++cell) {
      const Cell& c = result.cells[cell];
      y_run += c.region == Region::kY;
      dear += c.method == Method::kSimulated && static_cast<Purpose>(c.purpose) == Purpose::kThresholdCorners &&
              (c.region == Region::kO || c.region == Region::kR);
    }
    EXPECT_EQ(compare(map, result).differ, 0U) << avoid;
    EXPECT_LE(dear, y_run < 6 ? 1U : 2U) << "Y from TTC " << avoid << " s, " << y_run << " Y cells";
  }
}

// A dip of the avoidance threshold narrower than the first lattice (here near 35 km/h, friction
// aside): the corners around it have no Y cell below the top of their feasible TTCs, so the lines
// between take none, until a later simulation of theirs (an O/R label sample) avoids. That breaks no
// monotonicity along the line: its threshold is searched again between the simulated cells that
// bound it. No violation is reported, no line is simulated in full, and the searched map stays exact.
TEST(AdaptiveSearch, AThresholdALaterSimulationContradictsIsSearchedAgain) {
  for (const double width : {1.5, 3.0}) {
    SyntheticMap map = fine_map();
    map.lattice.levels[0] = range(30, 72, 2);
    map.lattice.levels[2] = {0.3, 0.4, 0.5, 0.6};
    map.lattice.levels[3] = {1.6, 2.2, 2.8};
    map.avoid_ttc = [width](double v, double mu, double passage, double) {
      return 1.6 + 0.2 * mu - 0.05 * passage - 0.8 * std::exp(-std::pow((v - 35.0) / width, 2.0));
    };
    map.unavoidable = [](double v, double ttc, double) {
      return ttc >= 0.3 + 0.004 * (v - 30.0) ? Region::kO : Region::kR;
    };
    const std::array<Result, 2> results = searched_and_predicted(map);
    for (const Result& result : results) {
      EXPECT_TRUE(result.violations.empty()) << width;
      EXPECT_EQ(result.lines_fully_resolved, 0U) << width;
      EXPECT_EQ(compare(map, result).g_wrong, 0U) << width;
    }
    EXPECT_EQ(compare(map, results[0]).differ, 0U) << width;
    const Comparison c = compare(map, results[1]);
    EXPECT_LE(static_cast<double>(c.differ), 0.02 * static_cast<double>(c.feasible)) << width;
  }
}

// Where the oracle says there is nothing to mitigate (the crash of doing nothing is already graded
// the lowest a crash can be), the unavoidable cells are R without sampling their labels: the same
// map from fewer simulations. Where the rule is wrong (an O it calls R), the map follows the rule and
// the verification sample is what finds it.
TEST(AdaptiveSearch, CellsWithNothingToMitigateAreRWithoutASimulation) {
  SyntheticMap map = fine_map();
  map.unavoidable = [](double v, double ttc, double) { return v > 50.0 && ttc > 0.4 ? Region::kO : Region::kR; };
  Result results[2];
  for (int rule = 0; rule < 2; ++rule) {
    SyntheticMap m = map;
    if (rule) m.nothing_to_mitigate = [](double v, double) { return v <= 50.0; };
    MapOracle oracle(m);
    results[rule] = search(m.lattice, oracle, Options{});
    EXPECT_EQ(compare(m, results[rule]).differ, 0U) << rule;
  }
  EXPECT_LT(results[1].simulated_for[static_cast<std::size_t>(Purpose::kLabels)],
            results[0].simulated_for[static_cast<std::size_t>(Purpose::kLabels)]);
  EXPECT_LT(results[1].simulated, results[0].simulated);
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {  // every inferred R still names its grounds
    const Cell& c = results[1].cells[cell];
    if (c.method == Method::kLine || c.method == Method::kBox) {
      ASSERT_FALSE(c.from.empty()) << cell;
      for (const auto from : c.from) EXPECT_EQ(results[1].cells[from].method, Method::kSimulated) << cell;
    }
  }
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {  // no label sampled where the rule holds
    const Cell& c = results[1].cells[cell];
    if (map.factors(cell)[0] <= 50.0 && c.method == Method::kSimulated) {
      EXPECT_NE(c.purpose, static_cast<std::uint8_t>(Purpose::kLabels)) << cell;
    }
  }

  SyntheticMap wrong = map;
  wrong.nothing_to_mitigate = [](double, double) { return true; };  // says R where the map has O
  MapOracle oracle(wrong);
  Options options;
  options.verify_sample = 300;
  const Result result = search(wrong.lattice, oracle, options);
  const Comparison c = compare(wrong, result);
  EXPECT_GT(c.differ, 0U);
  EXPECT_EQ(c.g_wrong, 0U);
  EXPECT_FALSE(result.verify_disagreements.empty());
}

TEST(AdaptiveSearch, RefusesSettingsItCannotWorkWith) {
  const SyntheticMap map = fine_map();
  MapOracle oracle(map);
  Options options;
  options.initial_levels = 1;
  EXPECT_THROW((void)search(map.lattice, oracle, options), std::invalid_argument);
  options = Options{};
  options.stride = 0;
  EXPECT_THROW((void)search(map.lattice, oracle, options), std::invalid_argument);
  options = Options{};
  options.spread = 0;
  EXPECT_THROW((void)search(map.lattice, oracle, options), std::invalid_argument);
  EXPECT_THROW(check(options), std::invalid_argument);  // what search() checks, before a sweep starts
  EXPECT_NO_THROW(check(Options{}));
  Lattice empty = map.lattice;
  empty.levels[2].clear();
  EXPECT_THROW((void)search(empty, oracle, Options{}), std::invalid_argument);
}

TEST(AdaptiveSearch, NamesItsBracketsBothWays) {
  for (const Brackets b : {Brackets::kAuto, Brackets::kSearch, Brackets::kPredict})
    EXPECT_EQ(brackets_named(brackets_name(b)), b);
  EXPECT_EQ(brackets_name(Options{}.brackets), "auto");
  EXPECT_EQ(brackets_named("predict"), Brackets::kPredict);
  for (const char* other : {"", "Predict", "exact"}) EXPECT_FALSE(brackets_named(other)) << other;
}

}  // namespace adaptive_test
}  // namespace emrm::campaign::adaptive
