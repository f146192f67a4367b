// Benchmarks of the analysis layer: loading and checking a safety case, and stepping FSMs.
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench

#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>

#include "emrm/fsm/load.hpp"
#include "emrm/safety/checks.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/safety/traceability.hpp"

namespace {

std::string read(const std::string& name) {
  std::ifstream in(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/" + name);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void BM_SafetyCaseLoad(benchmark::State& state) {
  const std::string text = read("safety.yaml");
  for (auto _ : state) benchmark::DoNotOptimize(emrm::safety::parse_safety_case(text, "safety.yaml"));
}
BENCHMARK(BM_SafetyCaseLoad);

void BM_SafetyCaseCheckAndTrace(benchmark::State& state) {
  const auto sc = emrm::safety::parse_safety_case(read("safety.yaml"), "safety.yaml");
  for (auto _ : state) {
    auto findings = emrm::safety::check(sc);
    auto rows = emrm::safety::traceability_matrix(sc);
    benchmark::DoNotOptimize(findings);
    benchmark::DoNotOptimize(rows);
  }
}
BENCHMARK(BM_SafetyCaseCheckAndTrace);

// A UCA region is evaluated once per scenario by scenario generation: this is its unit cost.
void BM_RegionEvaluation(benchmark::State& state) {
  const auto sc = emrm::safety::parse_safety_case(read("safety.yaml"), "safety.yaml");
  const auto& region = *sc.ucas[0].region_expression;
  std::vector<double> values{50, 10, 0.8, 0.7, 3.0};
  for (auto _ : state) {
    values[2] += 1e-9;
    benchmark::DoNotOptimize(region.holds(values));
  }
}
BENCHMARK(BM_RegionEvaluation);

// The simulator steps the EMRM FSM once per event of every simulated cell.
void BM_FsmStepThroughTrace(benchmark::State& state) {
  const auto g = emrm::fsm::parse_generator(read("emrm_fsm.yaml"), "emrm_fsm.yaml");
  const std::vector<std::string> word{"hazard_detected",        "high_risk", "execute_maneuver", "timeout_error",
                                      "post_incident_response", "safe"};
  const auto initial = *g.initial();
  for (auto _ : state) benchmark::DoNotOptimize(g.run(initial, word));
}
BENCHMARK(BM_FsmStepThroughTrace);

}  // namespace
