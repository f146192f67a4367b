// Writing to the results store: a batch of cells with their outcomes and trajectories in one
// transaction, and what the adaptive search replaces (its inferred cells, its summary).

#include <cmath>
#include <string>
#include <vector>

#include "emrm/campaign/store.hpp"
#include "emrm/core/text.hpp"
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

}  // namespace

void ResultStore::insert(const std::vector<CellRecord>& batch) {
  if (batch.empty()) return;
  exec(db_, path_, "BEGIN IMMEDIATE");
  try {
    // One placeholder per column of the table: the fixed ones and one per factor of the store's scene.
    const int columns = Statement(db_, path_, "SELECT * FROM cells LIMIT 0").column_count();
    std::string places(2 * static_cast<std::size_t>(columns) - 1, ',');
    for (std::size_t i = 0; i < places.size(); i += 2) places[i] = '?';
    const std::string insert_cell = "INSERT INTO cells VALUES(" + places + ")";
    Statement cell(db_, path_, insert_cell.c_str());
    Statement outcome(db_, path_, "INSERT INTO outcomes VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    Statement trajectory(db_, path_, "INSERT INTO trajectories VALUES(?,?,?,?,?,?)");
    for (const auto& r : batch) {
      cell.reset();
      cell.bind(1, r.grid);
      cell.bind(2, r.index);
      int c = 3;
      for (const double v : r.factors) cell.bind(c++, v);
      cell.bind(c++, std::to_string(r.seed));  // as text: SQLite integers are signed 64-bit
      cell.bind(c++, r.feasible);
      cell.bind(c++, r.region);
      cell.bind(c++, r.unmitigated_impact_speed_kph);
      cell.bind(c++, r.unmitigated_delta_v_kph);
      cell.bind(c++, r.unmitigated_p_mais3);
      cell.bind(c++, r.unmitigated_p_fatal);
      cell.bind(c++, r.unmitigated_loss_level);
      cell.bind(c++, r.evidence);
      cell.bind(c++, r.mitigation_evidence);
      cell.bind(c++, r.strengthened);
      cell.bind(c++, r.certificate);
      cell.bind(c++, r.p_mais3_reduction);
      cell.bind(c++, r.p_fatal_reduction);
      cell.bind(c++, r.method);
      std::string from;
      for (const std::int64_t i : r.inferred_from) from += (from.empty() ? "" : " ") + std::to_string(i);
      if (c != columns)
        throw UsageError(fmt::format("{}: error: cell {} of grid '{}' has {} factors, the store's scene {}",
                                     path_.string(), r.index, r.grid, r.factors.size(),
                                     static_cast<int>(r.factors.size()) + columns - c));
      cell.bind(c, from);
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
