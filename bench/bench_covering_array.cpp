// Covering-array generation on the reference models of docs/covering-arrays.md; the "rows" counter is the
// array size to compare with the best-known and PICT figures in docs/covering-arrays.md.
// CoveringT*: default options (greedy and post-optimisation); CoveringGreedyT*: greedy only.
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench --benchmark_filter=Covering

#include <benchmark/benchmark.h>

#include <vector>

#include "emrm/scenario/covering_array.hpp"

namespace {

std::vector<int> levels_of(std::initializer_list<std::pair<int, int>> groups) {
  std::vector<int> l;
  for (auto [levels, count] : groups) l.insert(l.end(), static_cast<std::size_t>(count), levels);
  return l;
}

void run(benchmark::State& state, const std::vector<int>& levels, int strength, bool optimise = true) {
  emrm::scenario::CoveringArrayOptions options;
  options.strength = strength;
  if (!optimise) options.improvement_effort = 0.0;
  std::size_t rows = 0;
  for (auto _ : state) {
    auto ca = emrm::scenario::generate_covering_array(levels, options);
    rows = ca.rows.size();
    benchmark::DoNotOptimize(ca);
  }
  state.counters["rows"] = static_cast<double>(rows);
}

void CoveringT2_3pow4(benchmark::State& s) { run(s, levels_of({{3, 4}}), 2); }
void CoveringT2_3pow13(benchmark::State& s) { run(s, levels_of({{3, 13}}), 2); }
void CoveringT2_2pow100(benchmark::State& s) { run(s, levels_of({{2, 100}}), 2); }
void CoveringT2_10pow20(benchmark::State& s) { run(s, levels_of({{10, 20}}), 2); }
void CoveringT2_4pow15_3pow17_2pow29(benchmark::State& s) { run(s, levels_of({{4, 15}, {3, 17}, {2, 29}}), 2); }
void CoveringT2_4pow1_3pow39_2pow35(benchmark::State& s) { run(s, levels_of({{4, 1}, {3, 39}, {2, 35}}), 2); }
void CoveringT3_3pow4(benchmark::State& s) { run(s, levels_of({{3, 4}}), 3); }
void CoveringT3_5pow10(benchmark::State& s) { run(s, levels_of({{5, 10}}), 3); }

void CoveringGreedyT2_3pow13(benchmark::State& s) { run(s, levels_of({{3, 13}}), 2, false); }
void CoveringGreedyT2_2pow100(benchmark::State& s) { run(s, levels_of({{2, 100}}), 2, false); }
void CoveringGreedyT2_10pow20(benchmark::State& s) { run(s, levels_of({{10, 20}}), 2, false); }
void CoveringGreedyT2_4pow15_3pow17_2pow29(benchmark::State& s) {
  run(s, levels_of({{4, 15}, {3, 17}, {2, 29}}), 2, false);
}
void CoveringGreedyT2_4pow1_3pow39_2pow35(benchmark::State& s) {
  run(s, levels_of({{4, 1}, {3, 39}, {2, 35}}), 2, false);
}
void CoveringGreedyT3_5pow10(benchmark::State& s) { run(s, levels_of({{5, 10}}), 3, false); }

}  // namespace

BENCHMARK(CoveringT2_3pow4)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT2_3pow13)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT2_2pow100)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT2_10pow20)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT2_4pow15_3pow17_2pow29)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT2_4pow1_3pow39_2pow35)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT3_3pow4)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringT3_5pow10)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT2_3pow13)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT2_2pow100)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT2_10pow20)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT2_4pow15_3pow17_2pow29)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT2_4pow1_3pow39_2pow35)->Unit(benchmark::kMillisecond);
BENCHMARK(CoveringGreedyT3_5pow10)->Unit(benchmark::kMillisecond);
