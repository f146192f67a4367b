#include "emrm/report/figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>
#include <utility>

#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/strategy.hpp"
#include "figure_parts.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;
using detail::Axis;
using detail::distinct_values;
using detail::kSameValue;
using detail::strategy_colour;
using detail::strategy_label;
using detail::write_csv;

/// The strategies of `records` in evaluation order, then any other in order of first appearance.
std::vector<std::string> ordered_strategies(const std::vector<CellRecord>& records) {
  const auto seen = results::strategy_names_of(records);
  std::vector<std::string> out;
  for (const auto& name : sim::strategy_names())
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) out.push_back(name);
  for (const auto& name : seen)
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  return out;
}

// The baseline is dashed in the sweep curves: in print its grey is then still told apart.
bool is_baseline(std::string_view strategy) {
  const sim::StrategyTable registered = sim::registered_strategies();
  const sim::StrategyInfo* info = registered.info(strategy);
  return info != nullptr && info->role == sim::StrategyRole::kBaseline;
}

// An adaptive sweep's inferred cells have a region and no strategy outcome (docs/adaptive.md): a
// rate per strategy is over the simulated cells only, and its figure says so.
struct SimulatedShare {
  std::size_t feasible = 0, inferred = 0;
  [[nodiscard]] std::string caption() const {
    if (inferred == 0) return "";
    return fmt::format(
        " Per strategy over the {} simulated of the {} feasible cells only: an adaptive sweep inferred the other {} "
        "cells' regions and ran no strategy there, and the cells it simulates lie near the region boundaries, so "
        "these rates are not the grid's.",
        feasible - inferred, feasible, inferred);
  }
};
SimulatedShare simulated_share(const std::vector<CellRecord>& cells) {
  SimulatedShare share;
  for (const auto& c : cells) {
    share.feasible += c.feasible;
    share.inferred += c.inferred();
  }
  return share;
}

// A figure of one grid: named and titled, with the grid's cells; a note when the store lacks it.
std::vector<CellRecord> figure_of_grid(Figure& figure, std::string name, std::string title, std::string_view what,
                                       const std::vector<CellRecord>& records, const std::string& grid) {
  figure.name = std::move(name);
  figure.title = std::move(title);
  auto cells = results::records_of_grid(records, grid);
  if (cells.empty()) figure.note = fmt::format("no {}: no grid '{}' in the store", what, grid);
  return cells;
}

}  // namespace

// --- loss comparison --------------------------------------------------------------------------

