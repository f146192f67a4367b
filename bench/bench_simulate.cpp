// Benchmarks of whole cells: every strategy at the default planner budget.
// The target: median ≤ 10 ms per cell on the 2-core machine.

#include <benchmark/benchmark.h>

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
BENCHMARK(BM_CellYellow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CellRed)->Unit(benchmark::kMillisecond);

// The median over a spread of the fine grid: 43 speeds × 46 TTCs, every 7th cell.
void BM_CellFineGridSample(benchmark::State& state) {
  const SceneConfig config;
  std::vector<CellInput> cells;
  int i = 0;
  for (int s = 30; s <= 72; ++s)
    for (int k = 0; k < 46; ++k)
      if (i++ % 7 == 0) cells.push_back({double(s), 0.25 + 0.06 * k, 1.0, 3.0, 10.0});
  std::size_t next = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(emrm::sim::simulate_cell(config, cells[next], {}));
    next = (next + 1) % cells.size();
  }
}
BENCHMARK(BM_CellFineGridSample)->Unit(benchmark::kMillisecond)->Iterations(200);

}  // namespace
