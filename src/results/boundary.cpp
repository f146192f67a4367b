#include "emrm/results/boundary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/stop_physics.hpp"

namespace emrm::results {
namespace {

// A line's key within its grid: μ, passage width, truck speed, then the speed. Cells of one line
// share these exactly: they come from one grid's expansion of the same values.
using SliceKey = std::vector<double>;                   // the held factors, μ first
using Line = std::vector<const campaign::CellRecord*>;  // the cells of one speed, any TTC order

std::size_t distinct_ttcs(const std::vector<const campaign::CellRecord*>& cells) {
  std::set<double> levels;
  for (const auto* c : cells) levels.insert(c->factors.time_to_collision_s());
  return levels.size();
}

// (TTC, passes) of the feasible cells of a line for a region boundary of highest rank `max_rank`.
std::vector<std::pair<double, bool>> region_passes(const Line& line, int max_rank) {
  std::vector<std::pair<double, bool>> out;
  for (const auto* c : line)
    if (c->feasible) out.emplace_back(c->factors.time_to_collision_s(), region_rank(c->region) <= max_rank);
  return out;
}

// (TTC, avoided) of the feasible cells of a line that hold an outcome of `strategy`.
std::vector<std::pair<double, bool>> strategy_passes(const Line& line, std::string_view strategy) {
  std::vector<std::pair<double, bool>> out;
  for (const auto* c : line) {
    if (!c->feasible) continue;
    if (const campaign::OutcomeRecord* o = c->outcome(strategy))
      out.emplace_back(c->factors.time_to_collision_s(), o->avoided);
  }
  return out;
}

constexpr sim::Region kRanked[] = {sim::Region::kG, sim::Region::kY, sim::Region::kO, sim::Region::kR};

std::optional<int> rank_of(sim::Region region) {
  for (int k = 0; k < 4; ++k)
    if (region == kRanked[k]) return k;
  return std::nullopt;
}

// Every feasible cell's region is checked first, so that a damaged store fails before any row is
// made, naming the cell (as count_regions does).
void check_regions(const std::vector<const campaign::CellRecord*>& cells) {
  for (const auto* c : cells)
    if (c->feasible && !rank_of(c->region))
      throw Error(fmt::format("cell {} of grid '{}' is feasible but its region is '{}' (expected G, Y, O or R)",
                              c->index, c->grid, core::enum_name(c->region)));
}

// The rows of one slice of a grid: for each boundary, one per speed.
void add_slice_rows(const BoundarySlice& slice, const std::map<double, Line>& lines,
                    const std::vector<std::string>& strategies, BoundaryReport& report) {
  const auto row = [&](const std::string& boundary, double speed, std::vector<std::pair<double, bool>> passes) {
    report.rows.push_back({slice.grid, slice.held, boundary, speed, ttc_threshold(std::move(passes))});
  };
  for (const auto& b : kRegionBoundaries)
    for (const auto& [speed, line] : lines) row(std::string(b.name), speed, region_passes(line, b.max_rank));
  for (const auto& s : strategies)
    for (const auto& [speed, line] : lines) row("strategy:" + s, speed, strategy_passes(line, s));
}

void add_analytic_rows(const std::string& grid, const std::vector<const campaign::CellRecord*>& cells,
                       BoundaryReport& report) {
  std::set<std::pair<double, double>> mu_speed;
  for (const auto* c : cells) mu_speed.emplace(c->factors.friction(), c->factors.ego_speed_kph());
  for (const auto& [mu, speed] : mu_speed) {
    const double distance = report.actuation->stopping_distance_m(speed / 3.6, mu, true);
    report.analytic.push_back({grid, mu, speed, distance, sim::stop_boundary_ttc_s(speed, mu, *report.actuation)});
  }
}

void add_grid(const std::string& grid, const std::vector<const campaign::CellRecord*>& cells,
              const std::vector<std::string>& strategies, BoundaryReport& report) {
  if (const std::size_t levels = distinct_ttcs(cells); levels < 2) {
    report.skipped.push_back({grid, levels});
    return;
  }
  check_regions(cells);
  report.grids.push_back(grid);
  std::map<SliceKey, std::map<double, Line>> slices;
  for (const auto* c : cells) {
    const auto held = c->factors.values().subspan(sim::kTtcFactor + 1);
    slices[SliceKey(held.begin(), held.end())][c->factors.ego_speed_kph()].push_back(c);
  }
  for (const auto& [key, lines] : slices) {
    report.slices.push_back({grid, key});
    report.lines += lines.size();
    add_slice_rows(report.slices.back(), lines, strategies, report);
  }
  if (report.actuation) add_analytic_rows(grid, cells, report);
}

// "speed × μ × passage × truck speed": what names a line, every factor but the TTC.
std::string line_factors(const sim::FactorTable& factors) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (i != sim::kTtcFactor) names.push_back(factors[i].name);
  return core::join(names, " × ");
}

std::string optional_ttc(const std::optional<double>& ttc) { return ttc ? fmt::format("{:.9g}", *ttc) : ""; }

}  // namespace