Figure draw_loss_comparison(const std::vector<CellRecord>& records, const std::string& grid, const fs::path& dir) {
  Figure figure;
  const auto cells = figure_of_grid(figure, "loss_comparison", fmt::format("Loss comparison on grid '{}'", grid),
                                    "loss comparison", records, grid);
  if (cells.empty()) return figure;
  const auto strategies = ordered_strategies(cells);
  std::vector<core::Row> rows;
  std::vector<std::string> lines, tics;
  std::size_t feasible = 0;
  for (const auto& strategy : strategies) {
    const auto k = results::strategy_kpis(cells, strategy, grid);
    if (k.cells == 0) continue;
    feasible = std::max(feasible, k.cells);
    core::Row row{strategy, std::to_string(k.cells), plot_percent(k.collision_avoidance_rate_pct),
                  plot_percent(k.mean_impact_speed_kph)};
    lines.push_back(
        fmt::format("{} {} {} {}", rows.size(), row[2], row[3], rgb_value(strategy_colour(strategy, strategies))));
    tics.push_back(fmt::format("{} {}", single_quoted(strategy_label(strategy)), rows.size()));
    rows.push_back(std::move(row));
  }
  if (rows.empty()) {
    figure.note = fmt::format("no loss comparison: grid '{}' has no feasible cell with a strategy outcome", grid);
    return figure;
  }
  const SimulatedShare share = simulated_share(cells);
  figure.title = fmt::format(
      "Loss comparison over the {} {} cells of grid '{}'. Left: collision-avoidance rate per strategy; "
      "right: mean residual impact speed (0 km/h for an avoided cell).{}",
      feasible, share.inferred == 0 ? "feasible" : "simulated", grid, share.caption());
  write_csv(figure, dir, {"strategy", "cells", "collision_avoidance_rate_pct", "mean_impact_speed_kph"}, rows);

  const std::string xtics = fmt::format("set xtics ({}) noenhanced rotate by -20\n", core::join(tics, ", "));
  const double n = static_cast<double>(rows.size());
  std::string body = fmt::format(
      "set multiplot layout 1,2 title {} font ',16'\n"
      "set style fill solid 0.9 border rgb 'black'\nset boxwidth 0.65\nset tics out nomirror\nset border 3\n"
      "set key off\nset grid ytics lc rgb '#dddddd'\nset xrange [-0.6:{}]\nset bmargin 5\n{}",
      single_quoted(fmt::format("Loss comparison, grid '{}' ({} {} cells)", enhanced_literal(grid), feasible,
                                share.inferred == 0 ? "feasible" : "simulated")),
      plot_number(n - 0.4), xtics);
  body +=
      "set title 'Collision avoidance'\nset ylabel 'collision-avoidance rate (%)'\nset yrange [0:100]\n"
      "set ytics 0,20,100\n"
      "plot $loss using 1:2:4 with boxes lc rgb variable, "
      "$loss using 1:2:(sprintf('%.1f', $2)) with labels offset 0,0.8\n";
  body +=
      "set title 'Residual impact speed'\nset ylabel 'mean residual impact speed (km/h)'\n"
      "set yrange [0:*]\nset ytics autofreq\nset offsets 0,0,graph 0.1,0\n"
      "plot $loss using 1:3:4 with boxes lc rgb variable, "
      "$loss using 1:3:(sprintf('%.1f', $3)) with labels offset 0,0.8\n"
      "unset multiplot\n";
  render_png_and_svg(figure.png, figure.svg, datablock("loss", lines), body, 1400, 650, 13);
  return figure;
}

// --- sweep curves -----------------------------------------------------------------------------

