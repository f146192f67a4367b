#include "emrm/campaign/store.hpp"

#include <fmt/format.h>
#include <sqlite3.h>
#include <unistd.h>

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>

#include "emrm/campaign/exports.hpp"
#include "emrm/core/text.hpp"
#include "emrm/version.hpp"

namespace emrm::campaign {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE grids(position INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE cells(
  grid TEXT NOT NULL, cell_index INTEGER NOT NULL,
  speed_kph REAL NOT NULL, ttc_s REAL NOT NULL, mu REAL NOT NULL, passage_m REAL NOT NULL,
  truck_speed_kph REAL NOT NULL, seed TEXT NOT NULL, feasible INTEGER NOT NULL, region TEXT NOT NULL,
  unmitigated_impact_speed_kph REAL NOT NULL, unmitigated_delta_v_kph REAL NOT NULL,
  unmitigated_p_mais3 REAL NOT NULL, unmitigated_p_fatal REAL NOT NULL, unmitigated_loss_level INTEGER NOT NULL,
  evidence TEXT NOT NULL, mitigation_evidence TEXT NOT NULL, strengthened INTEGER NOT NULL, certificate TEXT NOT NULL,
  p_mais3_reduction REAL NOT NULL, p_fatal_reduction REAL NOT NULL,
  method TEXT NOT NULL, inferred_from TEXT NOT NULL,
  PRIMARY KEY(grid, cell_index)) WITHOUT ROWID;
CREATE TABLE outcomes(
  grid TEXT NOT NULL, cell_index INTEGER NOT NULL, position INTEGER NOT NULL, strategy TEXT NOT NULL,
  avoided INTEGER NOT NULL, contact INTEGER NOT NULL, road_departure INTEGER NOT NULL,
  impact_speed_kph REAL NOT NULL, delta_v_kph REAL NOT NULL, p_mais3 REAL NOT NULL, p_fatal REAL NOT NULL,
  loss_level INTEGER NOT NULL, delta_loss INTEGER NOT NULL, min_ttc_s REAL,
  planner_nodes INTEGER NOT NULL, planner_rollouts INTEGER NOT NULL,
  fsm_trace TEXT NOT NULL, loss_evaluation_trace TEXT NOT NULL, chosen_strategy TEXT NOT NULL,
  adopted_from TEXT NOT NULL, evidence TEXT NOT NULL, maneuver TEXT NOT NULL,
  PRIMARY KEY(grid, cell_index, position)) WITHOUT ROWID;
CREATE TABLE trajectories(
  grid TEXT NOT NULL, cell_index INTEGER NOT NULL, position INTEGER NOT NULL,
  path TEXT NOT NULL, goal_tree TEXT NOT NULL, failsafe_tree TEXT NOT NULL,
  PRIMARY KEY(grid, cell_index, position)) WITHOUT ROWID;
CREATE TABLE adaptive(grid TEXT PRIMARY KEY, summary TEXT NOT NULL) WITHOUT ROWID;
)sql";

// Polylines as text: points "t x y v" joined by ';', polylines joined by '|'.
std::string encode(const Polyline& line) {
  std::string out;
  for (const auto& p : line) {
    if (!out.empty()) out += ';';
    out += fmt::format("{:.2f} {:.2f} {:.2f} {:.2f}", p[0], p[1], p[2], p[3]);
  }
  return out;
}

std::string encode(const std::vector<Polyline>& lines) {
  std::string out;
  for (std::size_t i = 0; i < lines.size(); ++i) out += (i ? "|" : "") + encode(lines[i]);
  return out;
}

Polyline decode_line(std::string_view text) {
  Polyline line;
  while (!text.empty()) {
    const auto end = std::min(text.find(';'), text.size());
    std::array<double, 4> p{};
    std::istringstream in{std::string(text.substr(0, end))};
    in >> p[0] >> p[1] >> p[2] >> p[3];
    line.push_back(p);
    text.remove_prefix(std::min(end + 1, text.size()));
  }
  return line;
}

std::vector<Polyline> decode_lines(std::string_view text) {
  std::vector<Polyline> lines;
  while (!text.empty()) {
    const auto end = std::min(text.find('|'), text.size());
    lines.push_back(decode_line(text.substr(0, end)));
    text.remove_prefix(std::min(end + 1, text.size()));
  }
  return lines;
}

[[noreturn]] void fail(sqlite3* db, const std::filesystem::path& path, const std::string& what) {
  throw Error(fmt::format("{}: {}: {}", path.string(), what, db ? sqlite3_errmsg(db) : "out of memory"));
}

// A text column (NULL, in a store edited by hand, reads as empty), or nothing when its bytes are
// not UTF-8.
std::optional<std::string> column_text(sqlite3_stmt* stmt, int col) {
  const auto* p = sqlite3_column_text(stmt, col);
  std::string value =
      p ? std::string(reinterpret_cast<const char*>(p), static_cast<std::size_t>(sqlite3_column_bytes(stmt, col)))
        : std::string();
  if (core::first_invalid_utf8(value)) return std::nullopt;
  return value;
}

// A prepared statement that finalizes itself.
class Statement {
 public:
  Statement(sqlite3* db, const std::filesystem::path& path, const char* sql) : db_(db), path_(&path) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK)
      fail(db, path, "cannot prepare a query");
  }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  /// True when a row is available.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db_, *path_, "query failed");
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  void bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
  }
  void bind(int i, double v) { sqlite3_bind_double(stmt_, i, v); }
  void bind(int i, std::int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
  void bind(int i, int v) { sqlite3_bind_int(stmt_, i, v); }
  void bind(int i, bool v) { sqlite3_bind_int(stmt_, i, v ? 1 : 0); }
  void bind_null(int i) { sqlite3_bind_null(stmt_, i); }

  /// The text of a column; a store edited by hand may hold bytes that are not UTF-8, refused here
  /// before they reach a JSON or CSV writer.
  std::string text(int col) const {
    if (auto value = column_text(stmt_, col)) return *value;
    throw UsageError(fmt::format("{}: error: not an emrm results store (column '{}' holds a byte that is not "
                                 "UTF-8; it was damaged or edited)",
                                 path_->string(), sqlite3_column_name(stmt_, col)));
  }
  double real(int col) const { return sqlite3_column_double(stmt_, col); }
  std::int64_t int64(int col) const { return sqlite3_column_int64(stmt_, col); }
  int integer(int col) const { return sqlite3_column_int(stmt_, col); }
  bool is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }

 private:
  sqlite3* db_;
  const std::filesystem::path* path_;
  sqlite3_stmt* stmt_ = nullptr;
};

