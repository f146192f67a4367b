// The results store (docs/campaign.md): its schema and metadata, opening it to write (created, or
// resumed when the configuration matches) or to read, and the SQLite calls its parts share.
// Writing rows is in store_write.cpp, reading them in store_read.cpp, merging shards in
// store_merge.cpp.

#include "emrm/campaign/store.hpp"

#include <fmt/format.h>
#include <sqlite3.h>
#include <unistd.h>

#include <map>
#include <sstream>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/version.hpp"
#include "store_fields.hpp"
#include "store_sql.hpp"

namespace emrm::campaign {

namespace detail {

[[noreturn]] void fail(sqlite3* db, const std::filesystem::path& path, const std::string& what) {
  throw Error(fmt::format("{}: {}: {}", path.string(), what, db ? sqlite3_errmsg(db) : "out of memory"));
}

std::optional<std::string> column_text(sqlite3_stmt* stmt, int col) {
  const auto* p = sqlite3_column_text(stmt, col);
  std::string value =
      p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt, col)))
        : std::string();
  if (core::first_invalid_utf8(value)) return std::nullopt;
  return value;
}

void exec(sqlite3* db, const std::filesystem::path& path, const char* sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw Error(fmt::format("{}: {}", path.string(), text));
  }
}

[[noreturn]] void not_a_store(const std::filesystem::path& path, const std::string& why) {
  throw UsageError(fmt::format("{}: error: not an emrm results store ({})", path.string(), why));
}

}  // namespace detail

namespace {

namespace fs = std::filesystem;

using detail::column_text;
using detail::exec;
using detail::not_a_store;
using detail::Statement;
using detail::whole_number;

// The cells table has a REAL column per factor of the scene's factor table, between cell_index and
// seed ({factors}); readers find them there by name.
constexpr const char* kSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE grids(position INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE cells(
  {cells},
  PRIMARY KEY(grid, cell_index)) WITHOUT ROWID;
CREATE TABLE outcomes(
  grid TEXT NOT NULL, cell_index INTEGER NOT NULL, position INTEGER NOT NULL,
  {outcomes},
  PRIMARY KEY(grid, cell_index, position)) WITHOUT ROWID;
CREATE TABLE trajectories(
  grid TEXT NOT NULL, cell_index INTEGER NOT NULL, position INTEGER NOT NULL,
  path TEXT NOT NULL, goal_tree TEXT NOT NULL, failsafe_tree TEXT NOT NULL,
  PRIMARY KEY(grid, cell_index, position)) WITHOUT ROWID;
CREATE TABLE adaptive(grid TEXT PRIMARY KEY, summary TEXT NOT NULL) WITHOUT ROWID;
)sql";

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

// Reads the meta table; UsageError when the database is not a store of our schema version.
CampaignMeta load_meta(sqlite3* db, const std::filesystem::path& path) {
  std::map<std::string, std::string> kv;
  {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT key, value FROM meta", -1, &raw, nullptr) != SQLITE_OK) {
      const std::string why = sqlite3_errmsg(db);
      sqlite3_finalize(raw);
      not_a_store(path, why);
    }
    int rc = 0;
    const auto column = [&](int i) {  // NULL (a store edited by hand) reads as empty
      auto value = column_text(raw, i);
      if (!value) {
        sqlite3_finalize(raw);
        not_a_store(path, "its metadata holds a byte that is not UTF-8");
      }
      return *value;
    };
    while ((rc = sqlite3_step(raw)) == SQLITE_ROW) kv[column(0)] = column(1);
    sqlite3_finalize(raw);
    if (rc != SQLITE_DONE) not_a_store(path, sqlite3_errmsg(db));
  }
  const auto get = [&](const std::string& key) {
    auto it = kv.find(key);
    if (it == kv.end()) not_a_store(path, "no '" + key + "' in its metadata");
    return it->second;
  };
  const std::string version = get("schema_version");
  if (version != std::to_string(kStoreSchemaVersion))
    throw UsageError(fmt::format("{}: error: results store of schema version {}, but this emrm reads version {}",
                                 path.string(), version, kStoreSchemaVersion));
  CampaignMeta meta;
  meta.config_hash = get("config_hash");
  meta.emrm_version = get("emrm_version");
  meta.campaign_yaml = get("campaign_yaml");
  meta.scene_yaml = get("scene_yaml");
  meta.seed = whole_number<std::uint64_t>(path, "seed", get("seed"));
  meta.strategies = split_lines(get("strategies"));
  meta.grids = split_lines(get("grids"));
  meta.shard_index = whole_number<int>(path, "shard_index", get("shard_index"));
  meta.shard_count = whole_number<int>(path, "shard_count", get("shard_count"));
  return meta;
}

