#pragma once

// Running a campaign (docs/campaign.md): every cell simulated once, in parallel, streamed into the
// results store; resumable after a crash; shardable across machines.

#include <cstddef>
#include <filesystem>
#include <string>

#include "emrm/campaign/campaign.hpp"

namespace emrm::campaign {

struct SweepOptions {
  std::filesystem::path output_dir;
  int threads = 0;      ///< 0 = all cores
  int shard_index = 1;  ///< 1-based: this run takes the cells whose global position % count == index − 1
  int shard_count = 1;
  bool progress = true;  ///< a progress bar on stderr, only when stderr is a terminal
  std::string unit = "cells";  ///< what the progress bar and messages count ("scenarios" for a planned run)
  /// When set, one JSON line per commit ({"done", "total", "elapsed_s", "eta_s"}), terminal or not.
  std::filesystem::path progress_log;
};

struct SweepSummary {
  std::size_t cells_total = 0;        ///< cells of this shard
  std::size_t cells_done_before = 0;  ///< found in the store and skipped
  std::size_t cells_simulated = 0;
  double seconds = 0.0;
};

/// "K/N" → (K, N). Throws UsageError unless 1 <= K <= N.
void parse_shard(const std::string& text, int& index, int& count);

/// Simulates the cells of `campaign` (of this shard) that OUTPUT_DIR/results.sqlite does not
/// hold yet, committing a transaction about every 0.5 s or 64 cells, then writes
/// OUTPUT_DIR/regions.csv, cells.csv and cells.json from the store. Results do not depend on the
/// thread count. Throws core::ConfigError (an InputError) for a campaign validate(campaign, true)
/// rejects (max_cells is not applied: the cells are already expanded); UsageError (exit 2) when
/// the store holds another configuration or shard, or the shard is invalid; emrm::Error when the
/// store cannot be written; core::Interrupted after an interrupt (core/interrupt.hpp), once the
/// cells in flight are stored.
SweepSummary sweep(const Campaign& campaign, const SweepOptions& options);

}  // namespace emrm::campaign