namespace {

/// One point of each strategy's curve: where it sits on the x axis, its leading CSV columns and the
/// cells it is the rate over.
struct SweepPoint {
  double x = 0.0;
  core::Row key;
  std::vector<CellRecord> cells;
};

/// The rows of the regions' curve (sweep curves over inferred cells): named in the CSV and the key.
constexpr std::string_view kByRegion = "regions_every_cell";
constexpr std::string_view kByRegionLabel = "every cell by its region (G or Y; not R)";

/// The x axis of the sweep: its label and range, the tics when it is categorical, the multiplot's title.
struct SweepAxis {
  std::string label, tics, title;
  double lo = 0.0, hi = 0.0;
};

/// Draws the curves of `points` into `figure` (its name and caption set by the caller): one row per
/// point and strategy with a feasible cell, the CSV's columns `key_header` then strategy, cells and
/// the two rates. False, with nothing written, when no point has a feasible cell.
bool draw_curves(Figure& figure, const std::vector<SweepPoint>& points, const std::vector<CellRecord>& cells,
                 const std::string& grid, const core::Row& key_header, const SweepAxis& axis, const fs::path& dir) {
  const auto strategies = ordered_strategies(cells);
  std::vector<core::Row> rows;
  std::vector<std::vector<std::string>> per_strategy(strategies.size());
  // With inferred cells, beside the strategies' rates over the simulated cells, the regions' over
  // every feasible cell: avoided somehow (G, Y), and mitigated somehow (not R).
  const bool by_region = simulated_share(cells).inferred > 0;
  std::vector<std::string> region_points;
  for (const SweepPoint& point : points) {
    for (std::size_t s = 0; s < strategies.size(); ++s) {
      const auto k = results::strategy_kpis(point.cells, strategies[s], grid);
      if (k.cells == 0) continue;  // every cell of this point infeasible: no point, the line bridges it
      core::Row row = point.key;
      row.insert(row.end(), {strategies[s], std::to_string(k.cells), plot_percent(k.collision_avoidance_rate_pct),
                             plot_percent(k.mitigability_success_pct)});
      per_strategy[s].push_back(fmt::format("{} {} {}", plot_number(point.x), row[row.size() - 2], row.back()));
      rows.push_back(std::move(row));
    }
    const auto regions = results::count_regions(point.cells, grid);
    if (by_region && regions.feasible > 0) {
      core::Row row = point.key;
      row.insert(row.end(), {std::string(kByRegion), std::to_string(regions.feasible),
                             plot_percent(regions.pct(regions.g + regions.y)),
                             plot_percent(regions.pct(regions.g + regions.y + regions.o))});
      region_points.push_back(fmt::format("{} {} {}", plot_number(point.x), row[row.size() - 2], row.back()));
      rows.push_back(std::move(row));
    }
  }
  if (rows.empty()) return false;
  core::Row header = key_header;
  header.insert(header.end(), {"strategy", "cells", "collision_avoidance_rate_pct", "mitigability_success_pct"});
  write_csv(figure, dir, header, rows);

  std::string data;
  std::vector<std::string> car_plot, ms_plot, key;
  for (std::size_t s = 0; s < strategies.size(); ++s) {
    if (per_strategy[s].empty()) continue;
    const std::string block = fmt::format("sweep_{}", s);
    data += datablock(block, per_strategy[s]);
    const std::string style =
        fmt::format("lc rgb {} lw 2 pt {} ps 0.8 dt {}", single_quoted(strategy_colour(strategies[s], strategies)),
                    5 + 2 * (s % 5), is_baseline(strategies[s]) ? 2 : 1);
    car_plot.push_back(fmt::format("${} using 1:2 with linespoints {} notitle", block, style));
    ms_plot.push_back(fmt::format("${} using 1:3 with linespoints {} notitle", block, style));
    key.push_back(fmt::format("NaN with linespoints {} title {}", style, single_quoted(strategy_label(strategies[s]))));
  }
  if (!region_points.empty()) {
    data += datablock("sweep_regions", region_points);
    constexpr std::string_view kStyle = "lc rgb 'black' lw 3 pt 7 ps 0.6 dt 1";
    car_plot.push_back(fmt::format("$sweep_regions using 1:2 with linespoints {} notitle", kStyle));
    ms_plot.push_back(fmt::format("$sweep_regions using 1:3 with linespoints {} notitle", kStyle));
    key.push_back(fmt::format("NaN with linespoints {} title {}", kStyle, single_quoted(kByRegionLabel)));
  }
  const int key_rows = key.size() <= 4 ? 1 : 2;  // a long key wraps
  const double key_h = key_rows == 1 ? 0.08 : 0.13, top = 0.93;
  std::string body = fmt::format(
      "set multiplot title {} font ',16'\n"
      "set tics out nomirror\nset border 3\nset key off\nset grid lc rgb '#dddddd'\n"
      "set xrange [{}:{}]\nset yrange [-2:102]\nset ytics 0,20,100\nset xlabel {}\n{}",
      single_quoted(axis.title), plot_number(axis.lo), plot_number(axis.hi), single_quoted(axis.label), axis.tics);
  body += fmt::format(
      "set origin 0,{0}\nset size 0.5,{1}\nset title 'Collision avoidance'\n"
      "set ylabel 'collision-avoidance rate (%)'\nplot {2}\n",
      key_h, top - key_h, core::join(car_plot, ", "));
  body += fmt::format(
      "set origin 0.5,{0}\nset size 0.5,{1}\nset title 'Mitigability success'\n"
      "set ylabel 'mitigability success (%)'\nplot {2}\n",
      key_h, top - key_h, core::join(ms_plot, ", "));
  body += "set key on\n" + key_strip(key_h, key_rows, 0, key) + "unset multiplot\n";
  render_png_and_svg(figure.png, figure.svg, data, body, 1400, 650, 13);
  return true;
}

}  // namespace

