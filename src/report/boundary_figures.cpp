// The boundary figures (docs/boundary.md): a slice's region map with its boundaries as step lines
// and the analytic stop boundary as a smooth one. Every line is drawn over a white halo so that it
// reads on any region colour; all step lines' halos come first, so that no halo hides a line that
// coincides with another (a strategy's often lies on a region boundary).

#include "emrm/report/boundary_figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "figure_parts.hpp"
#include "map_panels.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;
using detail::Axis;
using detail::distinct_values;
using results::BoundaryReport;
using results::BoundaryRow;
using results::BoundarySlice;

/// How one boundary's line is drawn: its colour, width and dashes, and its key label.
struct LineStyle {
  std::string colour;
  double width = 2.0;
  int dash = 1;
  std::string label;
};

constexpr std::string_view kStrategyPrefix = "strategy:";
constexpr int kAnalyticSamples = 120;
constexpr std::string_view kAnalyticColour = "#000000";
constexpr std::string_view kCircleStyle = "pt 6 ps 2 lw 2 lc rgb '#000000'";

/// The region boundaries in strong colours apart from the region fills, each narrower than the one
/// drawn before it so that coinciding boundaries show as nested stripes; the strategies' lines
/// narrower still, dashed in their registry colours: a strategy on a region boundary shows on it.
LineStyle style_of(const std::string& boundary, const std::vector<std::string>& strategies) {
  if (boundary == "stop") return {"#08306b", 6.0, 1, "stop: G above"};
  if (boundary == "avoid") return {"#c51b7d", 4.0, 1, "avoid: G or Y above"};
  if (boundary == "mitigate") return {"#00838f", 2.5, 1, "mitigate: G, Y or O above"};
  const std::string strategy = boundary.substr(kStrategyPrefix.size());
  const auto at = std::find(strategies.begin(), strategies.end(), strategy);
  const int dash = 2 + static_cast<int>(at - strategies.begin()) % 4;
  return {detail::strategy_colour(strategy, strategies), 1.8, dash,
          fmt::format("{} avoids above", detail::strategy_label(strategy))};
}

std::string line_spec(const LineStyle& s) {
  return fmt::format("lw {} dt {} lc rgb {}", s.width, s.dash, single_quoted(s.colour));
}

/// The white halo under a line.
std::string halo(const std::string& source, const LineStyle& s) {
  return fmt::format("{} with lines lw {} lc rgb '#ffffff' notitle", source, s.width + 2.5);
}

std::string line(const std::string& source, const LineStyle& s) {
  return fmt::format("{} with lines {} notitle", source, line_spec(s));
}

std::string key_entry(const LineStyle& s) {
  return fmt::format("NaN with lines {} title {}", line_spec(s), single_quoted(s.label));
}

