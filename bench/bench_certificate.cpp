// The unavoidability certificate (docs/physics.md, "Unavoidability certificates"): what a sweep
// pays per cell to try it before any search. The target: about a millisecond per call, well under
// what a search costs (tens of milliseconds).

#include <benchmark/benchmark.h>

#include <vector>

#include "emrm/sim/certificate.hpp"

namespace {

using emrm::sim::CellInput;
using emrm::sim::Scene;
using emrm::sim::SceneConfig;

// Every feasible cell of the fine grid (speed 30–72 km/h × TTC 0.25–2.95 s, mu 1, passage 3 m),
// one call per iteration in turn: the mean over a sweep's mix of certified, uncertified and
// quickly rejected cells.
void certify_fine_grid(benchmark::State& state, const emrm::sim::ActuationConfig& actuation) {
  SceneConfig config;
  config.actuation = actuation;
  std::vector<CellInput> cells;
  for (int s = 30; s <= 72; ++s)
    for (int k = 0; k < 46; ++k) {
      const CellInput cell{double(s), 0.25 + 0.06 * k, 1.0, 3.0, 10.0};
      if (Scene(config, cell).feasible()) cells.push_back(cell);
    }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(emrm::sim::certify_unavoidable(Scene(config, cells[i])));
    i = (i + 1) % cells.size();
  }
  state.counters["cells"] = static_cast<double>(cells.size());
}

void BM_Certify(benchmark::State& state) { certify_fine_grid(state, {}); }
void BM_CertifyLatency(benchmark::State& state) { certify_fine_grid(state, {.perception_latency_s = 0.25}); }
// The shipped scene's actuators (examples/tjunction/profiles/production.yaml).
void BM_CertifyProduction(benchmark::State& state) {
  certify_fine_grid(state, {.perception_latency_s = 0.25,
                            .brake_dead_time_s = 0.1,
                            .brake_ramp_s = 0.25,
                            .max_decel_mps2 = 0.0,
                            .steer_dead_time_s = 0.05,
                            .steer_time_constant_s = 0.1});
}
BENCHMARK(BM_Certify)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CertifyLatency)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CertifyProduction)->Unit(benchmark::kMicrosecond);

// The slowest kind of cell: low friction, so the arrival windows span the whole 3 s horizon and
// every witness is tried (no certificate).
void BM_CertifyLowFriction(benchmark::State& state) {
  const SceneConfig config;
  const Scene scene(config, {84.0, 1.3, 0.12, 5.0, 26.5});
  for (auto _ : state) benchmark::DoNotOptimize(emrm::sim::certify_unavoidable(scene));
}
BENCHMARK(BM_CertifyLowFriction)->Unit(benchmark::kMicrosecond);

// The checker re-evaluates one witness at half the step and with a dense set of multipliers.
void BM_CheckCertificate(benchmark::State& state) {
  const SceneConfig config;
  const Scene scene(config, {72.0, 0.3, 1.0, 3.0, 10.0});
  const auto cert = emrm::sim::certify_unavoidable(scene);
  if (!cert) {
    state.SkipWithError("no certificate for the benchmark's cell");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(emrm::sim::check_certificate(scene, *cert));
}
BENCHMARK(BM_CheckCertificate)->Unit(benchmark::kMicrosecond);

}  // namespace