Figure draw_sweep_curves(const std::vector<CellRecord>& records, const sim::FactorTable& factors,
                         const std::string& grid, const fs::path& dir) {
  Figure figure;
  const auto cells = figure_of_grid(figure, "sweep_curves", fmt::format("Parameter sweep over grid '{}'", grid),
                                    "sweep curves", records, grid);
  if (cells.empty()) return figure;
  const auto speeds = distinct_values(cells, Axis::kSpeed);
  std::vector<SweepPoint> points;
  for (const double speed : speeds) {
    SweepPoint& point = points.emplace_back(SweepPoint{speed, {plot_number(speed)}, {}});
    for (const auto& c : cells)
      if (std::abs(c.factors.ego_speed_kph() - speed) <= kSameValue) point.cells.push_back(c);
  }
  const sim::Factor& speed = factors[sim::kEgoSpeedFactor];
  const SweepAxis axis{speed.axis, "", fmt::format("Parameter sweep, grid '{}'", enhanced_literal(grid)),
                       speeds.front() - 1.0, speeds.back() + 1.0};
  if (!draw_curves(figure, points, cells, grid, {speed.key}, axis, dir)) {
    figure.note = fmt::format("no sweep curves: grid '{}' has no feasible cell with a strategy outcome", grid);
    return figure;
  }
  const SimulatedShare share = simulated_share(cells);
  figure.title = fmt::format(
      "Parameter sweep over grid '{}' ({} cells, {} ego speeds from {} to {} km/h), per strategy. Left: "
      "collision-avoidance rate; right: mitigability success (loss level below the unmitigated one), each over the "
      "feasible cells at that speed.{}",
      grid, cells.size(), speeds.size(), plot_number(speeds.front()), plot_number(speeds.back()), share.caption());
  if (share.inferred > 0)
    figure.title +=
        " The black line is over every feasible cell at that speed, inferred ones by their region: the share some "
        "strategy avoids (G or Y, left) and the share some strategy mitigates (not R, right).";
  return figure;
}

Figure draw_binned_sweep_curves(const std::vector<CellRecord>& cells, const std::vector<int>& levels,
                                const PlanFactor& factor, const fs::path& dir, const std::string& name) {
  Figure figure;
  figure.name = name;
  figure.title = fmt::format("Parameter sweep of the planned run by the ODD's bins of {}", factor.name);
  std::vector<SweepPoint> points;
  std::vector<std::string> tics;
  for (std::size_t k = 0; k < factor.levels.size(); ++k) {
    const std::string& label = factor.levels[k];
    SweepPoint& point = points.emplace_back(SweepPoint{static_cast<double>(k), {std::to_string(k), label}, {}});
    for (std::size_t i = 0; i < cells.size() && i < levels.size(); ++i)
      if (levels[i] == static_cast<int>(k)) point.cells.push_back(cells[i]);
    tics.push_back(fmt::format("{} {}", single_quoted(label), k));
  }
  const std::string grid = cells.empty() ? std::string() : cells.front().grid;
  const SweepAxis axis{enhanced_literal(plan_factor_label(factor)),
                       fmt::format("set xtics ({}) noenhanced\n", core::join(tics, ", ")),
                       fmt::format("Parameter sweep by the ODD's bins of {}", enhanced_literal(factor.name)), -0.5,
                       static_cast<double>(factor.levels.size()) - 0.5};
  if (!draw_curves(figure, points, cells, grid, {"level", "bin"}, axis, dir)) {
    figure.note = "no sweep curves: the planned run has no feasible scenario with a strategy outcome";
    return figure;
  }
  figure.title = fmt::format(
      "Parameter sweep of the planned run ({} scenarios) by the ODD's {} bins of {} ({}), per strategy. Left: "
      "collision-avoidance rate; right: mitigability success (loss level below the unmitigated one), each over the "
      "feasible scenarios in that bin (a bin without one has no point).",
      cells.size(), factor.levels.size(), factor.name, core::join(factor.levels, ", "));
  return figure;
}

std::string plan_factor_label(const PlanFactor& factor) {
  return factor.unit.empty() || factor.unit == "1" ? factor.name : fmt::format("{} ({})", factor.name, factor.unit);
}

// --- coverage comparison ----------------------------------------------------------------------