sqlite3* open_db(const std::filesystem::path& path, int flags) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw UsageError(fmt::format("{}: error: cannot open the results store: {}", path.string(), why));
  }
  sqlite3_busy_timeout(db, 10000);
  return db;
}

// A database without a single table: a store whose creation was cut short before its first
// commit (the schema and the metadata are one transaction), or an empty file. It is created afresh
// rather than refused as "not a store", so that rerunning the command resumes.
// A file that is no database at all is left to load_meta, which says so.
bool without_tables(sqlite3* db) {
  sqlite3_stmt* q = nullptr;
  const bool empty = sqlite3_prepare_v2(db, "SELECT COUNT(*) FROM sqlite_master", -1, &q, nullptr) == SQLITE_OK &&
                     sqlite3_step(q) == SQLITE_ROW && sqlite3_column_int64(q, 0) == 0;
  sqlite3_finalize(q);
  return empty;
}

// RAII closing for the error paths before a ResultStore owns the handle.
struct DbGuard {
  sqlite3* db;
  ~DbGuard() {
    if (db) sqlite3_close(db);
  }
  sqlite3* release() { return std::exchange(db, nullptr); }
};

}  // namespace

CampaignMeta make_meta(const Campaign& campaign) {
  CampaignMeta meta;
  meta.config_hash = config_hash(campaign);
  meta.emrm_version = kVersion;
  meta.campaign_yaml = campaign.text;
  meta.scene_yaml = sim::to_yaml(campaign.scene);
  meta.seed = campaign.seed;
  meta.strategies = campaign.strategies;
  for (const auto& grid : campaign.grids) meta.grids.push_back(grid.name);
  return meta;
}

ResultStore::ResultStore(sqlite3* db, std::filesystem::path path, CampaignMeta meta)
    : db_(db), path_(std::move(path)), meta_(std::move(meta)) {}

ResultStore::ResultStore(ResultStore&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)), path_(std::move(other.path_)), meta_(std::move(other.meta_)) {}

sim::FactorTable scenario_factors(const CampaignMeta& meta) {
  return sim::scenario_factors(sim::parse_stored_scene_config(meta.scene_yaml, "the results store's scene"));
}

ResultStore::~ResultStore() {
  if (db_) sqlite3_close(db_);
}

