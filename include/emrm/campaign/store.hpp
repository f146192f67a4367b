#pragma once

// The results store of a campaign (docs/campaign.md, "Store"): one SQLite file, DIR/results.sqlite,
// in WAL mode, written one transaction per batch so that a killed sweep loses at most the batch
// in flight and a rerun resumes. Readers stream rows from it; nothing holds all results at once.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/records.hpp"

struct sqlite3;

namespace emrm::campaign {

/// The store's file in a results folder (results::ResultsDir names the folder's other files).
inline constexpr std::string_view kStoreFile = "results.sqlite";

/// Version of the store's tables; a store of another version is refused.
inline constexpr int kStoreSchemaVersion = 4;

/// What a store says about the campaign that filled it.
struct CampaignMeta {
  std::string config_hash;
  std::string emrm_version;
  std::string campaign_yaml;  ///< the campaign file's text
  std::string scene_yaml;     ///< the effective scene
  std::uint64_t seed = 1;
  std::vector<std::string> strategies;
  std::vector<std::string> grids;  ///< in campaign order
  int shard_index = 1;
  int shard_count = 1;
};

/// The metadata a sweep of `campaign` writes (shard 1/1 unless changed).
[[nodiscard]] CampaignMeta make_meta(const Campaign& campaign);
/// The factors of the stored scene (sim::scenario_factors): the store's factor columns, in order.
/// Throws InputError for a stored scene that does not parse.
[[nodiscard]] sim::FactorTable scenario_factors(const CampaignMeta& meta);

/// An open results store. Move-only; closes the database when destroyed.
class ResultStore {
 public:
  /// Opens DIR's store for writing, creating it (and DIR) with `meta` when absent or without any
  /// table (an empty file, or a creation cut short before its one transaction committed). Throws
  /// UsageError (exit 2) when the existing store has another config hash (the message names the
  /// store and both hashes), another shard, or another schema version, or is not a store.
  static ResultStore open_for_writing(const std::filesystem::path& results_sqlite, const CampaignMeta& meta);
  /// Opens an existing store read-only. Throws UsageError if it is missing or not a store.
  static ResultStore open_for_reading(const std::filesystem::path& results_sqlite);

  ResultStore(ResultStore&& other) noexcept;
  ResultStore& operator=(ResultStore&&) = delete;
  ResultStore(const ResultStore&) = delete;
  ResultStore& operator=(const ResultStore&) = delete;
  ~ResultStore();

  [[nodiscard]] const CampaignMeta& meta() const noexcept { return meta_; }
  /// Inserts the cells and their outcomes in one transaction. Throws emrm::Error if a cell is
  /// already stored or the database cannot be written (nothing of the batch is then kept).
  void insert(const std::vector<CellRecord>& batch);
  /// Calls `visit(grid_position, index)` for every simulated cell (any order): inferred cells are
  /// not done for a sweep that simulates every cell.
  void for_each_key(const std::function<void(std::size_t, std::int64_t)>& visit) const;
  /// The simulated cells of a grid: (index, region), in index order.
  [[nodiscard]] std::vector<std::pair<std::int64_t, sim::Region>> simulated_regions(const std::string& grid) const;
  /// Deletes a grid's inferred cells (one transaction): a sweep is about to simulate or infer them anew.
  void delete_inferred(const std::string& grid);
  /// The summary of a grid's adaptive search (JSON text, docs/adaptive.md), replacing any before.
  void set_adaptive_summary(const std::string& grid, const std::string& json);
  /// Every grid's adaptive summary: (grid, JSON text), in grid order.
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> adaptive_summaries() const;
  /// Calls `visit(record)` for every stored cell with its outcomes, ordered by grid order, then
  /// index; outcomes in the campaign's strategy order. Streams: one record in memory at a time.
  void for_each_cell(const std::function<void(const CellRecord&)>& visit) const;
  /// Number of stored cells.
  [[nodiscard]] std::int64_t cell_count() const;
  /// Copies every cell and outcome of another store (same config hash, checked by the caller);
  /// cells already present are kept as they are.
  void absorb(const std::filesystem::path& other_results_sqlite);

 private:
  ResultStore(sqlite3* db, std::filesystem::path path, CampaignMeta meta);
  sqlite3* db_ = nullptr;
  std::filesystem::path path_;
  CampaignMeta meta_;
};

/// DIR/results.sqlite of a results folder, for `command`'s messages ("emrm report"). Throws
/// UsageError (exit 2) when DIR does not exist, is not a folder or holds no results.sqlite.
[[nodiscard]] std::filesystem::path results_store_in(const std::filesystem::path& dir, std::string_view command);

/// Every cell of a store, ordered by grid order then index. Throws as read_meta.
[[nodiscard]] std::vector<CellRecord> read_results(const std::filesystem::path& results_sqlite);
/// The store's metadata. Throws UsageError (exit 2) if the file is missing, is not a results
/// store, or has an incompatible schema version.
[[nodiscard]] CampaignMeta read_meta(const std::filesystem::path& results_sqlite);
/// Joins the stores DIR/results.sqlite of `dirs` (shards of one campaign) into
/// OUTPUT_DIR/results.sqlite (shard 1/1) and writes its exports (exports.hpp). Throws UsageError when a store is
/// missing or the config hashes differ.
void merge(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& output_dir);

}  // namespace emrm::campaign
