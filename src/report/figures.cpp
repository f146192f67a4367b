#include "emrm/report/figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string_view>
#include <utility>

#include "emrm/campaign/aggregate.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/sim/strategy.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;

// Colours for strategies the registry does not know (a store written with a strategy registered
// then): the registered ones keep their record's colour in every figure.
constexpr std::array<std::string_view, 5> kExtraColours{"#8c564b", "#e377c2", "#17becf", "#bcbd22", "#d62728"};

struct RegionStyle {
  std::string_view region;
  std::string_view colour;
  std::string_view label;
};
constexpr std::array<RegionStyle, 5> kRegions{{
    {"G", "#2ca02c", "G fully avoidable"},
    {"Y", "#ffdd57", "Y aggressive avoidance required"},
    {"O", "#ff7f0e", "O mitigatable"},
    {"R", "#d62728", "R not mitigatable"},
    {"infeasible", "#bdbdbd", "infeasible"},
}};

// Grid values such as 0.25 + 7·0.06 are a few ulps off their decimal; they are one value.
constexpr double kSameValue = 1e-9;

std::string strategy_label(std::string_view strategy) {
  const sim::StrategyTable registered = sim::registered_strategies();
  if (const sim::StrategyInfo* info = registered.info(strategy)) return info->label;
  std::string out(strategy);
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

/// The strategies of `records` in evaluation order, then any other in order of first appearance.
std::vector<std::string> ordered_strategies(const std::vector<CellRecord>& records) {
  const auto seen = campaign::strategy_names_of(records);
  std::vector<std::string> out;
  for (const auto& name : sim::strategy_names())
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) out.push_back(name);
  for (const auto& name : seen)
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  return out;
}

std::string strategy_colour(std::string_view strategy, const std::vector<std::string>& strategies) {
  const sim::StrategyTable registered = sim::registered_strategies();
  if (const sim::StrategyInfo* info = registered.info(strategy)) return info->colour;
  std::size_t extra = 0;
  for (const auto& s : strategies) {
    if (s == strategy) break;
    if (registered.info(s) == nullptr) ++extra;
  }
  return std::string(kExtraColours[extra % kExtraColours.size()]);
}

// The baseline is dashed in the sweep curves: in print its grey is then still told apart.
bool is_baseline(std::string_view strategy) {
  const sim::StrategyTable registered = sim::registered_strategies();
  const sim::StrategyInfo* info = registered.info(strategy);
  return info != nullptr && info->role == sim::StrategyRole::kBaseline;
}

// --- files ------------------------------------------------------------------------------------

/// Gives the figure its paths in `dir` and writes its CSV.
void write_csv(Figure& figure, const fs::path& dir, const core::Row& header, const std::vector<core::Row>& rows) {
  figure.csv = dir / (figure.name + ".csv");
  figure.png = dir / (figure.name + ".png");
  figure.svg = dir / (figure.name + ".svg");
  core::write_file(figure.csv, core::csv_table(header, rows));
}

// --- the mitigability map -----------------------------------------------------------------------

enum class Axis { kSpeed, kTtc, kMu };

double value_of(const CellRecord& r, Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return r.speed_kph;
    case Axis::kTtc:
      return r.ttc_s;
    case Axis::kMu:
      return r.mu;
  }
  return 0.0;
}

std::string_view axis_label(Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return "ego speed (km/h)";
    case Axis::kTtc:
      return "time to collision TTC (s)";
    case Axis::kMu:
      return "road friction μ (–)";
  }
  return "";
}

std::string_view axis_plural(Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return "speeds";
    case Axis::kTtc:
      return "TTCs";
    case Axis::kMu:
      return "μ";
  }
  return "";
}

std::vector<double> distinct_values(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end(), [](double x, double y) { return std::abs(x - y) <= kSameValue; }), v.end());
  return v;
}

/// Half the smallest step between distinct values: the half-width of a cell's rectangle.
double half_step(const std::vector<double>& values, Axis a) {
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  if (std::isfinite(step)) return step / 2.0;
  return a == Axis::kSpeed ? 1.0 : 0.05;  // a single value: a band of a plausible width
}

