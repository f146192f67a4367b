// The panel layout the maps share (docs/report.md): the paper's four grids as a 2×2 grid of
// panels, a panel's axes, heading and cell rectangles, the analytic stop boundary over it, and the
// multiplot with its key strip. How a cell is coloured is each map's own (region_maps.cpp,
// harm_reduction_map.cpp).

#include "map_panels.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "emrm/report/gnuplot.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::report::detail {

using campaign::CellRecord;

namespace {

/// Half the smallest step between distinct values: the half-width of a cell's rectangle.
double half_step(const std::vector<double>& values, const sim::Factor& factor) {
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  if (std::isfinite(step)) return step / 2.0;
  return factor.band;  // a single value: a band of a plausible width
}

double median_of(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

/// "(a) Speed × TTC, coarse grid", or the name alone for a map of one panel.
std::string panel_name(const MapPanel& p) {
  return p.lettered ? fmt::format("({}) {}", p.spec.letter, p.spec.name) : std::string(p.spec.name);
}

constexpr std::string_view kBoundaryStyle = "with lines dt 2 lw 2.5 lc rgb 'black'";

}  // namespace

std::string fixed_text(const sim::FactorTable& factors, Axis a, double v) {
  const sim::Factor& f = factor_of(factors, a);
  return fmt::format(fmt::runtime(f.held), value_label(f, v));
}

std::string value_label(const sim::Factor& factor, double v) {
  return factor.categorical() ? factor.value_text(v) : plot_number(v);
}

std::string region_of(const CellRecord& r) { return core::enum_text(r.feasible ? r.region : sim::Region::kInfeasible); }

std::string region_colour(std::string_view region) {
  for (const auto& s : kRegions)
    if (s.region == region) return std::string(s.colour);
  return std::string(kRegions.back().colour);
}

void fill_panel(MapPanel& p, std::vector<CellRecord> cells) {
  p.cells = std::move(cells);
  p.xs = distinct_values(p.cells, p.spec.x);
  p.ys = distinct_values(p.cells, p.spec.y);
  p.hx = half_step(p.xs, factor_of(p.factors, p.spec.x));
  p.hy = half_step(p.ys, factor_of(p.factors, p.spec.y));
  p.fixed = median_of(p.cells, p.spec.fixed);
  p.held = fixed_text(p.factors, p.spec.fixed, p.fixed);
}

void add_panel(MapLayout& layout, std::size_t i, const PanelSpec& spec, const std::vector<CellRecord>& records) {
  MapPanel p;
  p.spec = spec;
  p.factors = layout.factors;
  p.origin_x = i % 2 == 0 ? 0.0 : 0.5;
  p.origin_y = i < 2 ? layout.key_h + layout.cell_h : layout.key_h;
  std::vector<CellRecord> cells = results::records_of_grid(records, p.spec.grid);
  if (cells.empty()) {
    layout.missing.push_back(fmt::format("no grid '{}' in the store: panel ({}) left out", p.spec.grid, p.spec.letter));
    layout.missing_labels += fmt::format("set label {} {} at screen {},{} center\n", 90 + i,
                                         single_quoted(fmt::format("({}) {}: no grid '{}' in the store", p.spec.letter,
                                                                   p.spec.name, enhanced_literal(p.spec.grid))),
                                         p.origin_x + 0.25, p.origin_y + layout.cell_h / 2.0);
    return;
  }
  layout.total_cells += cells.size();
  fill_panel(p, std::move(cells));
  layout.panels.push_back(std::move(p));
}

MapLayout empty_layout(const sim::FactorTable& factors, double key_h) {
  MapLayout layout;
  layout.factors = factors;
  layout.key_h = key_h;
  layout.cell_h = (kMapTop - key_h) / 2.0;
  return layout;
}

MapLayout lay_out_map(const std::vector<CellRecord>& records, const sim::FactorTable& factors, const MapPanels& grids,
                      double key_h) {
  const std::array<PanelSpec, 4> specs{{
      {'a', grids.coarse, Axis::kSpeed, Axis::kTtc, Axis::kFriction, "Speed × TTC, coarse grid"},
      {'b', grids.fine, Axis::kSpeed, Axis::kTtc, Axis::kFriction, "Speed × TTC, fine grid"},
      {'c', grids.speed_mu, Axis::kSpeed, Axis::kFriction, Axis::kTtc, "Speed × friction"},
      {'d', grids.ttc_mu, Axis::kTtc, Axis::kFriction, Axis::kSpeed, "TTC × friction"},
  }};
  MapLayout layout = empty_layout(factors, key_h);
  for (std::size_t i = 0; i < specs.size(); ++i) add_panel(layout, i, specs[i], records);
  if (layout.panels.size() != 1) return layout;
  // One of the four grids alone (a fine-only campaign, or a user's grid of that name): the whole
  // page for it, not three empty slots; the others are said in `missing` only.
  layout.missing_labels.clear();
  layout.panel_w = 1.0;
  layout.cell_h = kMapTop - key_h;
  MapPanel& only = layout.panels.front();
  only.lettered = false;
  only.origin_x = 0.0;
  only.origin_y = key_h;
  return layout;
}

std::string no_map_note(std::string_view what, const MapPanels& grids) {
  return fmt::format("no {}: none of the grids '{}', '{}', '{}', '{}' is in the store", what, grids.coarse, grids.fine,
                     grids.speed_mu, grids.ttc_mu);
}

std::string panel_extent(const MapPanel& p) {
  return fmt::format("{} {} × {} {}, {}", p.xs.size(), factor_of(p.factors, p.spec.x).plural, p.ys.size(),
                     factor_of(p.factors, p.spec.y).plural, p.held);
}

std::string panel_caption(const MapPanel& p, std::string_view detail) {
  return fmt::format("{}, {} ({} cells; {})", panel_name(p), panel_extent(p), p.cells.size(), detail);
}

core::Row cell_columns(const MapPanel& p, const CellRecord& c) {
  core::Row row{std::string(1, p.spec.letter), c.grid};
  for (const double v : c.factors) row.push_back(plot_number(v));
  row.push_back(region_of(c));
  return row;
}

core::Row cell_header(const sim::FactorTable& factors, std::initializer_list<std::string> before,
                      std::initializer_list<std::string> after) {
  core::Row row(before);
  for (const sim::Factor& f : factors) row.push_back(f.key);
  row.insert(row.end(), after);
  return row;
}

std::string cell_box(const MapPanel& p, const CellRecord& c) {
  return fmt::format("{} {} {} {}", plot_number(value_of(c, p.spec.x)), plot_number(value_of(c, p.spec.y)),
                     plot_number(p.hx), plot_number(p.hy));
}

std::string boxes(std::string_view block, std::string_view colour) {
  return fmt::format("${} using 1:2:($3*1.03):($4*1.03):5 with boxxyerror fs solid 1.0 noborder lc {} notitle", block,
                     colour);
}

std::string boundary_text(double latency_s) {
  return latency_s == 0.0 ? std::string("TTC = v/(2μg)") : fmt::format("TTC = {:.3g} s + v/(2μg)", latency_s);
}

std::string boundary_function(const MapPanel& p, double latency_s) {
  if (std::isnan(latency_s)) return "";  // the scene's family has no stop boundary
  const double two_g = 2.0 * sim::kGravity_mps2;
  const PanelSpec& s = p.spec;
  if (s.x == Axis::kSpeed && s.y == Axis::kTtc)
    return fmt::format("({} + x/3.6/({}*{}))", plot_number(latency_s), plot_number(two_g), plot_number(p.fixed));
  if (s.x == Axis::kSpeed && s.y == Axis::kFriction) {
    if (p.fixed <= latency_s) return "";  // nothing stops within the latency alone
    return fmt::format("(x/3.6/({}*({} - {})))", plot_number(two_g), plot_number(p.fixed), plot_number(latency_s));
  }
  if (s.x != Axis::kTtc || s.y != Axis::kFriction) return "";  // no closed form over other factors
  // TTC × μ at a fixed speed: μ = v / (2 g (TTC − L)), defined right of the latency.
  return fmt::format("(x > {1} ? {0}/3.6/({2}*(x - {1})) : NaN)", plot_number(p.fixed), plot_number(latency_s),
                     plot_number(two_g));
}

std::string panel_plot(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                       const std::vector<std::string>& layers) {
  const std::string heading = fmt::format("{}: {} ({} cells)", panel_name(p), panel_extent(p), p.cells.size());
  std::string out =
      fmt::format("set origin {},{}\nset size {},{}\n", p.origin_x, p.origin_y, layout.panel_w, layout.cell_h);
  out += fmt::format("set title {}\n",
                     double_quoted(enhanced_literal(heading) + "\n{/*0.8 " + enhanced_literal(subtitle) + "}"));
  out += fmt::format("set xlabel {}\nset ylabel {}\n", single_quoted(factor_of(p.factors, p.spec.x).axis),
                     single_quoted(factor_of(p.factors, p.spec.y).axis));
  out +=
      fmt::format("set xrange [{}:{}]\nset yrange [{}:{}]\n", plot_number(p.xs.front() - p.hx),
                  plot_number(p.xs.back() + p.hx), plot_number(p.ys.front() - p.hy), plot_number(p.ys.back() + p.hy));
  return out + "plot " + core::join(layers, ", ") + "\n";
}

std::string panel_script(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                         std::vector<std::string> layers, double latency_s) {
  const std::string boundary = boundary_function(p, latency_s);
  if (!boundary.empty()) layers.push_back(fmt::format("{} {} notitle", boundary, kBoundaryStyle));
  return panel_plot(layout, p, subtitle, layers);
}

std::string boundary_key_entry(const std::string& label) {
  return fmt::format("NaN {} title {}", kBoundaryStyle, single_quoted(label));
}

std::string map_script(const MapLayout& layout, std::string_view title, const std::string& panels,
                       const std::vector<std::string>& key, int key_rows, int key_width_adjust, double strip_h) {
  std::string body = fmt::format(
      "set multiplot title {} font ',16'\n"
      "set samples 600\nset tics out nomirror\nset border 3\nset key off\n",
      single_quoted(title));
  body += panels;
  body += "set key on\n" + key_strip(strip_h, key_rows, key_width_adjust, key, layout.missing_labels);
  return body + "unset multiplot\n";
}

}  // namespace emrm::report::detail
