// Reading the results store: the keys and regions of its simulated cells, the adaptive summaries,
// and every cell with its outcomes and trajectories, in the order of the grids.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "emrm/campaign/store.hpp"
#include "store_fields.hpp"
#include "store_sql.hpp"

namespace emrm::campaign {
namespace {

using detail::named;
using detail::not_a_store;
using detail::Statement;
using detail::whole_number;

// Polylines as text (store_write.cpp): points "t x y v" joined by ';', polylines joined by '|'.
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

}  // namespace

void ResultStore::for_each_key(const std::function<void(std::size_t, std::int64_t)>& visit) const {
  Statement q(
      db_, path_,
      "SELECT g.position, c.cell_index FROM cells c JOIN grids g ON g.name = c.grid WHERE c.method = 'simulated'");
  while (q.step()) visit(static_cast<std::size_t>(q.int64(0)), q.int64(1));
}

std::vector<std::pair<std::int64_t, sim::Region>> ResultStore::simulated_regions(const std::string& grid) const {
  Statement q(db_, path_,
              "SELECT cell_index, region FROM cells WHERE grid = ? AND method = 'simulated' ORDER BY cell_index");
  q.bind(1, grid);
  std::vector<std::pair<std::int64_t, sim::Region>> out;
  while (q.step()) {
    const std::int64_t index = q.int64(0);
    out.emplace_back(index, named<sim::Region>(
                                path_, [&] { return fmt::format("region of cell {}#{}", grid, index); }, q.text(1)));
  }
  return out;
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
  Statement cells(db_, path_,
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
  // The columns of each field, found by name (store_fields.hpp); the factors' between them.
  const detail::FieldColumns<CellRecord> cell_columns(cells, path_);
  constexpr std::string_view kOutcomeKeys[] = {"grid", "cell_index", "position"};
  const detail::FieldColumns<OutcomeRecord> outcome_columns(outcomes, path_, kOutcomeKeys);
  while (cells.step()) {
    cell_columns.read(cells, r,
                      [&r](const char* name) { return fmt::format("{} of cell {}#{}", name, r.grid, r.index); });
    r.outcomes.clear();
    // Both queries run in the same order, so a cell's outcomes are the next rows that name it.
    while (have_outcome && outcomes.text(0) == r.grid && outcomes.int64(1) == r.index) {
      OutcomeRecord o;
      outcome_columns.read(outcomes, o, [&r](const char* name) {
        return fmt::format("{} of an outcome of cell {}#{}", name, r.grid, r.index);
      });
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

std::vector<CellRecord> read_results(const std::filesystem::path& results_sqlite) {
  const ResultStore store = ResultStore::open_for_reading(results_sqlite);
  std::vector<CellRecord> out;
  store.for_each_cell([&](const CellRecord& r) { out.push_back(r); });
  return out;
}

}  // namespace emrm::campaign
