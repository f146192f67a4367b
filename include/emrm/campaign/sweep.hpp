#pragma once

// Running a campaign (docs/campaign.md): every cell simulated once, in parallel, streamed into the
// results store; resumable after a crash; shardable across machines.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "emrm/campaign/adaptive.hpp"
#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/exports.hpp"

namespace emrm::campaign {

class Distributor;

struct SweepOptions {
  std::filesystem::path output_dir;
  int threads = 0;      ///< 0 = all cores
  int shard_index = 1;  ///< 1-based: this run takes the cells whose global position % count == index − 1
  int shard_count = 1;
  bool progress = true;        ///< a progress bar on stderr, only when stderr is a terminal
  std::string unit = "cells";  ///< what the progress bar and messages count ("scenarios" for a planned run)
  /// When set, one JSON line per commit ({"done", "total", "elapsed_s", "eta_s"}), terminal or not.
  std::filesystem::path progress_log;
  /// Sweep every product grid by the adaptive boundary search (docs/adaptive.md), not only those
  /// with `adaptive: true`. Not with shards.
  bool adaptive = false;
  /// The search's settings (adaptive.hpp), for every grid swept adaptively; the sweep sets only the
  /// seed of each grid's verification sample (from the campaign's seed and the grid's name).
  adaptive::Options search;
  /// Other processes that simulate cells beside this one's threads (distribute.hpp; the MPI ranks
  /// of cluster/mpi_sweep.hpp); borrowed. Null: this process alone.
  Distributor* distributor = nullptr;
};

/// What the adaptive search of one grid did (also stored, as JSON, in the store's adaptive table).
struct AdaptiveSummary {
  std::string grid;
  std::size_t feasible = 0;   ///< M: the grid's feasible cells
  std::size_t simulated = 0;  ///< N: simulated for this map, now or before a resume, verification included
  std::size_t inferred = 0;   ///< of them by the analytic stop boundary: inferred_stop
  std::size_t inferred_stop = 0;
  std::size_t rounds = 0;
  std::size_t lines = 0, lines_resolved = 0, lines_inferred = 0, lines_fully_resolved = 0;
  std::size_t violations = 0;  ///< monotonicity violations found (each resolved in full around it)
  std::size_t verify_population = 0, verify_sampled = 0, verify_disagreements = 0;
  double disagreement_low = 0.0, disagreement_high = 1.0;  ///< Wilson 95 % interval of the rate
  std::string json;                                        ///< the whole summary, as stored
};

struct SweepSummary {
  std::size_t cells_total = 0;        ///< cells of this shard
  std::size_t cells_done_before = 0;  ///< found in the store and skipped
  std::size_t cells_simulated = 0;
  double seconds = 0.0;
  double simulation_seconds = 0.0;        ///< thread-seconds this process's threads spent simulating cells
  std::vector<AdaptiveSummary> adaptive;  ///< one per grid swept adaptively, in grid order
  std::vector<GridCount> grids;           ///< every grid's cells and feasible cells in the store
};

/// "K/N" → (K, N). Throws UsageError unless 1 <= K <= N.
void parse_shard(const std::string& text, int& index, int& count);

/// Simulates the cells of `campaign` (of this shard) that OUTPUT_DIR/results.sqlite does not
/// hold yet (for a grid swept adaptively: those the search asks for, then stores the others as
/// inferred, replacing the inferred cells of an earlier run), committing a transaction about every 0.5 s or 64 cells,
/// then writes OUTPUT_DIR/regions.csv, cells.csv and cells.json from the store. Results do not depend on the thread
/// count. Throws core::ConfigError (an InputError) for a campaign validate(campaign, true) rejects (max_cells is not
/// applied: the cells are already expanded); UsageError (exit 2) when the store holds another configuration or shard,
/// the shard is invalid, or an adaptive sweep is sharded; emrm::Error when the store cannot be written;
/// core::Interrupted after an interrupt (core/interrupt.hpp), once the cells in flight are stored.
SweepSummary sweep(const Campaign& campaign, const SweepOptions& options);

}  // namespace emrm::campaign