ResultStore ResultStore::open_for_writing(const std::filesystem::path& results_sqlite, const CampaignMeta& meta) {
  if (results_sqlite.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(results_sqlite.parent_path(), ec);
    if (ec)
      throw UsageError(fmt::format("{}: error: cannot create the output folder: {}",
                                   results_sqlite.parent_path().string(), ec.message()));
  }
  const bool existed = std::filesystem::exists(results_sqlite);
  DbGuard guard{open_db(results_sqlite, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE)};
  sqlite3* db = guard.db;
  if (existed && !without_tables(db)) {
    const CampaignMeta stored = load_meta(db, results_sqlite);
    const std::string dir = results_sqlite.parent_path().string();
    if (stored.config_hash != meta.config_hash)
      throw UsageError(
          fmt::format("{}: error: the results in {} come from another configuration (config hash {}, this "
                      "campaign's is {}); "
                      "use another output folder or delete it to start over",
                      results_sqlite.string(), dir, stored.config_hash, meta.config_hash));
    if (stored.shard_index != meta.shard_index || stored.shard_count != meta.shard_count)
      throw UsageError(fmt::format("{}: error: the results in {} are shard {}/{}, not {}/{}; use another output folder",
                                   results_sqlite.string(), dir, stored.shard_index, stored.shard_count,
                                   meta.shard_index, meta.shard_count));
    exec(db, results_sqlite, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;");
    return ResultStore(guard.release(), results_sqlite, stored);
  }
  // WAL: a reader (a report, a progress query) never blocks the sweep, and a killed writer leaves
  // the last committed batch intact.
  exec(db, results_sqlite, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;");
  exec(db, results_sqlite, "BEGIN");
  {
    // The cells' and outcomes' columns from the records' field lists (store_fields.hpp).
    std::vector<std::string> keys;
    for (const sim::Factor& f : scenario_factors(meta)) keys.push_back(f.key);
    const std::string schema = fmt::format(
        fmt::runtime(kSchema), fmt::arg("cells", core::join(detail::column_definitions<CellRecord>(keys), ",\n  ")),
        fmt::arg("outcomes", core::join(detail::column_definitions<OutcomeRecord>({}), ",\n  ")));
    exec(db, results_sqlite, schema.c_str());
  }
  {
    Statement put(db, results_sqlite, "INSERT INTO meta(key, value) VALUES(?, ?)");
    const auto set = [&](const std::string& key, const std::string& value) {
      put.reset();
      put.bind(1, key);
      put.bind(2, value);
      put.step();
    };
    set("schema_version", std::to_string(kStoreSchemaVersion));
    set("config_hash", meta.config_hash);
    set("emrm_version", meta.emrm_version);
    set("campaign_yaml", meta.campaign_yaml);
    set("scene_yaml", meta.scene_yaml);
    set("seed", std::to_string(meta.seed));
    set("strategies", core::join(meta.strategies, "\n"));
    set("grids", core::join(meta.grids, "\n"));
    set("shard_index", std::to_string(meta.shard_index));
    set("shard_count", std::to_string(meta.shard_count));
    Statement grid(db, results_sqlite, "INSERT INTO grids(position, name) VALUES(?, ?)");
    for (std::size_t i = 0; i < meta.grids.size(); ++i) {
      grid.reset();
      grid.bind(1, static_cast<std::int64_t>(i));
      grid.bind(2, meta.grids[i]);
      grid.step();
    }
  }
  exec(db, results_sqlite, "COMMIT");
  return ResultStore(guard.release(), results_sqlite, meta);
}

ResultStore ResultStore::open_for_reading(const std::filesystem::path& results_sqlite) {
  if (!std::filesystem::is_regular_file(results_sqlite))
    throw UsageError(fmt::format("{}: error: no results store here (run `emrm sweep` first)", results_sqlite.string()));
  // Read-write when allowed (nothing is written): the last connection to close then removes the
  // -wal and -shm files, which a read-only one would leave behind.
  const auto dir = results_sqlite.has_parent_path() ? results_sqlite.parent_path() : fs::path(".");
  const bool writable = ::access(results_sqlite.c_str(), W_OK) == 0 && ::access(dir.c_str(), W_OK) == 0;
  DbGuard guard{open_db(results_sqlite, writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY)};
  CampaignMeta meta = load_meta(guard.db, results_sqlite);
  return ResultStore(guard.release(), results_sqlite, std::move(meta));
}

CampaignMeta read_meta(const std::filesystem::path& results_sqlite) {
  return ResultStore::open_for_reading(results_sqlite).meta();
}

std::filesystem::path results_store_in(const std::filesystem::path& dir, std::string_view command) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec))
    throw UsageError(fmt::format("{}: results folder '{}' does not exist", command, dir.string()));
  if (!std::filesystem::is_directory(dir, ec))
    throw UsageError(
        fmt::format("{}: '{}' is not a folder; expected a results folder written by emrm sweep, run or "
                    "reproduce",
                    command, dir.string()));
  auto store = dir / kStoreFile;
  if (!std::filesystem::is_regular_file(store, ec))
    throw UsageError(
        fmt::format("{}: '{}' holds no {}; expected a results folder written by emrm sweep, run or reproduce", command,
                    dir.string(), kStoreFile));
  return store;
}

}  // namespace emrm::campaign
