// The adaptive search tests' shared parts: a synthetic map with the real one's structure, its
// oracle, and the comparison of a search with the map.

#pragma once

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

#include "emrm/campaign/adaptive.hpp"
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

inline std::vector<double> range(double from, double to, double step) {
  std::vector<double> v;
  for (double x = from; x <= to + 1e-9; x += step) v.push_back(std::round(x * 1e9) / 1e9);
  return v;
}

// The paper's fine grid shape: 43 speeds x 46 TTCs.
inline SyntheticMap fine_map() {
  SyntheticMap map;
  map.lattice.levels = {range(30, 72, 1), range(0.25, 2.95, 0.06), {1.0}, {3.0}, {10.0}};
  map.avoid_ttc = [](double v, double mu, double, double) { return 0.6 + 0.004 * v / mu; };
  return map;
}

struct Comparison {
  std::size_t differ = 0, g_wrong = 0, feasible = 0;
};

inline Comparison compare(const SyntheticMap& map, const Result& result) {
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

}  // namespace adaptive_test
}  // namespace emrm::campaign::adaptive
