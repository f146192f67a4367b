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
#include "store_sql.hpp"

namespace emrm::campaign {
namespace {

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

std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string word; in >> word;) out.push_back(word);
  return out;
}

}  // namespace

void ResultStore::for_each_key(const std::function<void(std::size_t, std::int64_t)>& visit) const {
  Statement q(
      db_, path_,
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
  // The factor columns stand between cell_index and seed, one per factor of the scene (store.cpp).
  const int seed_column = cells.column_named("seed");
  if (seed_column < 2 || seed_column - 2 > static_cast<int>(sim::kMaxFactors))
    not_a_store(path_, "its cells table has no seed column after its factors");
  const auto factor_count = static_cast<std::size_t>(seed_column - 2);
  std::array<double, sim::kMaxFactors> factors{};
  while (cells.step()) {
    int c = 0;
    r.grid = cells.text(c++);
    r.index = cells.int64(c++);
    for (std::size_t f = 0; f < factor_count; ++f) factors[f] = cells.real(c++);
    r.factors = sim::CellInput(std::span<const double>(factors.data(), factor_count));
    r.seed = whole_number<std::uint64_t>(path_, fmt::format("seed of cell {}#{}", r.grid, r.index), cells.text(c++));
    r.feasible = cells.integer(c++) != 0;
    r.region = cells.text(c++);
    r.unmitigated_impact_speed_kph = cells.real(c++);
    r.unmitigated_delta_v_kph = cells.real(c++);
    r.unmitigated_p_mais3 = cells.real(c++);
    r.unmitigated_p_fatal = cells.real(c++);
    r.unmitigated_loss_level = cells.integer(c++);
    r.evidence = cells.text(c++);
    r.mitigation_evidence = cells.text(c++);
    r.strengthened = cells.integer(c++) != 0;
    r.certificate = cells.text(c++);
    r.p_mais3_reduction = cells.real(c++);
    r.p_fatal_reduction = cells.real(c++);
    r.method = cells.text(c++);
    if (r.method != "simulated" && r.method != "inferred")
      not_a_store(path_, fmt::format("the method of cell {}#{} is '{}', not simulated or inferred", r.grid, r.index,
                                     r.method.substr(0, 40)));
    r.inferred_from.clear();
    for (const auto& word : split_words(cells.text(c)))
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

std::vector<CellRecord> read_results(const std::filesystem::path& results_sqlite) {
  const ResultStore store = ResultStore::open_for_reading(results_sqlite);
  std::vector<CellRecord> out;
  store.for_each_cell([&](const CellRecord& r) { out.push_back(r); });
  return out;
}

}  // namespace emrm::campaign
