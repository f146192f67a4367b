#include "emrm/campaign/adaptive.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>

#include "emrm/sim/simulate.hpp"
#include "test_scale.hpp"

namespace emrm::campaign::adaptive {
namespace adaptive_test {

using sim::Region;

// A synthetic map over (speed, TTC, mu, passage, truck speed) with the structure of the real one:
// infeasible beyond a distance, G above an analytic stop threshold, Y above an avoidance threshold,
// O or R below by a rule of its own; `exceptions` flips chosen cells against that structure.
struct SyntheticMap {
  Lattice lattice;
  double max_distance_m = 24.5;
  std::function<double(double v, double mu, double passage, double truck)> avoid_ttc;  ///< Y from this TTC
  std::function<Region(double v, double ttc, double mu)> unavoidable = [](double v, double, double) {
    return v > 60.0 ? Region::kO : Region::kR;
  };
  std::set<std::size_t> flipped;  ///< unavoidable cells turned into the other unavoidable region
  /// A truck still on its way (truck speed above 0): below these TTCs the car passes in front of it,
  /// G below the first, Y below the second. None when unset.
  std::function<double(double v, double mu)> early_g_ttc, early_ttc;
  /// Where the oracle says an unavoidable cell is R without a simulation (nowhere when unset).
  std::function<bool(double v, double ttc)> nothing_to_mitigate;

  [[nodiscard]] std::array<double, 5> factors(std::size_t cell) const {
    std::array<double, 5> f{};
    for (std::size_t k = 5; k-- > 0;) {
      f[k] = lattice.levels[k][cell % lattice.levels[k].size()];
      cell /= lattice.levels[k].size();
    }
    return f;
  }
  [[nodiscard]] static double stop_ttc(double v_kph, double mu) {
    const double v = v_kph / 3.6;
    return 0.35 + v / (2.0 * mu * 9.81);
  }
  [[nodiscard]] bool passes_early(std::size_t cell) const { return early_ttc && factors(cell)[4] > 0.0; }
  [[nodiscard]] bool feasible(std::size_t cell) const {
    const auto f = factors(cell);
    return f[0] / 3.6 * f[1] <= max_distance_m;
  }
  [[nodiscard]] Region truth(std::size_t cell) const {
    const auto f = factors(cell);
    Region r;
    if (passes_early(cell) && f[1] < early_g_ttc(f[0], f[2]))
      r = Region::kG;
    else if (passes_early(cell) && f[1] < early_ttc(f[0], f[2]))
      r = Region::kY;
    else if (f[1] >= stop_ttc(f[0], f[2]))
      r = Region::kG;
    else if (f[1] >= avoid_ttc(f[0], f[2], f[3], f[4]))
      r = Region::kY;
    else
      r = unavoidable(f[0], f[1], f[2]);
    if (flipped.count(cell) != 0 && (r == Region::kO || r == Region::kR)) r = r == Region::kR ? Region::kO : Region::kR;
    return r;
  }
};

class MapOracle final : public Oracle {
 public:
  explicit MapOracle(const SyntheticMap& map) : map_(map), calls_(map.lattice.size()) {}
  [[nodiscard]] bool feasible(std::size_t cell) const override { return map_.feasible(cell); }
  [[nodiscard]] StopCall stop(std::size_t cell) const override {
    const auto f = map_.factors(cell);
    const double margin = f[0] / 3.6 * (f[1] - SyntheticMap::stop_ttc(f[0], f[2]));
    if (margin > 0.1) return StopCall::kStops;
    // As physics knows it: braking cannot avoid once the truck is in the way when the car gets there.
    const bool arrived = !map_.passes_early(cell) || f[1] >= map_.early_g_ttc(f[0], f[2]) + 0.05;
    return margin < -0.1 && arrived ? StopCall::kCannotStop : StopCall::kUnknown;
  }
  [[nodiscard]] bool passes_early(std::size_t cell) const override { return map_.passes_early(cell); }
  [[nodiscard]] bool nothing_to_mitigate(std::size_t cell) const override {
    const auto f = map_.factors(cell);
    return map_.nothing_to_mitigate && map_.nothing_to_mitigate(f[0], f[1]);
  }
  [[nodiscard]] Region simulate(std::size_t cell) override {
    EXPECT_TRUE(map_.feasible(cell)) << "simulated an infeasible cell " << cell;
    EXPECT_EQ(calls_[cell]++, 0) << "simulated cell " << cell << " twice";
    ++total_;
    return map_.truth(cell);
  }
  [[nodiscard]] std::size_t total() const { return total_.load(); }

 private:
  const SyntheticMap& map_;
  std::vector<std::atomic<int>> calls_;
  std::atomic<std::size_t> total_{0};
};

std::vector<double> range(double from, double to, double step) {
  std::vector<double> v;
  for (double x = from; x <= to + 1e-9; x += step) v.push_back(std::round(x * 1e9) / 1e9);
  return v;
}

// The paper's fine grid shape: 43 speeds x 46 TTCs.
SyntheticMap fine_map() {
  SyntheticMap map;
  map.lattice.levels = {range(30, 72, 1), range(0.25, 2.95, 0.06), {1.0}, {3.0}, {10.0}};
  map.avoid_ttc = [](double v, double mu, double, double) { return 0.6 + 0.004 * v / mu; };
  return map;
}

struct Comparison {
  std::size_t differ = 0, g_wrong = 0, feasible = 0;
};

Comparison compare(const SyntheticMap& map, const Result& result) {
  Comparison c;
  for (std::size_t cell = 0; cell < map.lattice.size(); ++cell) {
    if (!map.feasible(cell)) {
      EXPECT_EQ(result.cells[cell].method, Method::kNone);
      continue;
    }
    ++c.feasible;
    const Region truth = map.truth(cell);
    c.differ += result.cells[cell].region != truth;
    c.g_wrong += (result.cells[cell].region == Region::kG) != (truth == Region::kG);
  }
  return c;
}

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
  for (const auto& levels : std::vector<std::array<std::vector<double>, 5>>{
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
  Lattice empty = map.lattice;
  empty.levels[2].clear();
  EXPECT_THROW((void)search(empty, oracle, Options{}), std::invalid_argument);
}

}  // namespace adaptive_test
}  // namespace emrm::campaign::adaptive