void exec(sqlite3* db, const std::filesystem::path& path, const char* sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw Error(fmt::format("{}: {}", path.string(), text));
  }
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string word; in >> word;) out.push_back(word);
  return out;
}

[[noreturn]] void not_a_store(const std::filesystem::path& path, const std::string& why);

// A whole number the store keeps as text, or not_a_store naming what holds something else.
template <typename T>
T whole_number(const std::filesystem::path& path, const std::string& what, const std::string& text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    not_a_store(path, fmt::format("its {} is '{}', not a whole number", what, text.substr(0, 40)));
  return value;
}

[[noreturn]] void not_a_store(const std::filesystem::path& path, const std::string& why) {
  throw UsageError(fmt::format("{}: error: not an emrm results store ({})", path.string(), why));
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
    throw UsageError(
        fmt::format("{}: error: results store of schema version {}, but this emrm reads version {}",
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

ResultStore::~ResultStore() {
  if (db_) sqlite3_close(db_);
}

ResultStore ResultStore::open_for_writing(const std::filesystem::path& results_sqlite,
                                          const CampaignMeta& meta) {
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
      throw UsageError(
          fmt::format("{}: error: the results in {} are shard {}/{}, not {}/{}; use another output folder",
                      results_sqlite.string(), dir, stored.shard_index, stored.shard_count, meta.shard_index,
                      meta.shard_count));
    exec(db, results_sqlite, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;");
    return ResultStore(guard.release(), results_sqlite, stored);
  }
  // WAL: a reader (a report, a progress query) never blocks the sweep, and a killed writer leaves
  // the last committed batch intact.
  exec(db, results_sqlite, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;");
  exec(db, results_sqlite, "BEGIN");
  exec(db, results_sqlite, kSchema);
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
    throw UsageError(
        fmt::format("{}: error: no results store here (run `emrm sweep` first)", results_sqlite.string()));
  // Read-write when allowed (nothing is written): the last connection to close then removes the
  // -wal and -shm files, which a read-only one would leave behind.
  const auto dir = results_sqlite.has_parent_path() ? results_sqlite.parent_path() : fs::path(".");
  const bool writable = ::access(results_sqlite.c_str(), W_OK) == 0 && ::access(dir.c_str(), W_OK) == 0;
  DbGuard guard{open_db(results_sqlite, writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY)};
  CampaignMeta meta = load_meta(guard.db, results_sqlite);
  return ResultStore(guard.release(), results_sqlite, std::move(meta));
}

void ResultStore::insert(const std::vector<CellRecord>& batch) {
  if (batch.empty()) return;
  exec(db_, path_, "BEGIN IMMEDIATE");
  try {
    Statement cell(db_, path_, "INSERT INTO cells VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    Statement outcome(db_, path_, "INSERT INTO outcomes VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    Statement trajectory(db_, path_, "INSERT INTO trajectories VALUES(?,?,?,?,?,?)");
    for (const auto& r : batch) {
      cell.reset();
      cell.bind(1, r.grid);
      cell.bind(2, r.index);
      cell.bind(3, r.speed_kph);
      cell.bind(4, r.ttc_s);
      cell.bind(5, r.mu);
      cell.bind(6, r.passage_m);
      cell.bind(7, r.truck_speed_kph);
      cell.bind(8, std::to_string(r.seed));  // as text: SQLite integers are signed 64-bit
      cell.bind(9, r.feasible);
      cell.bind(10, r.region);
      cell.bind(11, r.unmitigated_impact_speed_kph);
      cell.bind(12, r.unmitigated_delta_v_kph);
      cell.bind(13, r.unmitigated_p_mais3);
      cell.bind(14, r.unmitigated_p_fatal);
      cell.bind(15, r.unmitigated_loss_level);
      cell.bind(16, r.evidence);
      cell.bind(17, r.mitigation_evidence);
      cell.bind(18, r.strengthened);
      cell.bind(19, r.certificate);
      cell.bind(20, r.p_mais3_reduction);
      cell.bind(21, r.p_fatal_reduction);
      cell.bind(22, r.method);
      std::string from;
      for (const std::int64_t i : r.inferred_from) from += (from.empty() ? "" : " ") + std::to_string(i);
      cell.bind(23, from);
      cell.step();
      for (std::size_t i = 0; i < r.outcomes.size(); ++i) {
        const auto& o = r.outcomes[i];
        outcome.reset();
        outcome.bind(1, r.grid);
        outcome.bind(2, r.index);
        outcome.bind(3, static_cast<std::int64_t>(i));
        outcome.bind(4, o.strategy);
        outcome.bind(5, o.avoided);
        outcome.bind(6, o.contact);
        outcome.bind(7, o.road_departure);
        outcome.bind(8, o.impact_speed_kph);
        outcome.bind(9, o.delta_v_kph);
        outcome.bind(10, o.p_mais3);
        outcome.bind(11, o.p_fatal);
        outcome.bind(12, o.loss_level);
        outcome.bind(13, o.delta_loss);
        if (std::isfinite(o.min_ttc_s))
          outcome.bind(14, o.min_ttc_s);
        else
          outcome.bind_null(14);
        outcome.bind(15, o.planner_nodes);
        outcome.bind(16, o.planner_rollouts);
        outcome.bind(17, core::join(o.fsm_trace, " "));
        outcome.bind(18, core::join(o.loss_evaluation_trace, " "));
        outcome.bind(19, o.chosen_strategy);
        outcome.bind(20, o.adopted_from);
        outcome.bind(21, o.evidence);
        outcome.bind(22, o.maneuver);
        outcome.step();
        if (o.path.empty() && o.goal_tree.empty() && o.failsafe_tree.empty()) continue;
        trajectory.reset();
        trajectory.bind(1, r.grid);
        trajectory.bind(2, r.index);
        trajectory.bind(3, static_cast<std::int64_t>(i));
        trajectory.bind(4, encode(o.path));
        trajectory.bind(5, encode(o.goal_tree));
        trajectory.bind(6, encode(o.failsafe_tree));
        trajectory.step();
      }
    }
    exec(db_, path_, "COMMIT");
  } catch (...) {
    // The whole batch or nothing: a failed COMMIT (a full disk) leaves the transaction open until
    // rolled back, and the next batch must not begin inside it.
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void ResultStore::for_each_key(const std::function<void(std::size_t, std::int64_t)>& visit) const {
  Statement q(db_, path_,
              "SELECT g.position, c.cell_index FROM cells c JOIN grids g ON g.name = c.grid WHERE c.method = 'simulated'");
  while (q.step()) visit(static_cast<std::size_t>(q.int64(0)), q.int64(1));
}

std::vector<std::pair<std::int64_t, std::string>> ResultStore::simulated_regions(const std::string& grid) const {
  Statement q(db_, path_,
              "SELECT cell_index, region FROM cells WHERE grid = ? AND method = 'simulated' ORDER BY cell_index");
  q.bind(1, grid);
  std::vector<std::pair<std::int64_t, std::string>> out;
  while (q.step()) out.emplace_back(q.int64(0), q.text(1));
  return out;
}

void ResultStore::delete_inferred(const std::string& grid) {
  Statement q(db_, path_, "DELETE FROM cells WHERE grid = ? AND method = 'inferred'");
  q.bind(1, grid);
  q.step();
}

void ResultStore::set_adaptive_summary(const std::string& grid, const std::string& json) {
  Statement q(db_, path_, "INSERT OR REPLACE INTO adaptive(grid, summary) VALUES(?, ?)");
  q.bind(1, grid);
  q.bind(2, json);
  q.step();
}

std::vector<std::pair<std::string, std::string>> ResultStore::adaptive_summaries() const {
  Statement q(db_, path_,
              "SELECT a.grid, a.summary FROM adaptive a JOIN grids g ON g.name = a.grid ORDER BY g.position");
  std::vector<std::pair<std::string, std::string>> out;
  while (q.step()) out.emplace_back(q.text(0), q.text(1));
  return out;
}

std::int64_t ResultStore::cell_count() const {
  Statement q(db_, path_, "SELECT COUNT(*) FROM cells");
  q.step();
  return q.int64(0);
}

void ResultStore::for_each_cell(const std::function<void(const CellRecord&)>& visit) const {
  Statement cells(
      db_, path_,
      "SELECT c.* FROM cells c JOIN grids g ON g.name = c.grid ORDER BY g.position, c.cell_index");
  Statement outcomes(db_, path_,
                     "SELECT o.* FROM outcomes o JOIN grids g ON g.name = o.grid "
                     "ORDER BY g.position, o.cell_index, o.position");
  // Trajectories are few (grids with keep_trees): read them first, keyed by cell and position.
  std::map<std::tuple<std::string, std::int64_t, std::int64_t>, std::array<std::string, 3>> trajectories;
  {
    Statement t(db_, path_, "SELECT * FROM trajectories");
    while (t.step()) trajectories[{t.text(0), t.int64(1), t.int64(2)}] = {t.text(3), t.text(4), t.text(5)};
  }
  bool have_outcome = outcomes.step();
  CellRecord r;
  while (cells.step()) {
    r.grid = cells.text(0);
    r.index = cells.int64(1);
    r.speed_kph = cells.real(2);
    r.ttc_s = cells.real(3);
    r.mu = cells.real(4);
    r.passage_m = cells.real(5);
    r.truck_speed_kph = cells.real(6);
    r.seed = whole_number<std::uint64_t>(path_, fmt::format("seed of cell {}#{}", r.grid, r.index), cells.text(7));
    r.feasible = cells.integer(8) != 0;
    r.region = cells.text(9);
    r.unmitigated_impact_speed_kph = cells.real(10);
    r.unmitigated_delta_v_kph = cells.real(11);
    r.unmitigated_p_mais3 = cells.real(12);
    r.unmitigated_p_fatal = cells.real(13);
    r.unmitigated_loss_level = cells.integer(14);
    r.evidence = cells.text(15);
    r.mitigation_evidence = cells.text(16);
    r.strengthened = cells.integer(17) != 0;
    r.certificate = cells.text(18);
    r.p_mais3_reduction = cells.real(19);
    r.p_fatal_reduction = cells.real(20);
    r.method = cells.text(21);
    if (r.method != "simulated" && r.method != "inferred")
      not_a_store(path_, fmt::format("the method of cell {}#{} is '{}', not simulated or inferred", r.grid, r.index,
                                     r.method.substr(0, 40)));
    r.inferred_from.clear();
    for (const auto& word : split_words(cells.text(22)))
      r.inferred_from.push_back(
          whole_number<std::int64_t>(path_, fmt::format("inferred_from of cell {}#{}", r.grid, r.index), word));
    r.outcomes.clear();
    // Both queries run in the same order, so a cell's outcomes are the next rows that name it.
    while (have_outcome && outcomes.text(0) == r.grid && outcomes.int64(1) == r.index) {
      OutcomeRecord o;
      o.strategy = outcomes.text(3);
      o.avoided = outcomes.integer(4) != 0;
      o.contact = outcomes.integer(5) != 0;
      o.road_departure = outcomes.integer(6) != 0;
      o.impact_speed_kph = outcomes.real(7);
      o.delta_v_kph = outcomes.real(8);
      o.p_mais3 = outcomes.real(9);
      o.p_fatal = outcomes.real(10);
      o.loss_level = outcomes.integer(11);
      o.delta_loss = outcomes.integer(12);
      o.min_ttc_s = outcomes.is_null(13) ? std::numeric_limits<double>::infinity() : outcomes.real(13);
      o.planner_nodes = outcomes.integer(14);
      o.planner_rollouts = outcomes.integer(15);
      o.fsm_trace = split_words(outcomes.text(16));
      o.loss_evaluation_trace = split_words(outcomes.text(17));
      o.chosen_strategy = outcomes.text(18);
      o.adopted_from = outcomes.text(19);
      o.evidence = outcomes.text(20);
      o.maneuver = outcomes.text(21);
      if (const auto it = trajectories.find({r.grid, r.index, outcomes.int64(2)}); it != trajectories.end()) {
        o.path = decode_line(it->second[0]);
        o.goal_tree = decode_lines(it->second[1]);
        o.failsafe_tree = decode_lines(it->second[2]);
      }
      r.outcomes.push_back(std::move(o));
      have_outcome = outcomes.step();
    }
    visit(r);
  }
}

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

CampaignMeta read_meta(const std::filesystem::path& results_sqlite) {
  return ResultStore::open_for_reading(results_sqlite).meta();
}

std::filesystem::path results_store_in(const std::filesystem::path& dir, std::string_view command) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec))
    throw UsageError(fmt::format("{}: results folder '{}' does not exist", command, dir.string()));
  if (!std::filesystem::is_directory(dir, ec))
    throw UsageError(fmt::format("{}: '{}' is not a folder; expected a results folder written by emrm sweep, run or "
                                 "reproduce",
                                 command, dir.string()));
  const auto store = dir / "results.sqlite";
  if (!std::filesystem::is_regular_file(store, ec))
    throw UsageError(fmt::format("{}: '{}' holds no results.sqlite; expected a results folder written by emrm "
                                 "sweep, run or reproduce",
                                 command, dir.string()));
  return store;
}

std::vector<CellRecord> read_results(const std::filesystem::path& results_sqlite) {
  const ResultStore store = ResultStore::open_for_reading(results_sqlite);
  std::vector<CellRecord> out;
  store.for_each_cell([&](const CellRecord& r) { out.push_back(r); });
  return out;
}

void merge(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& output_dir) {
  if (dirs.empty()) throw UsageError("merge: no folders to merge");
  std::vector<CampaignMeta> metas;
  for (const auto& dir : dirs) metas.push_back(read_meta(dir / "results.sqlite"));
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
  const auto out_path = output_dir / "results.sqlite";
  {
    ResultStore out = ResultStore::open_for_writing(out_path, meta);
    for (const auto& dir : dirs) {
      if (std::filesystem::exists(out_path) && std::filesystem::exists(dir / "results.sqlite") &&
          std::filesystem::equivalent(out_path, dir / "results.sqlite"))
        continue;  // merging a store into itself adds nothing
      out.absorb(dir / "results.sqlite");
    }
  }
  write_exports(out_path, output_dir);
}

}  // namespace emrm::campaign