double median_of(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

struct PanelSpec {
  char letter;
  std::string grid;
  Axis x, y, fixed;
  std::string_view name;  ///< "Speed × TTC, coarse grid"
};

std::string region_of(const CellRecord& r) { return r.feasible ? r.region : std::string("infeasible"); }

std::string region_colour(std::string_view region) {
  for (const auto& s : kRegions)
    if (s.region == region) return std::string(s.colour);
  return std::string(kRegions.back().colour);
}

std::string fixed_text(Axis a, double v) {
  switch (a) {
    case Axis::kSpeed:
      return fmt::format("v = {} km/h", plot_number(v));
    case Axis::kTtc:
      return fmt::format("TTC = {} s", plot_number(v));
    case Axis::kMu:
      return fmt::format("μ = {}", plot_number(v));
  }
  return "";
}

/// The dashed analytic stop boundary TTC = L + v/(2μg) as a gnuplot function of the panel's x.
std::string boundary_function(const PanelSpec& p, double fixed, double latency_s) {
  const double two_g = 2.0 * sim::kGravity_mps2;
  if (p.x == Axis::kSpeed && p.y == Axis::kTtc)
    return fmt::format("({} + x/3.6/({}*{}))", plot_number(latency_s), plot_number(two_g), plot_number(fixed));
  if (p.x == Axis::kSpeed && p.y == Axis::kMu) {
    if (fixed <= latency_s) return "";  // nothing stops within the latency alone
    return fmt::format("(x/3.6/({}*({} - {})))", plot_number(two_g), plot_number(fixed), plot_number(latency_s));
  }
  // TTC × μ at a fixed speed: μ = v / (2 g (TTC − L)), defined right of the latency.
  return fmt::format("(x > {1} ? {0}/3.6/({2}*(x - {1})) : NaN)", plot_number(fixed), plot_number(latency_s), plot_number(two_g));
}

}  // namespace