/// Half the smallest step between `values`; `fallback` for a single value.
double half_step(const std::vector<double>& values, double fallback) {
  double step = INFINITY;
  for (std::size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  return std::isfinite(step) ? step / 2.0 : fallback;
}

/// Where a line's step is drawn: between the bracket's two levels, or half a step below t* when
/// every level passes; nothing when no level passes (a step at the top of the cells would read as
/// "passes above" over cells that are infeasible or absent) or the line had no cell.
std::optional<double> drawn_ttc(const BoundaryRow& r, double half_ttc_step) {
  const auto& t = r.threshold;
  if (!t.at) return std::nullopt;
  return t.below ? (*t.below + *t.at) / 2.0 : *t.at - half_ttc_step;
}

std::string optional_number(const std::optional<double>& x) { return x ? plot_number(*x) : std::string(); }

/// One slice's figure as it is being built: the overlay (its layers gathered apart: every halo
/// under every step line), the figure's CSV rows.
struct SliceDrawing {
  detail::OverlaidMap map;
  std::vector<std::string> halos, lines, circles;
  std::vector<core::Row> csv;
  int blocks = 0;
};

/// The step line of one boundary over the speeds `xs` (rows in speed order, one per speed) into a
/// datablock; a speed without a step breaks the line.
void add_step_line(SliceDrawing& d, const std::string& boundary, const std::vector<const BoundaryRow*>& rows,
                   const std::vector<double>& xs, double hx, double hy, const LineStyle& style) {
  std::vector<std::string> points, circles;
  bool any_step = false;
  for (const BoundaryRow* row : rows) {
    const BoundaryRow& r = *row;
    const auto at = std::lower_bound(xs.begin(), xs.end(), r.speed_kph - detail::kSameValue);
    const std::optional<double> y = drawn_ttc(r, hy);
    d.csv.push_back({boundary, plot_number(r.speed_kph), optional_number(r.threshold.below),
                     optional_number(r.threshold.at), optional_number(y), std::to_string(r.threshold.exceptions)});
    if (!y || at == xs.end()) {
      points.emplace_back();  // a blank line: gnuplot does not join across it
      continue;
    }
    any_step = true;
    const std::size_t k = static_cast<std::size_t>(at - xs.begin());
    const double left = k == 0 ? xs[k] - hx : (xs[k - 1] + xs[k]) / 2.0;
    const double right = k + 1 == xs.size() ? xs[k] + hx : (xs[k] + xs[k + 1]) / 2.0;
    points.push_back(fmt::format("{} {}", plot_number(left), plot_number(*y)));
    points.push_back(fmt::format("{} {}", plot_number(right), plot_number(*y)));
    if (r.threshold.exceptions > 0) circles.push_back(fmt::format("{} {}", plot_number(r.speed_kph), plot_number(*y)));
  }
  d.map.key.push_back(key_entry(style));
  if (!any_step) return;
  const std::string block = fmt::format("boundary_{}", d.blocks++);
  d.map.data += datablock(block, points);
  d.halos.push_back(halo("$" + block, style));
  d.lines.push_back(line("$" + block, style));
  if (circles.empty()) return;
  d.map.data += datablock(block + "_odd", circles);
  d.circles.push_back(fmt::format("${}_odd using 1:2 with points {} notitle", block, kCircleStyle));
}

/// The analytic stop boundary at the slice's μ, sampled across the speed axis.
void add_analytic_line(SliceDrawing& d, const BoundaryReport& report, double mu, const std::vector<double>& xs,
                       double hx) {
  d.map.layers = d.halos;
  d.map.layers.insert(d.map.layers.end(), d.lines.begin(), d.lines.end());
  d.map.layers.insert(d.map.layers.end(), d.circles.begin(), d.circles.end());
  if (!report.actuation) return;  // the family has none (sim::stop_boundary_applies)
  const double low = std::max(xs.front() - hx, 0.5 * xs.front());
  const double high = xs.back() + hx;
  std::vector<std::string> points;
  for (int i = 0; i <= kAnalyticSamples; ++i) {
    const double v = low + (high - low) * i / kAnalyticSamples;
    const double ttc = sim::stop_boundary_ttc_s(v, mu, *report.actuation);
    points.push_back(fmt::format("{} {}", plot_number(v), plot_number(ttc)));
    d.csv.push_back({"analytic_stop", plot_number(v), "", "", plot_number(ttc), ""});
  }
  d.map.data += datablock("analytic_stop", points);
  const LineStyle style{std::string(kAnalyticColour), 2.5, 2, "analytic stop boundary"};
  // On top of everything: the step lines are read against it.
  d.map.layers.push_back(halo("$analytic_stop", style));
  d.map.layers.push_back(line("$analytic_stop", style));
  d.map.key.push_back(key_entry(style));
}

// The slice's held factors (μ on) as a heading says them: "μ = 0.5, passage 3 m, truck 10 km/h".
std::string held_text(const sim::FactorTable& factors, const BoundarySlice& s) {
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < s.held.size(); ++i)
    parts.push_back(detail::fixed_text(factors, Axis{sim::kFrictionFactor + i}, s.held[i]));
  return core::join(parts, ", ");
}

/// "boundary_GRID", then "_FACTOR_VALUE" for each factor of the slice that varies over its grid.
std::string slice_stem(const sim::FactorTable& factors, const BoundarySlice& s,
                       const std::vector<CellRecord>& grid_cells) {
  std::string stem = "boundary_" + detail::file_stem(s.grid);
  for (std::size_t i = 0; i < s.held.size(); ++i) {
    const Axis a{sim::kFrictionFactor + i};
    if (distinct_values(grid_cells, a).size() > 1)
      stem += fmt::format("_{}_{}", detail::factor_of(factors, a).key, detail::file_stem(plot_number(s.held[i])));
  }
  return stem;
}

