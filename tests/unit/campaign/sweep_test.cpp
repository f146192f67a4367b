#include "emrm/campaign/sweep.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <utility>

#include "emrm/campaign/store.hpp"
#include "scratch.hpp"

namespace emrm::campaign {
namespace sweep_test {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return test::scratch_dir("sweep-test", name); }

// Cheap cells: slow, early hazards (green) and far ones (infeasible, not simulated).
Campaign small_campaign() {
  return parse_campaign(
      "grids:\n  - name: a\n    speed_kph: [30, 35]\n    ttc_s: [2.5, 2.9]\n"
      "  - name: b\n    speed_kph: 72\n    ttc_s: [2.0, 2.5, 2.9]\n",
      "small.yaml", ".");
}

TEST(ParseShard, AcceptsKOfNAndRejectsTheRest) {
  int k = 0;
  int n = 0;
  parse_shard("2/3", k, n);
  EXPECT_EQ(k, 2);
  EXPECT_EQ(n, 3);
  for (const char* bad : {"0/2", "3/2", "x", "1/0", "1/2x", "/2", "1/", "-1/2", ""})
    EXPECT_THROW(parse_shard(bad, k, n), UsageError) << bad;
}

TEST(Sweep, ValidatesACodeBuiltCampaignBeforeOpeningTheStore) {
  Campaign c = small_campaign();
  c.grids[1].cells[2][3] = -1;  // the passage
  SweepOptions options;
  options.output_dir = scratch("invalid");
  options.progress = false;
  try {
    (void)sweep(c, options);
    FAIL() << "expected a ConfigError";
  } catch (const core::ConfigError& e) {
    EXPECT_EQ(e.path().str(), "grids[1].cells[2]");
    EXPECT_THAT(e.message(), ::testing::HasSubstr("campaign: grids[1].cells[2]: grid 'b': passage_m"));
  }
  EXPECT_FALSE(fs::exists(options.output_dir / "results.sqlite"));
  // The cell limit guards loading only: an expanded campaign above it is swept.
  c = small_campaign();
  c.max_cells = 1;
  EXPECT_NO_THROW((void)validate(c, /*force=*/true));
}

TEST(Sweep, StoresEveryCellOnceAndResumesWithNothingToDo) {
  const Campaign c = small_campaign();
  SweepOptions options;
  options.output_dir = scratch("once");
  options.threads = 2;
  const SweepSummary first = sweep(c, options);
  EXPECT_EQ(first.cells_total, 7u);
  EXPECT_EQ(first.cells_simulated, 7u);
  EXPECT_EQ(first.cells_done_before, 0u);
  const auto records = read_results(options.output_dir / "results.sqlite");
  ASSERT_EQ(records.size(), 7u);
  EXPECT_EQ(records[0].grid, "a");
  EXPECT_EQ(records[6].grid, "b");
  EXPECT_EQ(records[6].index, 2);
  for (const auto& r : records) {
    EXPECT_EQ(r.seed, cell_seed(c, r.grid, c.grids[r.grid == "a" ? 0 : 1].cells[static_cast<std::size_t>(r.index)]));
    EXPECT_EQ(r.outcomes.size(), r.feasible ? c.strategies.size() : 0u);
  }
  const SweepSummary second = sweep(c, options);
  EXPECT_EQ(second.cells_simulated, 0u);
  EXPECT_EQ(second.cells_done_before, 7u);
  EXPECT_EQ(read_results(options.output_dir / "results.sqlite").size(), 7u);
}

TEST(Sweep, ShardsPartitionTheCellsByGlobalPosition) {
  const Campaign c = small_campaign();
  std::set<std::pair<std::string, std::int64_t>> seen;
  std::size_t total = 0;
  for (int k = 1; k <= 3; ++k) {
    SweepOptions options;
    options.output_dir = scratch("shard" + std::to_string(k));
    options.threads = 1;
    options.shard_index = k;
    options.shard_count = 3;
    total += sweep(c, options).cells_total;
    for (const auto& r : read_results(options.output_dir / "results.sqlite")) {
      const std::size_t position = (r.grid == "a" ? 0u : 4u) + static_cast<std::size_t>(r.index);
      EXPECT_EQ(position % 3, static_cast<std::size_t>(k - 1));
      EXPECT_TRUE(seen.emplace(r.grid, r.index).second);
    }
  }
  EXPECT_EQ(total, 7u);
  EXPECT_EQ(seen.size(), 7u);
}

TEST(Sweep, RefusesAChangedConfiguration) {
  SweepOptions options;
  options.output_dir = scratch("changed");
  (void)sweep(small_campaign(), options);
  Campaign changed = small_campaign();
  changed.seed = 2;
  EXPECT_THROW((void)sweep(changed, options), UsageError);
}

// The adaptive search's settings reach it whole (SweepOptions::search is copied, not field by
// field), except the verification sample's seed, which the sweep derives per grid.
TEST(Sweep, HandsTheSearchItsOptionsButTheSeed) {
  const Campaign c = parse_campaign(
      "seed: 3\ngrids:\n  - name: m\n    speed_kph: {from: 30, to: 70, step: 10}\n"
      "    ttc_s: {from: 0.3, to: 2.1, step: 0.2}\n",
      "adaptive.yaml", ".");
  const auto adaptive_sweep = [&](const std::string& name, const adaptive::Options& search) {
    SweepOptions options;
    options.output_dir = scratch(name);
    options.threads = 2;
    options.progress = false;
    options.adaptive = true;
    options.search = search;
    const SweepSummary s = sweep(c, options);
    EXPECT_EQ(s.adaptive.size(), 1u);
    return s.adaptive.empty() ? AdaptiveSummary{} : s.adaptive[0];
  };
  const AdaptiveSummary defaults = adaptive_sweep("defaults", SweepOptions{}.search);
  adaptive::Options unverified;
  unverified.verify_sample = 0;
  const AdaptiveSummary without = adaptive_sweep("unverified", unverified);
  EXPECT_GT(defaults.verify_sampled, 0u);
  EXPECT_EQ(without.verify_sampled, 0u);
  EXPECT_LT(without.simulated, defaults.simulated);
  adaptive::Options seeded;
  seeded.seed = 12345;  // not the sweep's: derived from the campaign's seed and the grid
  EXPECT_EQ(adaptive_sweep("seeded", seeded).json, defaults.json);
}

}  // namespace sweep_test
}  // namespace emrm::campaign