Figure draw_mitigability_map(const std::vector<CellRecord>& records, const fs::path& dir, const MapPanels& panels,
                             double latency_s) {
  Figure figure;
  figure.name = "mitigability_map";
  figure.title = "Mitigability regions";  // replaced by the full caption once drawn
  const std::array<PanelSpec, 4> specs{{
      {'a', panels.coarse, Axis::kSpeed, Axis::kTtc, Axis::kMu, "Speed × TTC, coarse grid"},
      {'b', panels.fine, Axis::kSpeed, Axis::kTtc, Axis::kMu, "Speed × TTC, fine grid"},
      {'c', panels.speed_mu, Axis::kSpeed, Axis::kMu, Axis::kTtc, "Speed × friction"},
      {'d', panels.ttc_mu, Axis::kTtc, Axis::kMu, Axis::kSpeed, "TTC × friction"},
  }};

  std::vector<core::Row> rows;
  std::vector<std::string> missing, caption_parts;
  std::string data, panel_plots, missing_labels;
  std::size_t total_cells = 0;
  // Panels sit in a fixed 2×2 layout above a key strip; a missing panel leaves its slot with a label.
  const double key_h = 0.06, top = 0.955, cell_h = (top - key_h) / 2.0;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const PanelSpec& p = specs[i];
    const double origin_x = i % 2 == 0 ? 0.0 : 0.5;
    const double origin_y = i < 2 ? key_h + cell_h : key_h;
    const auto cells = campaign::records_of_grid(records, p.grid);
    if (cells.empty()) {
      missing.push_back(fmt::format("no grid '{}' in the store: panel ({}) left out", p.grid, p.letter));
      missing_labels += fmt::format("set label {} {} at screen {},{} center\n", 90 + i,
                                    single_quoted(fmt::format("({}) {}: no grid '{}' in the store", p.letter, p.name,
                                                       enhanced_literal(p.grid))),
                                    origin_x + 0.25, origin_y + cell_h / 2.0);
      continue;
    }
    total_cells += cells.size();
    const auto regions = campaign::count_regions(records, p.grid);  // throws on a corrupt region
    const auto xs = distinct_values(cells, p.x), ys = distinct_values(cells, p.y);
    const double hx = half_step(xs, p.x), hy = half_step(ys, p.y);
    const double fixed = median_of(cells, p.fixed);

    std::vector<std::string> lines;
    for (const auto& c : cells) {
      core::Row row{std::string(1, p.letter), c.grid,          plot_number(c.speed_kph), plot_number(c.ttc_s),
                    plot_number(c.mu),             plot_number(c.passage_m), region_of(c)};
      const std::string& x = p.x == Axis::kSpeed ? row[2] : row[3];
      const std::string& y = p.y == Axis::kTtc ? row[3] : row[4];
      lines.push_back(fmt::format("{} {} {} {} {}", x, y, plot_number(hx), plot_number(hy), rgb_value(region_colour(row[6]))));
      rows.push_back(std::move(row));
    }
    const std::string block = fmt::format("map_{}", p.letter);
    data += datablock(block, lines);

    const auto share = [&](std::size_t n) { return fmt::format("{:.1f} %", regions.pct(n)); };
    const std::string shares =
        regions.feasible == 0
            ? std::string("no feasible cell")
            : fmt::format("G {}, Y {}, O {}, R {} of {} feasible", share(regions.g), share(regions.y),
                          share(regions.o), share(regions.r), regions.feasible);
    const std::string title =
        fmt::format("({}) {}: {} {} × {} {}, {} ({} cells)", p.letter, p.name, xs.size(), axis_plural(p.x), ys.size(),
                    axis_plural(p.y), fixed_text(p.fixed, fixed), cells.size());
    caption_parts.push_back(fmt::format("({}) {}, {} {} × {} {}, {} ({} cells; {})", p.letter, p.name, xs.size(),
                                        axis_plural(p.x), ys.size(), axis_plural(p.y), fixed_text(p.fixed, fixed),
                                        cells.size(), shares));

    panel_plots += fmt::format("set origin {},{}\nset size 0.5,{}\n", origin_x, origin_y, cell_h);
    panel_plots += fmt::format("set title {}\n", double_quoted(enhanced_literal(title) + "\n{/*0.8 " + enhanced_literal(shares) + "}"));
    panel_plots += fmt::format("set xlabel {}\nset ylabel {}\n", single_quoted(axis_label(p.x)), single_quoted(axis_label(p.y)));
    panel_plots += fmt::format("set xrange [{}:{}]\nset yrange [{}:{}]\n", plot_number(xs.front() - hx),
                               plot_number(xs.back() + hx), plot_number(ys.front() - hy), plot_number(ys.back() + hy));
    // Neighbours overlap by 3 % of a cell so that antialiased edges leave no seams between them.
    panel_plots += fmt::format(
        "plot ${} using 1:2:($3*1.03):($4*1.03):5 with boxxyerror fs solid 1.0 noborder lc rgb variable notitle", block);
    const std::string boundary = boundary_function(p, fixed, latency_s);
    if (!boundary.empty()) panel_plots += ", " + boundary + " with lines dt 2 lw 2.5 lc rgb 'black' notitle";
    panel_plots += "\n";
  }

  if (rows.empty()) {
    figure.note = fmt::format("no mitigability map: none of the grids '{}', '{}', '{}', '{}' is in the store",
                              panels.coarse, panels.fine, panels.speed_mu, panels.ttc_mu);
    return figure;
  }
  figure.note = core::join(missing, "; ");
  const std::string boundary_text =
      latency_s == 0.0 ? std::string("TTC = v/(2μg)") : fmt::format("TTC = {} s + v/(2μg)", plot_number(latency_s));
  figure.title = fmt::format(
      "Mitigability regions over {} simulated cells: {}. Each rectangle is one cell: G (green) fully avoidable, "
      "Y (yellow) aggressive avoidance required, O (orange) mitigatable, R (red) not mitigatable, grey infeasible. "
      "Dashed: the analytic stop boundary {} (g = {} m/s²) at the panel's fixed parameter.",
      total_cells, core::join(caption_parts, "; "), boundary_text, plot_number(sim::kGravity_mps2));
  write_csv(figure, dir, {"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region"}, rows);

  std::string body = fmt::format(
      "set multiplot title {} font ',16'\n"
      "set samples 600\nset tics out nomirror\nset border 3\nset key off\n",
      single_quoted(fmt::format("Mitigability regions ({} cells)", total_cells)));
  body += panel_plots;
  std::vector<std::string> key;
  for (const auto& s : kRegions)
    key.push_back(fmt::format("NaN with boxes fs solid 1.0 lc rgb {} title {}", single_quoted(s.colour), single_quoted(s.label)));
  key.push_back(fmt::format("NaN with lines dt 2 lw 2.5 lc rgb 'black' title {}",
                            single_quoted("stop boundary " + boundary_text)));
  body += "set key on\n" + key_strip(key_h, 2, -6, key, missing_labels) + "unset multiplot\n";
  render_png_and_svg(figure.png, figure.svg, data, body, 1400, 1000, 13);
  return figure;
}

