// Benchmarks of whole cells: every strategy at the default planner budget.
// The target: median ≤ 10 ms per cell on the 2-core machine.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "emrm/sim/simulate.hpp"

namespace {

using emrm::sim::CellInput;
using emrm::sim::SceneConfig;

// One representative cell of each region of the fine grid (mu = 1, passage 3 m).
void run_cell(benchmark::State& state, CellInput cell) {
  const SceneConfig config;
  for (auto _ : state) benchmark::DoNotOptimize(emrm::sim::simulate_cell(config, cell, {}));
}

void BM_CellGreen(benchmark::State& state) { run_cell(state, {50.0, 1.2, 1.0, 3.0, 10.0}); }
void BM_CellYellow(benchmark::State& state) { run_cell(state, {60.0, 0.8, 1.0, 3.0, 10.0}); }
void BM_CellRed(benchmark::State& state) { run_cell(state, {72.0, 0.3, 1.0, 3.0, 10.0}); }
BENCHMARK(BM_CellGreen)->Unit(benchmark::kMillisecond);

// What simulate_cell pays to validate its scene, against the whole green cell above.
void BM_SceneValidate(benchmark::State& state) {
  const SceneConfig config;
  for (auto _ : state) emrm::sim::validate(config);
}
BENCHMARK(BM_SceneValidate)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CellYellow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CellRed)->Unit(benchmark::kMillisecond);

// Times each cell once, one by one, and reports the median and the 90th percentile, over all cells
// and over the cells of each region (G, Y, and O or R, these certified or undecided: what a cell
// costs depends most on its region and evidence,
// and grids of two families hold their regions in other shares): Google Benchmark gives no median
// over a set of different inputs.
void time_cells(benchmark::State& state, const SceneConfig& config, const std::vector<CellInput>& cells) {
  std::map<std::string, std::vector<double>> ms;
  std::map<std::string, double> rollouts;
  for (auto _ : state) {
    ms.clear();
    for (const auto& cell : cells) {
      const auto start = std::chrono::steady_clock::now();
      const auto result = emrm::sim::simulate_cell(config, cell, {});
      const double taken = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      const auto region = result.region;
      const char* group = region == emrm::sim::Region::kG ? "G" : (region == emrm::sim::Region::kY ? "Y" : "OR");
      for (const auto& o : result.strategies)  // the chooser repeats the rollouts of what it chose
        if (o.chosen_strategy.empty()) rollouts[group] += o.planner.rollouts;
      ms["all"].push_back(taken);
      ms[group].push_back(taken);
      // An O or R cell without a certificate runs the strengthened search: dearer than a certified one.
      if (region == emrm::sim::Region::kO || region == emrm::sim::Region::kR)
        ms[result.evidence == emrm::sim::Evidence::kUndecided ? "OR_undecided" : "OR_certified"].push_back(taken);
    }
  }
  for (auto& [group, times] : ms) {
    std::sort(times.begin(), times.end());
    const std::string suffix = group == "all" ? "" : "_" + group;
    state.counters["cells" + suffix] = static_cast<double>(times.size());
    state.counters["median_ms" + suffix] = times[times.size() / 2];
    if (group == "all") state.counters["p90_ms"] = times[times.size() * 9 / 10];
    if (rollouts.count(group)) {
      double total = 0.0;
      for (double t : times) total += t;
      state.counters["rollouts" + suffix] = rollouts[group] / times.size();
      state.counters["us_per_rollout" + suffix] = 1000.0 * total / rollouts[group];
    }
  }
}

// The figure: every feasible cell of the fine grid (43 speeds × 46 TTCs, mu = 1, every 5th
// cell).
void BM_CellMedianOverFineGrid(benchmark::State& state) {
  const SceneConfig config;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 30; s <= 72; ++s)
    for (int k = 0; k < 46; ++k) {
      const CellInput cell{double(s), 0.25 + 0.06 * k, 1.0, 3.0, 10.0};
      if (emrm::sim::Scene(config, cell).feasible() && i++ % 5 == 0) cells.push_back(cell);
    }
  time_cells(state, config, cells);
}
BENCHMARK(BM_CellMedianOverFineGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

// The same for the family highway_obstacle (issue 37: a cell of any family within 2× of a
// T-junction cell): 60–150 km/h × TTC 0.5–2 s on μ 0.8, a truck and a deer, blocking the shoulder
// and the right lane or standing in it, every 3rd cell.
void BM_CellMedianOverHighwayGrid(benchmark::State& state) {
  SceneConfig config;
  config.family = "highway_obstacle";
  config.max_initial_distance_m = 90.0;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 60; s <= 150; s += 10)
    for (int k = 0; k <= 6; ++k)
      for (const double obstacle : {0.0, 1.0})
        for (const double blocked_m : {5.0, 6.25}) {
          const CellInput cell{double(s), 0.5 + 0.25 * k, 0.8, obstacle, blocked_m, 0.0};
          if (emrm::sim::Scene(config, cell).feasible() && i++ % 3 == 0) cells.push_back(cell);
        }
  time_cells(state, config, cells);
}
BENCHMARK(BM_CellMedianOverHighwayGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

// The same for the family pedestrian_crossing: 20–60 km/h × TTC 0.5–2.5 s on a dry road, a walking
// and a running pedestrian, with and without the oncoming car, every 2nd cell.
void BM_CellMedianOverPedestrianGrid(benchmark::State& state) {
  SceneConfig config;
  config.family = "pedestrian_crossing";
  config.max_initial_distance_m = 40.0;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 20; s <= 60; s += 5)
    for (int k = 0; k <= 8; ++k)
      for (const double pedestrian_kph : {5.0, 8.0})
        for (const double oncoming : {0.0, 1.0}) {
          const CellInput cell{double(s), 0.5 + 0.25 * k, 1.0, pedestrian_kph, oncoming};
          if (emrm::sim::Scene(config, cell).feasible() && i++ % 2 == 0) cells.push_back(cell);
        }
  time_cells(state, config, cells);
}
BENCHMARK(BM_CellMedianOverPedestrianGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

// The same for the family cut_in (the road of examples/cut_in/scene.yaml: no hard shoulder; the car
// and its actuators as in the T-junction's grid, instant, so that the two differ in the family
// alone): 60–120 km/h × TTC 0.5–2.5 s on a dry road, a gentle cut-in (20 km/h slower, 1 m/s,
// 4 m/s²) and a sharp one (30 km/h, 2 m/s, 8 m/s²), with and without the overtaking car, every 2nd
// cell.
void BM_CellMedianOverCutInGrid(benchmark::State& state) {
  SceneConfig config = emrm::sim::load_scene_config(EMRM_SOURCE_DIR "/examples/cut_in/scene.yaml");
  config.actuation = SceneConfig{}.actuation;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 60; s <= 120; s += 10)
    for (int k = 0; k <= 8; ++k)
      for (const auto& [relative, lateral, decel] : {std::tuple{20.0, 1.0, 4.0}, std::tuple{30.0, 2.0, 8.0}})
        for (const double following : {0.0, 1.0}) {
          const CellInput cell{double(s), 0.5 + 0.25 * k, 1.0, relative, lateral, decel, following};
          if (emrm::sim::Scene(config, cell).feasible() && i++ % 2 == 0) cells.push_back(cell);
        }
  time_cells(state, config, cells);
}
BENCHMARK(BM_CellMedianOverCutInGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