Figure draw_coverage_comparison(const std::vector<scenario::CoverageReport>& reports, const fs::path& dir) {
  Figure figure;
  figure.name = "coverage_comparison";
  figure.title = "Coverage comparison";
  if (reports.empty()) {
    figure.note = "no coverage comparison: the coverage report has neither a plan nor a baseline";
    return figure;
  }
  const auto percent_of = [](const scenario::CoverageCount& c) { return plot_percent(100.0 * c.fraction()); };
  std::vector<core::Row> rows;
  std::vector<std::string> lines, tics;
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const scenario::CoverageReport& r = reports[i];
    const std::string scenarios = std::to_string(r.scenarios);
    rows.push_back({r.name, scenarios, percent_of(r.hazards), percent_of(r.malfunctions), percent_of(r.transitions),
                    percent_of(r.cells), percent_of(r.twise)});
    const auto& row = rows.back();
    lines.push_back(fmt::format("{} {} {} {}", i, row[2], row[3], row[5]));
    tics.push_back(fmt::format("{} {}", double_quoted(r.name + "\n(" + scenarios + " scenarios)"), i));
  }
  figure.title = fmt::format(
      "Coverage comparison of the scenario plan and {} baseline method(s): hazard, UCA and ODD-cell coverage (%), "
      "each measured by the same checker.",
      reports.size() - 1);
  write_csv(figure, dir, {"method", "scenarios", "hazard_pct", "uca_pct", "transition_pct", "cell_pct", "twise_pct"},
            rows);

  constexpr std::array<std::pair<std::string_view, std::string_view>, 3> kSeries{
      {{"hazard coverage", "#4c72b0"}, {"UCA coverage", "#dd8452"}, {"cell coverage", "#55a868"}}};
  constexpr double kWidth = 0.26;
  std::string plot;
  for (std::size_t s = 0; s < kSeries.size(); ++s) {
    const double shift = (static_cast<double>(s) - 1.0) * kWidth;
    plot += fmt::format(
        "$coverage using ($1+{0}):{1} with boxes lc rgb {2} title {3}, "
        "$coverage using ($1+{0}):{1}:(pct_label(${1})) with labels offset 0,0.7 font ',11' notitle",
        plot_number(shift), s + 2, single_quoted(kSeries[s].second), single_quoted(kSeries[s].first));
    plot += s + 1 < kSeries.size() ? ", " : "\n";
  }
  const double n = static_cast<double>(reports.size());
  std::string body = fmt::format(
      "set title 'Coverage comparison' font ',16' offset 0,1\n"
      "pct_label(v) = v == floor(v) ? sprintf('%.0f', v) : sprintf('%.1f', v)\n"
      "set style fill solid 0.9 border rgb 'black'\nset boxwidth {}\nset tics out nomirror\nset border 3\n"
      "set grid ytics lc rgb '#dddddd'\nset key below center horizontal reverse Left samplen 2.5 width 2\n"
      "set xrange [-0.6:{}]\nset yrange [0:100]\nset ytics 0,20,100\nset ylabel 'coverage (%)'\n"
      "set xtics ({}) noenhanced\nset bmargin 5\nplot {}",
      plot_number(kWidth * 0.95), plot_number(n - 0.4), core::join(tics, ", "), plot);
  render_png_and_svg(figure.png, figure.svg, datablock("coverage", lines), body, 1200, 700, 13);
  return figure;
}

// --- traceability matrix ----------------------------------------------------------------------

