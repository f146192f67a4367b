#include "emrm/campaign/distribute.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "emrm/campaign/store.hpp"
#include "emrm/campaign/sweep.hpp"
#include "scratch.hpp"

namespace emrm::campaign {
namespace distribute_test {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return test::scratch_dir("distribute-test", name); }

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
// and delivers each late (after the next one, or once no cell waits), as records come back over a
// network; waits for more while the queue is open (an adaptive search asks as it goes).
class AnotherProcess final : public Distributor {
 public:
  void distribute(const Campaign& given, TaskQueue& queue) override {
    EXPECT_EQ(config_hash(given), config_hash(campaign));
    std::optional<CellRecord> held;
    int held_cost = 0;
    for (;;) {
      const auto task = queue.next();
      if (!task) {
        if (held) queue.deliver(std::move(*held), held_cost, 0.001);
        held.reset();
        if (!queue.open()) break;
        std::this_thread::yield();
        continue;
      }
      ++taken;
      CellRecord record = simulate_task(given, *task);
      if (held) queue.deliver(std::move(*held), held_cost, 0.001);
      held = std::move(record);
      held_cost = task->cost;
    }
  }
  [[nodiscard]] int threads() const noexcept override { return 1; }
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

// The search asks for each simulation as it goes; cells simulated by the other process give the
// same map, the same decisions and the same store as the search alone.
TEST(Distributor, AnAdaptiveSearchsCellsSimulatedElsewhereGiveTheMapOfOneProcess) {
  const Campaign campaign = parse_campaign(
      "seed: 3\ngrids:\n  - name: m\n    speed_kph: {from: 30, to: 70, step: 10}\n"
      "    ttc_s: {from: 0.3, to: 2.1, step: 0.2}\n",
      "adaptive.yaml", ".");
  SweepOptions alone;
  alone.output_dir = scratch("adaptive-alone");
  alone.threads = 1;
  alone.progress = false;
  alone.adaptive = true;
  const SweepSummary by_itself = sweep(campaign, alone);

  AnotherProcess elsewhere;
  elsewhere.campaign = campaign;
  SweepOptions shared = alone;
  shared.output_dir = scratch("adaptive-shared");
  shared.distributor = &elsewhere;
  const SweepSummary summary = sweep(campaign, shared);
  EXPECT_GT(elsewhere.taken, 0);
  ASSERT_EQ(summary.adaptive.size(), 1u);
  ASSERT_EQ(by_itself.adaptive.size(), 1u);
  EXPECT_EQ(summary.adaptive[0].json, by_itself.adaptive[0].json);
  EXPECT_LT(summary.cells_simulated, 50u);  // a fraction of the 50 cells: the search, not a full sweep
  for (const char* file : {"regions.csv", "cells.csv", "cells.json"})
    EXPECT_EQ(text_of(shared.output_dir / file), text_of(alone.output_dir / file)) << file;
}

}  // namespace distribute_test
}  // namespace emrm::campaign