TtcThreshold ttc_threshold(std::vector<std::pair<double, bool>> cells) {
  TtcThreshold t;
  t.cells = cells.size();
  std::sort(cells.begin(), cells.end());
  // Down from the top level while every cell of the level passes: the last such level is t*.
  std::size_t i = cells.size();
  while (i > 0) {
    const double level = cells[i - 1].first;
    std::size_t start = i;
    bool passes = true;
    while (start > 0 && cells[start - 1].first == level) passes = passes && cells[--start].second;
    if (!passes) {
      t.below = level;
      break;
    }
    t.at = level;
    i = start;
  }
  // Every passing cell below t* (at or below the failing level `below`) breaks monotonicity.
  for (std::size_t k = 0; k < i; ++k) t.exceptions += cells[k].second ? 1 : 0;
  return t;
}

int region_rank(sim::Region region) {
  if (const auto rank = rank_of(region)) return *rank;
  throw Error(fmt::format("region '{}' is not G, Y, O or R", core::enum_name(region)));
}

bool BoundarySlice::holds(const campaign::CellRecord& cell) const noexcept {
  const auto values = cell.factors.values();
  return cell.grid == grid && values.size() == sim::kTtcFactor + 1 + held.size() &&
         std::equal(held.begin(), held.end(), values.begin() + sim::kTtcFactor + 1);
}

std::size_t BoundaryReport::non_monotone() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(rows.begin(), rows.end(), [](const BoundaryRow& r) { return r.threshold.exceptions > 0; }));
}

BoundaryReport compute_boundaries(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                                  const std::optional<sim::ActuationConfig>& actuation) {
  BoundaryReport report;
  report.actuation = actuation;
  report.factors = factors;
  const std::vector<std::string> strategies = strategy_names_of(records);
  for (const auto& b : kRegionBoundaries) report.boundaries.emplace_back(b.name);
  for (const auto& s : strategies) report.boundaries.push_back("strategy:" + s);
  for (const auto& grid : grid_names(records)) {
    std::vector<const campaign::CellRecord*> cells;
    for (const auto& r : records)
      if (r.grid == grid) cells.push_back(&r);
    add_grid(grid, cells, strategies, report);
  }
  return report;
}

std::string boundary_csv(const BoundaryReport& report) {
  std::vector<core::Row> rows;
  for (const auto& r : report.rows) {
    core::Row row{r.grid};
    for (const double v : r.held) row.push_back(fmt::format("{:.9g}", v));
    row.insert(row.end(), {r.boundary, fmt::format("{:.9g}", r.speed_kph), optional_ttc(r.threshold.below),
                           optional_ttc(r.threshold.at), std::to_string(r.threshold.exceptions),
                           std::to_string(r.threshold.cells)});
    rows.push_back(std::move(row));
  }
  const sim::FactorTable& f = report.factors;
  core::Row header{"grid"};
  for (std::size_t i = sim::kTtcFactor + 1; i < f.size(); ++i) header.push_back(f[i].key);
  header.insert(header.end(),
                {"boundary", f[sim::kEgoSpeedFactor].key, "ttc_below_s", "ttc_at_s", "exceptions", "cells_used"});
  return core::csv_table(header, rows);
}

std::string analytic_stop_csv(const BoundaryReport& report) {
  std::vector<core::Row> rows;
  for (const auto& a : report.analytic)
    rows.push_back({a.grid, fmt::format("{:.9g}", a.mu), fmt::format("{:.9g}", a.speed_kph),
                    fmt::format("{:.6f}", a.stopping_distance_m), fmt::format("{:.6f}", a.ttc_s)});
  const sim::FactorTable& f = report.factors;
  return core::csv_table(
      {"grid", f[sim::kFrictionFactor].key, f[sim::kEgoSpeedFactor].key, "stopping_distance_m", f[sim::kTtcFactor].key},
      rows);
}

std::vector<std::filesystem::path> write_boundary_files(const std::filesystem::path& out_dir,
                                                        const BoundaryReport& report) {
  const std::vector<core::FileContent> files{{out_dir / "boundary.csv", boundary_csv(report)},
                                             {out_dir / "analytic_stop.csv", analytic_stop_csv(report)}};
  core::write_files(files);
  return {files[0].path, files[1].path};
}

std::string summary(const BoundaryReport& report) {
  std::string out = fmt::format("{} with boundaries ({}), {}\n", core::counted(report.grids.size(), "grid", "grids"),
                                core::join(report.grids, ", "),
                                core::counted(report.skipped.size(), "grid skipped", "grids skipped"));
  for (const auto& s : report.skipped)
    out += fmt::format("  grid '{}' skipped: {} (a boundary needs at least 2)\n", s.grid,
                       core::counted(s.ttc_levels, "TTC level", "TTC levels"));
  out += fmt::format("{} ({}) in {}; {} written ({})\n", core::counted(report.lines, "line", "lines"),
                     line_factors(report.factors), core::counted(report.slices.size(), "slice", "slices"),
                     core::counted(report.rows.size(), "boundary", "boundaries"), core::join(report.boundaries, ", "));
  const std::size_t odd = report.non_monotone();
  out += odd == 0 ? std::string("every line is monotone in TTC\n")
                  : fmt::format("{} not monotone in TTC: a cell below the threshold passes (column exceptions)\n",
                                core::counted(odd, "boundary line is", "boundary lines are"));
  return out;
}

}  // namespace emrm::results
