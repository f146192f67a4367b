#include "emrm/campaign/distribute.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"

namespace emrm::campaign {
namespace distribute_test {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("emrm-distribute-test-" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  return dir;
}

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Infeasible, green and dear cells, so that both sides get some of each class.
Campaign mixed_campaign() {
  return parse_campaign("seed: 3\ngrids:\n  - name: m\n    speed_kph: [30, 50, 72]\n    ttc_s: [0.5, 1.0, 2.9]\n",
                        "mixed.yaml", ".");
}

// Another process as a test sees it: takes cells from the queue as fast as it can, simulates them here,
// and delivers each late (after the next one), as records come back over a network.
class AnotherProcess final : public Distributor {
 public:
  void distribute(TaskQueue& queue) override {
    std::optional<CellRecord> held;
    int held_cost = 0;
    while (const auto task = queue.next()) {
      ++taken;
      CellRecord record = simulate_task(campaign, *task);
      if (held) queue.deliver(std::move(*held), held_cost, 0.001);
      held = std::move(record);
      held_cost = task->cost;
    }
    if (held) queue.deliver(std::move(*held), held_cost, 0.001);
  }
  Campaign campaign = mixed_campaign();
  int taken = 0;
};

TEST(Distributor, CellsSimulatedElsewhereGiveTheExportsOfOneProcess) {
  const Campaign campaign = mixed_campaign();
  SweepOptions alone;
  alone.output_dir = scratch("alone");
  alone.threads = 1;
  alone.progress = false;
  sweep(campaign, alone);

  AnotherProcess elsewhere;
  SweepOptions shared = alone;
  shared.output_dir = scratch("shared");
  shared.distributor = &elsewhere;
  const SweepSummary summary = sweep(campaign, shared);
  EXPECT_GT(elsewhere.taken, 0);
  EXPECT_EQ(summary.cells_simulated, 9u);  // the distributor's cells count as simulated
  EXPECT_EQ(ResultStore::open_for_reading(shared.output_dir / "results.sqlite").cell_count(), 9);
  for (const char* file : {"regions.csv", "cells.csv", "cells.json"})
    EXPECT_EQ(text_of(shared.output_dir / file), text_of(alone.output_dir / file)) << file;
}

TEST(Distributor, IsRefusedForAnAdaptiveSweep) {
  AnotherProcess elsewhere;
  SweepOptions options;
  options.output_dir = scratch("adaptive");
  options.progress = false;
  options.adaptive = true;
  options.distributor = &elsewhere;
  EXPECT_THROW(sweep(elsewhere.campaign, options), UsageError);
  EXPECT_FALSE(fs::exists(options.output_dir / "results.sqlite"));
}

}  // namespace distribute_test
}  // namespace emrm::campaign
