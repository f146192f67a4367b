// Writing to the results store: a batch of cells with their outcomes and trajectories in one
// transaction, and what the adaptive search replaces (its inferred cells, its summary).

#include <cmath>
#include <string>
#include <vector>

#include "emrm/campaign/store.hpp"
#include "emrm/core/text.hpp"
#include "store_fields.hpp"
#include "store_sql.hpp"

namespace emrm::campaign {
namespace {

using detail::exec;
using detail::Statement;

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

// "?,?,…,?": one placeholder per column of a table.
std::string placeholders(int columns) {
  std::string places(2 * static_cast<std::size_t>(columns) - 1, ',');
  for (std::size_t i = 0; i < places.size(); i += 2) places[i] = '?';
  return places;
}

}  // namespace

void ResultStore::insert(const std::vector<CellRecord>& batch) {
  if (batch.empty()) return;
  exec(db_, path_, "BEGIN IMMEDIATE");
  try {
    // One placeholder per column of the table: the fixed ones and one per factor of the store's scene.
    const int columns = Statement(db_, path_, "SELECT * FROM cells LIMIT 0").column_count();
    const std::string insert_cell = "INSERT INTO cells VALUES(" + placeholders(columns) + ")";
    Statement cell(db_, path_, insert_cell.c_str());
    const std::string insert_outcome =
        "INSERT INTO outcomes VALUES(" +
        placeholders(Statement(db_, path_, "SELECT * FROM outcomes LIMIT 0").column_count()) + ")";
    Statement outcome(db_, path_, insert_outcome.c_str());
    Statement trajectory(db_, path_, "INSERT INTO trajectories VALUES(?,?,?,?,?,?)");
    for (const auto& r : batch) {
      cell.reset();
      const int bound = detail::bind_fields(cell, 1, r) - 1;
      if (bound != columns)
        throw UsageError(fmt::format("{}: error: cell {} of grid '{}' has {} factors, the store's scene {}",
                                     path_.string(), r.index, r.grid, r.factors.size(),
                                     static_cast<int>(r.factors.size()) + columns - bound));
      cell.step();
      for (std::size_t i = 0; i < r.outcomes.size(); ++i) {
        const auto& o = r.outcomes[i];
        outcome.reset();
        outcome.bind(1, r.grid);
        outcome.bind(2, r.index);
        outcome.bind(3, static_cast<std::int64_t>(i));
        detail::bind_fields(outcome, 4, o);
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

}  // namespace emrm::campaign