Figure draw_slice(const BoundaryReport& report, const BoundarySlice& slice, std::vector<CellRecord> cells,
                  const std::string& name, const fs::path& dir) {
  Figure figure;
  figure.name = name;
  SliceDrawing d;
  d.map.factors = report.factors;
  d.map.grid = slice.grid;
  d.map.held = held_text(report.factors, slice);
  d.map.title = fmt::format("Boundaries of grid '{}', {}", slice.grid, d.map.held);
  const std::vector<double> xs = distinct_values(cells, Axis::kSpeed);
  const double hx = half_step(xs, detail::factor_of(report.factors, Axis::kSpeed).band);
  const double hy = half_step(distinct_values(cells, Axis::kTtc), detail::factor_of(report.factors, Axis::kTtc).band);
  std::vector<std::string> strategies;  // the report's, for the colours of unregistered ones
  for (const auto& b : report.boundaries)
    if (b.rfind(kStrategyPrefix, 0) == 0) strategies.push_back(b.substr(kStrategyPrefix.size()));
  for (const auto& boundary : report.boundaries) {
    std::vector<const BoundaryRow*> rows;
    for (const auto& r : report.rows)
      if (r.boundary == boundary && r.grid == slice.grid && r.held == slice.held) rows.push_back(&r);
    if (!rows.empty()) add_step_line(d, boundary, rows, xs, hx, hy, style_of(boundary, strategies));
  }
  add_analytic_line(d, report, slice.held.front(), xs, hx);
  const bool non_monotone = !d.circles.empty();
  if (non_monotone)
    d.map.key.push_back(fmt::format("NaN with points {} title 'not monotone: a cell below passes'", kCircleStyle));
  d.map.cells = std::move(cells);

  detail::write_csv(figure, dir,
                    {"series", detail::factor_of(report.factors, Axis::kSpeed).key, "ttc_below_s", "ttc_at_s",
                     "drawn_ttc_s", "exceptions"},
                    d.csv);
  const detail::MapCaption caption = detail::draw_overlaid_map(figure, d.map);
  figure.title = fmt::format(
      "Boundaries of grid '{}': {} ({} cells; {}). Each rectangle is one cell in its region's colour. Each step "
      "line sits, at every speed, between the highest TTC level that fails and the lowest from which every level "
      "passes: the cells are G (stop), G or Y (avoid), G, Y or O (mitigate), or avoided by the strategy (dashed, "
      "in its colour); a speed where no level passes has no step.{}{}{}",
      slice.grid, caption.extent, d.map.cells.size(), caption.shares,
      report.actuation ? fmt::format(" Dashed black: the analytic stop boundary through the scene's actuators ({}).",
                                     report.actuation->summary())
                       : std::string(" The scene's family has no analytic stop boundary (docs/families.md)."),
      non_monotone ? " A circle marks a line that is not monotone in TTC: a cell below its threshold passes." : "",
      caption.evidence);
  return figure;
}

Figure undrawn_slices(const BoundaryReport& report, std::size_t drawn, const std::string& name) {
  Figure figure;
  figure.name = name;
  figure.title = "Boundaries, further slices";
  std::vector<std::string> left;
  for (std::size_t i = drawn; i < report.slices.size(); ++i)
    left.push_back(fmt::format("grid '{}' {}", report.slices[i].grid, held_text(report.factors, report.slices[i])));
  figure.note = fmt::format("{} slices; the first {} are drawn, these not: {}", report.slices.size(), drawn,
                            core::join(left, "; "));
  return figure;
}

}  // namespace

std::vector<Figure> draw_boundary_figures(const BoundaryReport& report, const std::vector<CellRecord>& records,
                                          const fs::path& dir, const BoundaryFigureOptions& options) {
  std::vector<Figure> figures;
  detail::StemSet stems;
  const std::size_t drawn = std::min(report.slices.size(), options.max_figures);
  for (std::size_t i = 0; i < drawn; ++i) {
    const BoundarySlice& slice = report.slices[i];
    const std::vector<CellRecord> grid_cells = results::records_of_grid(records, slice.grid);
    std::vector<CellRecord> cells;
    for (const auto& c : grid_cells)
      if (slice.holds(c)) cells.push_back(c);
    if (cells.empty()) continue;  // a report of other records
    figures.push_back(
        draw_slice(report, slice, std::move(cells), stems.unique(slice_stem(report.factors, slice, grid_cells)), dir));
  }
  if (drawn < report.slices.size()) figures.push_back(undrawn_slices(report, drawn, stems.unique("boundary_more")));
  return figures;
}

}  // namespace emrm::report
