// Benchmarks of the minimum scenario set: loading the shipped ODD (with its safety case), building
// the plan, and the independent coverage check with the three baselines.
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench --benchmark_filter=Plan

#include <benchmark/benchmark.h>

#include <string>

#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/plan.hpp"
#include "emrm/scenario/plan_io.hpp"

namespace {

const std::string kOdd = std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/odd.yaml";

void BM_PlanLoadOdd(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(emrm::scenario::load_odd(kOdd));
}
BENCHMARK(BM_PlanLoadOdd)->Unit(benchmark::kMillisecond);

void BM_PlanBuild(benchmark::State& state) {
  const auto odd = emrm::scenario::load_odd(kOdd);
  std::size_t size = 0;
  for (auto _ : state) {
    const auto plan = emrm::scenario::build_plan(odd);
    size = plan.scenarios.size();
    benchmark::DoNotOptimize(plan);
  }
  state.counters["scenarios"] = static_cast<double>(size);
}
BENCHMARK(BM_PlanBuild)->Unit(benchmark::kMillisecond);

void BM_PlanCoverageCheckWithBaselines(benchmark::State& state) {
  const auto odd = emrm::scenario::load_odd(kOdd);
  const auto plan = emrm::scenario::build_plan(odd);
  for (auto _ : state) benchmark::DoNotOptimize(emrm::scenario::coverage_comparison(odd, plan));
}
BENCHMARK(BM_PlanCoverageCheckWithBaselines)->Unit(benchmark::kMillisecond);

}  // namespace
