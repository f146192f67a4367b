// Benchmarks of the campaign engine: a 40-cell sweep with 1 and 2 threads, in cells per second.
// The speed-up of Arg(2) over Arg(1) is the load balance the sweep promises (>= 1.8x on 2 cores).
// Run: cmake --workflow --preset bench && ./build/bench/bench/emrm_bench --benchmark_filter=Sweep

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/sweep.hpp"

namespace {

// 40 cells mixing the dear (red, orange: ~130 ms) with the cheap (green, infeasible), weighted
// towards low TTCs so that no handful of dear cells decides the wall time of a 2-thread run.
const char* const kCampaign =
    "seed: 1\n"
    "grids:\n"
    "  - name: bench\n"
    "    speed_kph: {from: 30, to: 72, levels: 5}\n"
    "    ttc_s: [0.25, 0.3, 0.35, 0.4, 0.5, 0.7, 1.0, 1.5]\n";

void BM_Sweep40Cells(benchmark::State& state) {
  const emrm::campaign::Campaign campaign = emrm::campaign::parse_campaign(kCampaign, "bench.yaml", ".");
  const auto dir = std::filesystem::temp_directory_path() / ("emrm-bench-sweep-" + std::to_string(::getpid()));
  emrm::campaign::SweepOptions options;
  options.output_dir = dir;
  options.threads = static_cast<int>(state.range(0));
  options.progress = false;
  std::size_t cells = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::filesystem::remove_all(dir);
    state.ResumeTiming();
    cells += emrm::campaign::sweep(campaign, options).cells_simulated;
  }
  std::filesystem::remove_all(dir);
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Sweep40Cells)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// What sweep() pays once to validate a campaign: the shipped one, every cell through validate_cell.
void BM_CampaignValidate(benchmark::State& state) {
  const auto campaign =
      emrm::campaign::load_campaign(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/campaign.yaml");
  for (auto _ : state) emrm::campaign::validate(campaign, /*force=*/true);
  state.counters["cells"] = static_cast<double>(emrm::campaign::total_cells(campaign));
}
BENCHMARK(BM_CampaignValidate)->Unit(benchmark::kMicrosecond);

}  // namespace