// --- loss comparison --------------------------------------------------------------------------

Figure draw_loss_comparison(const std::vector<CellRecord>& records, const std::string& grid, const fs::path& dir) {
  Figure figure;
  figure.name = "loss_comparison";
  figure.title = fmt::format("Loss comparison on grid '{}'", grid);
  const auto cells = campaign::records_of_grid(records, grid);
  if (cells.empty()) {
    figure.note = fmt::format("no loss comparison: no grid '{}' in the store", grid);
    return figure;
  }
  const auto strategies = ordered_strategies(cells);
  std::vector<core::Row> rows;
  std::vector<std::string> lines, tics;
  std::size_t feasible = 0;
  for (const auto& strategy : strategies) {
    const auto k = campaign::strategy_kpis(cells, strategy, grid);
    if (k.cells == 0) continue;
    feasible = std::max(feasible, k.cells);
    core::Row row{strategy, std::to_string(k.cells), plot_percent(k.collision_avoidance_rate_pct),
                  plot_percent(k.mean_impact_speed_kph)};
    lines.push_back(fmt::format("{} {} {} {}", rows.size(), row[2], row[3], rgb_value(strategy_colour(strategy, strategies))));
    tics.push_back(fmt::format("{} {}", single_quoted(strategy_label(strategy)), rows.size()));
    rows.push_back(std::move(row));
  }
  if (rows.empty()) {
    figure.note = fmt::format("no loss comparison: grid '{}' has no feasible cell with a strategy outcome", grid);
    return figure;
  }
  figure.title = fmt::format(
      "Loss comparison over the {} feasible cells of grid '{}'. Left: collision-avoidance rate per strategy; "
      "right: mean residual impact speed (0 km/h for an avoided cell).",
      feasible, grid);
  write_csv(figure, dir, {"strategy", "cells", "collision_avoidance_rate_pct", "mean_impact_speed_kph"}, rows);

  const std::string xtics = fmt::format("set xtics ({}) noenhanced rotate by -20\n", core::join(tics, ", "));
  const double n = static_cast<double>(rows.size());
  std::string body = fmt::format(
      "set multiplot layout 1,2 title {} font ',16'\n"
      "set style fill solid 0.9 border rgb 'black'\nset boxwidth 0.65\nset tics out nomirror\nset border 3\n"
      "set key off\nset grid ytics lc rgb '#dddddd'\nset xrange [-0.6:{}]\nset bmargin 5\n{}",
      single_quoted(fmt::format("Loss comparison, grid '{}' ({} feasible cells)", enhanced_literal(grid), feasible)),
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

Figure draw_sweep_curves(const std::vector<CellRecord>& records, const std::string& grid, const fs::path& dir) {
  Figure figure;
  figure.name = "sweep_curves";
  figure.title = fmt::format("Parameter sweep over grid '{}'", grid);
  const auto cells = campaign::records_of_grid(records, grid);
  if (cells.empty()) {
    figure.note = fmt::format("no sweep curves: no grid '{}' in the store", grid);
    return figure;
  }
  const auto strategies = ordered_strategies(cells);
  const auto speeds = distinct_values(cells, Axis::kSpeed);
  std::vector<core::Row> rows;
  std::vector<std::vector<std::string>> per_strategy(strategies.size());
  for (const double speed : speeds) {
    std::vector<CellRecord> at_speed;
    for (const auto& c : cells)
      if (std::abs(c.speed_kph - speed) <= kSameValue) at_speed.push_back(c);
    for (std::size_t s = 0; s < strategies.size(); ++s) {
      const auto k = campaign::strategy_kpis(at_speed, strategies[s], grid);
      if (k.cells == 0) continue;  // every cell at this speed infeasible: no point, the line bridges it
      core::Row row{plot_number(speed), strategies[s], std::to_string(k.cells), plot_percent(k.collision_avoidance_rate_pct),
                    plot_percent(k.mitigability_success_pct)};
      per_strategy[s].push_back(fmt::format("{} {} {}", row[0], row[3], row[4]));
      rows.push_back(std::move(row));
    }
  }
  if (rows.empty()) {
    figure.note = fmt::format("no sweep curves: grid '{}' has no feasible cell with a strategy outcome", grid);
    return figure;
  }
  figure.title = fmt::format(
      "Parameter sweep over grid '{}' ({} cells, {} ego speeds from {} to {} km/h), per strategy. Left: "
      "collision-avoidance rate; right: mitigability success (loss level below the unmitigated one), each over the "
      "feasible cells at that speed.",
      grid, cells.size(), speeds.size(), plot_number(speeds.front()), plot_number(speeds.back()));
  write_csv(figure, dir, {"speed_kph", "strategy", "cells", "collision_avoidance_rate_pct", "mitigability_success_pct"},
            rows);

  std::string data;
  std::vector<std::string> car_plot, ms_plot, key;
  for (std::size_t s = 0; s < strategies.size(); ++s) {
    if (per_strategy[s].empty()) continue;
    const std::string block = fmt::format("sweep_{}", s);
    data += datablock(block, per_strategy[s]);
    const std::string style = fmt::format("lc rgb {} lw 2 pt {} ps 0.8 dt {}",
                                          single_quoted(strategy_colour(strategies[s], strategies)), 5 + 2 * (s % 5),
                                          is_baseline(strategies[s]) ? 2 : 1);
    car_plot.push_back(fmt::format("${} using 1:2 with linespoints {} notitle", block, style));
    ms_plot.push_back(fmt::format("${} using 1:3 with linespoints {} notitle", block, style));
    key.push_back(fmt::format("NaN with linespoints {} title {}", style, single_quoted(strategy_label(strategies[s]))));
  }
  const double key_h = 0.08, top = 0.93;
  const double x_lo = speeds.front() - 1.0, x_hi = speeds.back() + 1.0;
  std::string body = fmt::format(
      "set multiplot title {} font ',16'\n"
      "set tics out nomirror\nset border 3\nset key off\nset grid lc rgb '#dddddd'\n"
      "set xrange [{}:{}]\nset yrange [-2:102]\nset ytics 0,20,100\nset xlabel 'ego speed (km/h)'\n",
      single_quoted(fmt::format("Parameter sweep, grid '{}'", enhanced_literal(grid))), plot_number(x_lo), plot_number(x_hi));
  body += fmt::format("set origin 0,{0}\nset size 0.5,{1}\nset title 'Collision avoidance'\n"
                      "set ylabel 'collision-avoidance rate (%)'\nplot {2}\n",
                      key_h, top - key_h, core::join(car_plot, ", "));
  body += fmt::format("set origin 0.5,{0}\nset size 0.5,{1}\nset title 'Mitigability success'\n"
                      "set ylabel 'mitigability success (%)'\nplot {2}\n",
                      key_h, top - key_h, core::join(ms_plot, ", "));
  body += "set key on\n" + key_strip(key_h, 1, 0, key) + "unset multiplot\n";
  render_png_and_svg(figure.png, figure.svg, data, body, 1400, 650, 13);
  return figure;
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
    plot += fmt::format("$coverage using ($1+{0}):{1} with boxes lc rgb {2} title {3}, "
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
    auto it = std::find_if(links.begin(), links.end(), [&](const Link& l) { return l.uca == r.uca && l.hazard == r.hazard; });
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
      std::max<std::size_t>(1, (most + 9) / 10), static_cast<int>(hazards.size()) - 2, static_cast<int>(ucas.size()) - 2);
  render_png_and_svg(figure.png, figure.svg, datablock("trace", lines), body, width, height, 13);
  return figure;
}

}  // namespace emrm::report
