// Merging results stores: the shards of one campaign (the same config hash) joined into one.

#include <fmt/format.h>
#include <sqlite3.h>

#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/store.hpp"
#include "store_sql.hpp"

namespace emrm::campaign {
namespace {

using detail::exec;
using detail::Statement;
}  // namespace

void ResultStore::absorb(const std::filesystem::path& other_results_sqlite) {
  Statement attach(db_, path_, "ATTACH DATABASE ? AS src");
  attach.bind(1, other_results_sqlite.string());
  attach.step();
  try {
    exec(db_, path_,
         "BEGIN IMMEDIATE;"
         "INSERT OR IGNORE INTO cells SELECT * FROM src.cells;"
         "INSERT OR IGNORE INTO outcomes SELECT * FROM src.outcomes;"
         "INSERT OR IGNORE INTO trajectories SELECT * FROM src.trajectories;"
         "INSERT OR IGNORE INTO adaptive SELECT * FROM src.adaptive;"
         "COMMIT;");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_exec(db_, "DETACH DATABASE src", nullptr, nullptr, nullptr);
    throw;
  }
  exec(db_, path_, "DETACH DATABASE src");
}

void merge(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& output_dir) {
  if (dirs.empty()) throw UsageError("merge: no folders to merge");
  std::vector<CampaignMeta> metas;
  for (const auto& dir : dirs) metas.push_back(read_meta(dir / kStoreFile));
  for (std::size_t i = 1; i < dirs.size(); ++i)
    if (metas[i].config_hash != metas[0].config_hash)
      throw UsageError(
          fmt::format("merge: error: {} and {} come from different configurations (config hash {} and {}); "
                      "only shards of one "
                      "campaign can be merged",
                      dirs[0].string(), dirs[i].string(), metas[0].config_hash, metas[i].config_hash));
  CampaignMeta meta = metas[0];
  meta.shard_index = 1;
  meta.shard_count = 1;
  const auto out_path = output_dir / kStoreFile;
  {
    ResultStore out = ResultStore::open_for_writing(out_path, meta);
    for (const auto& dir : dirs) {
      if (std::filesystem::exists(out_path) && std::filesystem::exists(dir / kStoreFile) &&
          std::filesystem::equivalent(out_path, dir / kStoreFile))
        continue;  // merging a store into itself adds nothing
      out.absorb(dir / kStoreFile);
    }
  }
  write_exports(out_path, output_dir);
}

}  // namespace emrm::campaign
