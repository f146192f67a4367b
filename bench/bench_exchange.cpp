// Benchmarks of the exchange module (docs/openscenario.md): `emrm assess` on a long recorded
// trajectory (target ≥ 100 000 samples per second, reading the CSV included), and the export of a
// cell with its executed trajectory.
// Run: ./build/dev/bench/emrm_bench --benchmark_filter=Assess

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "emrm/exchange/assess.hpp"
#include "emrm/exchange/opendrive.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/exchange/plan_export.hpp"

namespace {

namespace exchange = emrm::exchange;
namespace sim = emrm::sim;

// A recording at 100 Hz of a car weaving gently through the passage beside the truck and on down
// the road, then braking to a stop: every sample is judged (no contact ends it early), and the
// samples near the truck pay for the full contact test.
std::string recording(std::size_t samples) {
  std::string csv = "t,x,y,psi,v\n";
  const double dt = 0.01;
  double x = -2.0;
  double v = 12.0;
  for (std::size_t k = 0; k < samples; ++k) {
    const double t = static_cast<double>(k) * dt;
    const double y = -3.6 + 0.2 * std::sin(0.5 * t);
    const double psi = std::atan2(0.2 * 0.5 * std::cos(0.5 * t), 12.0);  // the weave's slope at the cruising speed
    csv += fmt::format("{},{},{},{},{}\n", t, x, y, psi, v);
    x += v * dt;
    if (k + 200 >= samples) v = std::max(0.0, v - 0.06);
  }
  return csv;
}

void BM_AssessTrajectory(benchmark::State& state) {
  const sim::SceneConfig config;
  const sim::CellInput cell{43.2, 1.0, 1.0, 3.0, 10.0};
  const auto samples = static_cast<std::size_t>(state.range(0));
  const std::string csv = recording(samples);
  for (auto _ : state) {
    const auto trajectory = exchange::parse_trajectory_csv(csv, "bench.csv", exchange::TrajectoryFormat::kEmrm, config);
    const exchange::Assessment a = exchange::assess(config, cell, trajectory);
    benchmark::DoNotOptimize(a);
    if (a.contact || a.road_departure) state.SkipWithError("the recording should not touch anything");
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(samples));
}
BENCHMARK(BM_AssessTrajectory)->Arg(1000)->Arg(20000)->Unit(benchmark::kMillisecond);

void BM_ExportCellWithTrajectory(benchmark::State& state) {
  const sim::SceneConfig config;
  const sim::CellInput cell{50.0, 1.2, 0.8, 3.0, 10.0};
  std::vector<sim::PathPoint> path;
  for (int k = 0; k <= 300; ++k) {
    sim::PathPoint p;
    p.t_s = 0.01 * k;
    p.state.x_m = -2.12 + 13.0 * p.t_s;
    p.state.y_m = -1.75 - 0.3 * p.t_s;
    p.state.vx_mps = 13.0;
    path.push_back(p);
  }
  const exchange::EgoTrajectory trajectory{"dodge", path};
  for (auto _ : state) {
    std::string xodr = exchange::opendrive_xml(config, cell);
    std::string xosc = exchange::openscenario_xml(config, cell, &trajectory, {});
    benchmark::DoNotOptimize(xodr);
    benchmark::DoNotOptimize(xosc);
  }
}
BENCHMARK(BM_ExportCellWithTrajectory)->Unit(benchmark::kMicrosecond);

// A plan of 400 scenarios (the shipped plan has 378) exported as one logical scenario, its
// distribution and every road network, written to a temporary folder (target: ≤ 2 s).
void BM_ExportPlan(benchmark::State& state) {
  const sim::SceneConfig config;
  emrm::scenario::ScenarioFile plan;
  plan.file = "scenarios.csv";
  plan.factors = {"speed_kph", "ttc_s", "mu", "passage_m", "truck_speed_kph"};
  for (int k = 0; k < 400; ++k) {
    const double v = 20.0 + (k % 11) * 5.0;
    const double ttc = std::min(0.2 + (k % 13) * 0.15, 0.99 * config.max_initial_distance_m / (v / 3.6));
    plan.rows.push_back({fmt::format("S{:03}", k),
                         "pairs",
                         {v, ttc, 0.3 + (k % 7) * 0.1, 1.5 + (k % 5) * 0.5, 5.0 + (k % 3) * 5.0},
                         "c",
                         {},
                         {},
                         1.0,
                         1,
                         {"scenarios.csv", k + 2, 1}});
  }
  const auto dir = std::filesystem::temp_directory_path() / "emrm-bench-export-plan";
  for (auto _ : state) {
    const auto out = exchange::export_plan(dir, config, plan, {});
    benchmark::DoNotOptimize(out);
  }
  std::filesystem::remove_all(dir);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(plan.rows.size()));
}
BENCHMARK(BM_ExportPlan)->Unit(benchmark::kMillisecond);

}  // namespace
