// Benchmarks of whole cells: every strategy at the default planner budget.
// The target: median ≤ 10 ms per cell on the 2-core machine.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
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

// The figure is a median over cells, which Google Benchmark does not give for a set of
// different inputs: each iteration times every feasible cell of the fine grid (43 speeds × 46
// TTCs, mu = 1, every 5th cell) one by one and reports the median and the 90th percentile.
void BM_CellMedianOverFineGrid(benchmark::State& state) {
  const SceneConfig config;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 30; s <= 72; ++s)
    for (int k = 0; k < 46; ++k) {
      const CellInput cell{double(s), 0.25 + 0.06 * k, 1.0, 3.0, 10.0};
      if (emrm::sim::Scene(config, cell).feasible() && i++ % 5 == 0) cells.push_back(cell);
    }
  std::vector<double> ms;
  for (auto _ : state) {
    ms.clear();
    for (const auto& cell : cells) {
      const auto start = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(emrm::sim::simulate_cell(config, cell, {}));
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
  }
  std::sort(ms.begin(), ms.end());
  state.counters["cells"] = static_cast<double>(ms.size());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p90_ms"] = ms[ms.size() * 9 / 10];
}
BENCHMARK(BM_CellMedianOverFineGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
