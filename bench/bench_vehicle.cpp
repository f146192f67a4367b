// Benchmarks of the vehicle models: one RK4 step is the inner loop of every planner rollout.
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench --benchmark_filter=Step

#include <benchmark/benchmark.h>

#include "emrm/sim/vehicle.hpp"

namespace {

using emrm::sim::Control;
using emrm::sim::KinematicBicycle;
using emrm::sim::SingleTrackFiala;
using emrm::sim::VehicleModel;
using emrm::sim::VehicleParams;
using emrm::sim::VehicleState;

// A cornering, braking state in the dynamic range; the benchmark nudges it every iteration so the
// step cannot be hoisted out of the loop.
VehicleState cornering() {
  VehicleState s;
  s.vx_mps = 18.0;
  s.vy_mps = 0.4;
  s.yaw_rate_radps = 0.3;
  s.yaw_rad = 0.2;
  s.steer_rad = 0.05;
  return s;
}

void step_loop(benchmark::State& state, const VehicleModel& model, const Control& u) {
  const VehicleState start = cornering();
  double nudge = 0.0;
  for (auto _ : state) {
    VehicleState s = start;
    s.vy_mps += nudge;
    nudge = nudge > 1e-3 ? 0.0 : nudge + 1e-7;
    benchmark::DoNotOptimize(s);
    VehicleState next = model.step(s, u, 0.8, 0.01);
    benchmark::DoNotOptimize(next);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_SingleTrackFialaStep(benchmark::State& state) {
  const SingleTrackFiala model{VehicleParams{}};
  step_loop(state, model, {.steer_rate_radps = 0.4, .brake = 0.3, .rear_lock = false});
}
BENCHMARK(BM_SingleTrackFialaStep);

// The drifting branch (locked rear axle) has its own square root.
void BM_SingleTrackFialaStepRearLock(benchmark::State& state) {
  const SingleTrackFiala model{VehicleParams{}};
  step_loop(state, model, {.steer_rate_radps = 0.4, .brake = 0.0, .rear_lock = true});
}
BENCHMARK(BM_SingleTrackFialaStepRearLock);

void BM_KinematicStep(benchmark::State& state) {
  const KinematicBicycle model{VehicleParams{}};
  step_loop(state, model, {.steer_rate_radps = 0.4, .brake = 0.3, .rear_lock = false});
}
BENCHMARK(BM_KinematicStep);

}  // namespace
