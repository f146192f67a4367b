// Benchmarks of the geometry the simulator calls every step: the separating-axis test (target
// ≤ 20 ns per call), the contact query at an impact, and the truck's closed-form motion.
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench --benchmark_filter=Overlap

#include <benchmark/benchmark.h>

#include <array>
#include <numbers>

#include "emrm/core/geometry.hpp"
#include "emrm/sim/scene.hpp"

namespace {

using emrm::core::OrientedBox;

// A cycle of ego poses around the truck's near corner: some overlap, some do not, all within the
// bounding-circle filter, so every call pays for the full separating-axis test.
std::array<OrientedBox, 64> ego_poses_near(const OrientedBox& truck) {
  std::array<OrientedBox, 64> poses{};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double k = static_cast<double>(i);
    poses[i] = {{truck.center.x - 3.2 + 0.05 * k, truck.center.y - 6.6 + 0.03 * k}, -0.4 + 0.0125 * k, 4.508, 1.61};
  }
  return poses;
}

OrientedBox truck_box() { return {{16.25, 1.0}, -std::numbers::pi / 2, 10.0, 2.5}; }

void BM_OrientedBoxOverlap(benchmark::State& state) {
  const OrientedBox truck = truck_box();
  const auto poses = ego_poses_near(truck);
  std::size_t i = 0;
  std::size_t hits = 0;
  for (auto _ : state) {
    OrientedBox ego = poses[i++ & 63];
    benchmark::DoNotOptimize(ego);  // opaque to the optimiser: no constant folding across calls
    const bool hit = emrm::core::overlaps(ego, truck);
    benchmark::DoNotOptimize(hit);
    hits += hit;
  }
  state.counters["overlap_fraction"] =
      benchmark::Counter(static_cast<double>(hits), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_OrientedBoxOverlap);

// Far apart (the common case along a trajectory): the bounding circles reject without trigonometry.
void BM_OrientedBoxOverlapFar(benchmark::State& state) {
  OrientedBox truck = truck_box();
  OrientedBox ego{{-2.0, -1.75}, 0.0, 4.508, 1.61};
  for (auto _ : state) {
    ego.center.x += 1e-9;
    benchmark::DoNotOptimize(ego);
    benchmark::DoNotOptimize(emrm::core::overlaps(ego, truck));
  }
}
BENCHMARK(BM_OrientedBoxOverlapFar);

void BM_Contact(benchmark::State& state) {
  const OrientedBox truck = truck_box();
  const auto poses = ego_poses_near(truck);
  std::size_t i = 0;
  for (auto _ : state) {
    OrientedBox ego = poses[i++ & 63];
    benchmark::DoNotOptimize(ego);
    benchmark::DoNotOptimize(emrm::core::contact(ego, truck));
  }
}
BENCHMARK(BM_Contact);

void BM_TruckAt(benchmark::State& state) {
  const emrm::sim::SceneConfig config;
  const emrm::sim::Scene scene(config, emrm::sim::CellInput{50.0, 1.2, 1.0, 2.0, 10.0});
  double t = 0.0;
  for (auto _ : state) {
    t = t < 4.0 ? t + 0.01 : 0.0;
    benchmark::DoNotOptimize(t);
    benchmark::DoNotOptimize(scene.hazard_at(t));
  }
}
BENCHMARK(BM_TruckAt);

}  // namespace