Figure draw_traceability(const std::vector<safety::TraceRow>& rows, const fs::path& dir) {
  Figure figure;
  figure.name = "traceability_matrix";
  figure.title = "Traceability matrix";
  if (rows.empty()) {
    figure.note = "no traceability matrix: the safety case has no (UCA, hazard) link";
    return figure;
  }
  struct Link {
    std::string uca, hazard;
    std::vector<std::string> losses, scenarios;
  };
  std::vector<std::string> ucas, hazards;
  std::vector<Link> links;
  const auto add_unique = [](std::vector<std::string>& to, const std::string& s) {
    if (std::find(to.begin(), to.end(), s) == to.end()) to.push_back(s);
  };
  for (const auto& r : rows) {
    add_unique(ucas, r.uca);
    add_unique(hazards, r.hazard);
    auto it =
        std::find_if(links.begin(), links.end(), [&](const Link& l) { return l.uca == r.uca && l.hazard == r.hazard; });
    if (it == links.end()) it = links.insert(links.end(), Link{r.uca, r.hazard, {}, {}});
    if (!r.loss.empty()) add_unique(it->losses, r.loss);
    for (const auto& s : r.scenarios) add_unique(it->scenarios, s);
  }
  std::vector<core::Row> csv_rows;
  std::vector<std::string> lines;
  std::size_t most = 0, traced = 0;
  for (const auto& l : links) {
    const auto col = std::find(hazards.begin(), hazards.end(), l.hazard) - hazards.begin();
    const auto row = std::find(ucas.begin(), ucas.end(), l.uca) - ucas.begin();
    csv_rows.push_back({l.uca, l.hazard, core::join(l.losses, " "), std::to_string(l.scenarios.size())});
    lines.push_back(fmt::format("{} {} {}", col, row, csv_rows.back()[3]));
    most = std::max(most, l.scenarios.size());
    if (!l.scenarios.empty()) ++traced;
  }
  figure.title = fmt::format(
      "Traceability matrix: {} UCAs (rows) × {} hazards (columns). Each of the {} linked pairs shows the number of "
      "scenarios tracing to it ({} with at least one); blank pairs are not linked.",
      ucas.size(), hazards.size(), links.size(), traced);
  write_csv(figure, dir, {"uca", "hazard", "losses", "scenarios"}, csv_rows);

  const auto tic_list = [](const std::vector<std::string>& names) {
    std::vector<std::string> t;
    for (std::size_t i = 0; i < names.size(); ++i) t.push_back(fmt::format("{} {}", single_quoted(names[i]), i));
    return core::join(t, ", ");
  };
  std::size_t longest = 0;
  for (const auto& h : hazards) longest = std::max(longest, h.size());
  const int width = std::clamp(320 + 90 * static_cast<int>(hazards.size()), 800, 2000);
  const int height = std::clamp(220 + 55 * static_cast<int>(ucas.size()), 450, 1800);
  std::string body = fmt::format(
      "set title 'Traceability: scenarios per (UCA, hazard) link' font ',16'\n"
      "set xrange [-0.5:{}]\nset yrange [{}:-0.5]\nset tics scale 0\n"
      "set xtics ({}) noenhanced{}\nset ytics ({}) noenhanced\n"
      "set xlabel 'hazard'\nset ylabel 'unsafe control action'\nset key off\n"
      "set palette defined (0 '#f7fbff', 1 '#9ecae1', 2 '#4292c6')\nset cbrange [0:{}]\n"
      "set cblabel 'scenarios tracing to the link' offset 2,0\nset cbtics {} out\nset format cb '%.0f'\n"
      "set for [i=0:{}] arrow from first i+0.5,graph 0 to first i+0.5,graph 1 nohead lc rgb '#e0e0e0' back\n"
      "set for [j=0:{}] arrow from graph 0,first j+0.5 to graph 1,first j+0.5 nohead lc rgb '#e0e0e0' back\n"
      "plot $trace using 1:2:(0.46):(0.46):3 with boxxyerror fs solid 1.0 border lc rgb '#525252' lc palette, "
      "$trace using 1:2:(sprintf('%d', $3)) with labels font ',13'\n",
      plot_number(static_cast<double>(hazards.size()) - 0.5), plot_number(static_cast<double>(ucas.size()) - 0.5),
      tic_list(hazards), longest > 6 ? " rotate by -30" : "", tic_list(ucas), std::max<std::size_t>(most, 1),
      std::max<std::size_t>(1, (most + 9) / 10), static_cast<int>(hazards.size()) - 2,
      static_cast<int>(ucas.size()) - 2);
  render_png_and_svg(figure.png, figure.svg, datablock("trace", lines), body, width, height, 13);
  return figure;
}

}  // namespace emrm::report
