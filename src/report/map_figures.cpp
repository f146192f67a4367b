// The maps over the grids' cells (docs/report.md): the mitigability map and the harm-reduction
// map. Both share one 2×2 panel layout — grids, axes, cell rectangles, the stop boundary — and
// differ only in how a cell is coloured and what the key says.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/results/aggregate.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/sim/vehicle.hpp"
#include "figure_parts.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;
using detail::Axis;
using detail::distinct_values;
using detail::file_stem;
using detail::StemSet;
using detail::is_o_or_r;
using detail::is_undecided;
using detail::value_of;
using detail::write_csv;

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

std::string_view axis_label(Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return "ego speed (km/h)";
    case Axis::kTtc:
      return "time to collision TTC (s)";
    case Axis::kMu:
      return "road friction μ (–)";
    case Axis::kPassage:
      return "passage width (m)";
    case Axis::kTruckSpeed:
      return "truck speed (km/h)";
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
    case Axis::kPassage:
      return "passage widths";
    case Axis::kTruckSpeed:
      return "truck speeds";
  }
  return "";
}

/// Half the smallest step between distinct values: the half-width of a cell's rectangle.
double half_step(const std::vector<double>& values, Axis a) {
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
  if (std::isfinite(step)) return step / 2.0;
  // A single value: a band of a plausible width.
  return a == Axis::kSpeed || a == Axis::kTruckSpeed ? 1.0 : 0.05;
}

double median_of(const std::vector<CellRecord>& cells, Axis a) {
  std::vector<double> v;
  for (const auto& c : cells) v.push_back(value_of(c, a));
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

std::string fixed_text(Axis a, double v) {
  switch (a) {
    case Axis::kSpeed:
      return fmt::format("v = {} km/h", plot_number(v));
    case Axis::kTtc:
      return fmt::format("TTC = {} s", plot_number(v));
    case Axis::kMu:
      return fmt::format("μ = {}", plot_number(v));
    case Axis::kPassage:
      return fmt::format("passage {} m", plot_number(v));
    case Axis::kTruckSpeed:
      return fmt::format("truck {} km/h", plot_number(v));
  }
  return "";
}

std::string region_of(const CellRecord& r) { return r.feasible ? r.region : std::string("infeasible"); }

std::string region_colour(std::string_view region) {
  for (const auto& s : kRegions)
    if (s.region == region) return std::string(s.colour);
  return std::string(kRegions.back().colour);
}

// --- the panels both maps share -----------------------------------------------------------------

struct PanelSpec {
  char letter;
  std::string grid;
  Axis x, y, fixed;
  std::string_view name;  ///< "Speed × TTC, coarse grid"
};

/// One panel whose grid has cells: its cells, their extent, and where it sits on the page.
struct MapPanel {
  PanelSpec spec;
  std::vector<CellRecord> cells;
  std::vector<double> xs, ys;  ///< the distinct values along each axis
  double hx = 0.0, hy = 0.0;   ///< half a cell's width and height
  double fixed = 0.0;          ///< the median of the factor the panel holds fixed
  std::string held;            ///< what the panel holds fixed, as its heading says it: "μ = 1"
  bool lettered = true;        ///< headed "(a) NAME" (a panel of the 2×2 layout), else "NAME"
  double origin_x = 0.0, origin_y = 0.0;
};

constexpr int kMapWidthPx = 1400, kMapHeightPx = 1000, kMapFontPt = 13;

/// A map's 2×2 layout above a key strip `key_h` high (screen units): the panels that have cells,
/// in order (a)–(d); a missing grid leaves its slot empty but for a label, and is said in `missing`.
struct MapLayout {
  std::vector<MapPanel> panels;
  std::vector<std::string> missing;
  std::string missing_labels;  ///< gnuplot labels for the empty slots, drawn with the key strip
  std::size_t total_cells = 0;
  double key_h = 0.0, cell_h = 0.0;
  double panel_w = 0.5;  ///< a panel's width (screen units)
  int width_px = kMapWidthPx, height_px = kMapHeightPx;
};

/// Gives `p` its cells and their extent along the axes of its spec.
void fill_panel(MapPanel& p, std::vector<CellRecord> cells) {
  p.cells = std::move(cells);
  p.xs = distinct_values(p.cells, p.spec.x);
  p.ys = distinct_values(p.cells, p.spec.y);
  p.hx = half_step(p.xs, p.spec.x);
  p.hy = half_step(p.ys, p.spec.y);
  p.fixed = median_of(p.cells, p.spec.fixed);
  p.held = fixed_text(p.spec.fixed, p.fixed);
}

/// Puts panel `spec` in slot `i` (0–3, row by row) of `layout` with the cells of its grid in
/// `records`; a grid without cells leaves the slot empty but for a label.
void add_panel(MapLayout& layout, std::size_t i, const PanelSpec& spec, const std::vector<CellRecord>& records) {
  MapPanel p;
  p.spec = spec;
  p.origin_x = i % 2 == 0 ? 0.0 : 0.5;
  p.origin_y = i < 2 ? layout.key_h + layout.cell_h : layout.key_h;
  std::vector<CellRecord> cells = results::records_of_grid(records, p.spec.grid);
  if (cells.empty()) {
    layout.missing.push_back(fmt::format("no grid '{}' in the store: panel ({}) left out", p.spec.grid, p.spec.letter));
    layout.missing_labels += fmt::format(
        "set label {} {} at screen {},{} center\n", 90 + i,
        single_quoted(fmt::format("({}) {}: no grid '{}' in the store", p.spec.letter, p.spec.name,
                                  enhanced_literal(p.spec.grid))),
        p.origin_x + 0.25, p.origin_y + layout.cell_h / 2.0);
    return;
  }
  layout.total_cells += cells.size();
  fill_panel(p, std::move(cells));
  layout.panels.push_back(std::move(p));
}

constexpr double kMapTop = 0.955;  // below the multiplot's title

MapLayout empty_layout(double key_h) {
  MapLayout layout;
  layout.key_h = key_h;
  layout.cell_h = (kMapTop - key_h) / 2.0;
  return layout;
}

MapLayout lay_out_map(const std::vector<CellRecord>& records, const MapPanels& grids, double key_h) {
  const std::array<PanelSpec, 4> specs{{
      {'a', grids.coarse, Axis::kSpeed, Axis::kTtc, Axis::kMu, "Speed × TTC, coarse grid"},
      {'b', grids.fine, Axis::kSpeed, Axis::kTtc, Axis::kMu, "Speed × TTC, fine grid"},
      {'c', grids.speed_mu, Axis::kSpeed, Axis::kMu, Axis::kTtc, "Speed × friction"},
      {'d', grids.ttc_mu, Axis::kTtc, Axis::kMu, Axis::kSpeed, "TTC × friction"},
  }};
  MapLayout layout = empty_layout(key_h);
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
  return fmt::format("no {}: none of the grids '{}', '{}', '{}', '{}' is in the store", what, grids.coarse,
                     grids.fine, grids.speed_mu, grids.ttc_mu);
}

/// "5 speeds × 6 TTCs, μ = 1": the panel's extent, as its heading and the caption state it.
std::string panel_extent(const MapPanel& p) {
  return fmt::format("{} {} × {} {}, {}", p.xs.size(), axis_plural(p.spec.x), p.ys.size(), axis_plural(p.spec.y),
                     p.held);
}

/// "(a) Speed × TTC, coarse grid", or the name alone for a map of one panel.
std::string panel_name(const MapPanel& p) {
  return p.lettered ? fmt::format("({}) {}", p.spec.letter, p.spec.name) : std::string(p.spec.name);
}

/// The panel's part of the figure's caption, `detail` after its cell count.
std::string panel_caption(const MapPanel& p, std::string_view detail) {
  return fmt::format("{}, {} ({} cells; {})", panel_name(p), panel_extent(p), p.cells.size(), detail);
}

/// The CSV columns every map starts a cell's row with: panel, grid, speed_kph, ttc_s, mu,
/// passage_m, region.
core::Row cell_columns(const MapPanel& p, const CellRecord& c) {
  return {std::string(1, p.spec.letter), c.grid,           plot_number(c.speed_kph), plot_number(c.ttc_s),
          plot_number(c.mu),             plot_number(c.passage_m), region_of(c)};
}

/// A cell's rectangle, the start of its datablock line: x y half-width half-height.
std::string cell_box(const MapPanel& p, const CellRecord& c) {
  return fmt::format("{} {} {} {}", plot_number(value_of(c, p.spec.x)), plot_number(value_of(c, p.spec.y)),
                     plot_number(p.hx), plot_number(p.hy));
}

/// The plot item drawing the rectangles of datablock `block` (x y hx hy COLOUR), coloured by `colour`
/// ("rgb variable", "palette"). Neighbours overlap by 3 % of a cell so that antialiased edges leave
/// no seams between them.
std::string boxes(std::string_view block, std::string_view colour) {
  return fmt::format("${} using 1:2:($3*1.03):($4*1.03):5 with boxxyerror fs solid 1.0 noborder lc {} notitle", block,
                     colour);
}

std::string boundary_text(double latency_s) {
  return latency_s == 0.0 ? std::string("TTC = v/(2μg)")
                          : fmt::format("TTC = {:.3g} s + v/(2μg)", latency_s);
}

/// The dashed analytic stop boundary TTC = L + v/(2μg) as a gnuplot function of the panel's x.
std::string boundary_function(const MapPanel& p, double latency_s) {
  const double two_g = 2.0 * sim::kGravity_mps2;
  const PanelSpec& s = p.spec;
  if (s.x == Axis::kSpeed && s.y == Axis::kTtc)
    return fmt::format("({} + x/3.6/({}*{}))", plot_number(latency_s), plot_number(two_g), plot_number(p.fixed));
  if (s.x == Axis::kSpeed && s.y == Axis::kMu) {
    if (p.fixed <= latency_s) return "";  // nothing stops within the latency alone
    return fmt::format("(x/3.6/({}*({} - {})))", plot_number(two_g), plot_number(p.fixed), plot_number(latency_s));
  }
  if (s.x != Axis::kTtc || s.y != Axis::kMu) return "";  // no closed form over other factors
  // TTC × μ at a fixed speed: μ = v / (2 g (TTC − L)), defined right of the latency.
  return fmt::format("(x > {1} ? {0}/3.6/({2}*(x - {1})) : NaN)", plot_number(p.fixed), plot_number(latency_s),
                     plot_number(two_g));
}

constexpr std::string_view kBoundaryStyle = "with lines dt 2 lw 2.5 lc rgb 'black'";

/// One panel of the multiplot: its place, its heading with `subtitle` under it, its axes, then
/// `layers` (plot items over its cells, in drawing order).
std::string panel_plot(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                       const std::vector<std::string>& layers) {
  const std::string heading = fmt::format("{}: {} ({} cells)", panel_name(p), panel_extent(p), p.cells.size());
  std::string out =
      fmt::format("set origin {},{}\nset size {},{}\n", p.origin_x, p.origin_y, layout.panel_w, layout.cell_h);
  out += fmt::format("set title {}\n",
                     double_quoted(enhanced_literal(heading) + "\n{/*0.8 " + enhanced_literal(subtitle) + "}"));
  out += fmt::format("set xlabel {}\nset ylabel {}\n", single_quoted(axis_label(p.spec.x)),
                     single_quoted(axis_label(p.spec.y)));
  out += fmt::format("set xrange [{}:{}]\nset yrange [{}:{}]\n", plot_number(p.xs.front() - p.hx),
                     plot_number(p.xs.back() + p.hx), plot_number(p.ys.front() - p.hy),
                     plot_number(p.ys.back() + p.hy));
  return out + "plot " + core::join(layers, ", ") + "\n";
}

/// panel_plot with the closed-form stop boundary on top of `layers`.
std::string panel_script(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                         std::vector<std::string> layers, double latency_s) {
  const std::string boundary = boundary_function(p, latency_s);
  if (!boundary.empty()) layers.push_back(fmt::format("{} {} notitle", boundary, kBoundaryStyle));
  return panel_plot(layout, p, subtitle, layers);
}

/// The key's entry for a dashed stop boundary titled `label`.
std::string boundary_key_entry(const std::string& label) {
  return fmt::format("NaN {} title {}", kBoundaryStyle, single_quoted(label));
}

/// The whole map: a multiplot titled `title` holding `panels` (panel_script), then the key strip
/// (`key` entries in at most `key_rows` rows, `strip_h` high) with the empty slots' labels.
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


constexpr std::string_view kUndecidedLabel = "undecided (no avoidance found,\nnone proven impossible)";
constexpr std::string_view kReductionLabel = "reduction of P(MAIS3+) by the best strategy";
constexpr std::string_view kCrossKeyStyle = "pt 2 ps 1.2 lw 1.5 lc rgb 'black'";

/// The cross over an undecided cell, sized by the cell on the page (a panel's plot area is roughly
/// 80 % of its width and 70 % of its height): readable on the fine grid's flat cells, and not
/// filling a coarse grid's cell.
std::string cross_style(const MapLayout& layout, const MapPanel& p) {
  const double cell_w_px = layout.panel_w * layout.width_px * 0.8 / static_cast<double>(p.xs.size());
  const double cell_h_px = layout.cell_h * layout.height_px * 0.7 / static_cast<double>(p.ys.size());
  constexpr double kPointPx = 9.0;  // about the size of a cross at point size 1 at this size and font
  const double size = std::clamp(0.6 * std::sqrt(cell_w_px * cell_h_px) / kPointPx, 0.5, 1.5);
  return fmt::format("pt 2 ps {:.2f} lw 1.5 lc rgb 'black'", size);
}

/// A panel's cells in their region colours, undecided O/R cells crossed: its plot items, appended
/// to `data` as datablocks; one CSV row per cell (cell_columns, then evidence) appended to `rows`.
struct RegionPanel {
  std::vector<std::string> layers;
  std::string shares;  ///< "G a %, Y b %, O c %, R d % of N feasible[, k undecided]"
};
RegionPanel region_panel(const MapLayout& layout, const MapPanel& p, std::vector<core::Row>& rows, std::string& data) {
  const auto regions = results::count_regions(p.cells, p.spec.grid);  // throws on a corrupt region
  std::vector<std::string> lines, crosses;
  for (const auto& c : p.cells) {
    core::Row row = cell_columns(p, c);
    row.push_back(c.feasible ? c.evidence : std::string());
    lines.push_back(fmt::format("{} {}", cell_box(p, c), rgb_value(region_colour(row[6]))));
    if (is_undecided(c))
      crosses.push_back(fmt::format("{} {}", plot_number(value_of(c, p.spec.x)), plot_number(value_of(c, p.spec.y))));
    rows.push_back(std::move(row));
  }
  RegionPanel out;
  const std::string block = fmt::format("map_{}", p.spec.letter);
  data += datablock(block, lines);
  out.layers.push_back(boxes(block, "rgb variable"));
  if (!crosses.empty()) {
    const std::string cross_block = fmt::format("undecided_{}", p.spec.letter);
    data += datablock(cross_block, crosses);
    out.layers.push_back(fmt::format("${} using 1:2 with points {} notitle", cross_block, cross_style(layout, p)));
  }
  const auto share = [&](std::size_t n) { return fmt::format("{:.1f} %", regions.pct(n)); };
  out.shares = regions.feasible == 0 ? std::string("no feasible cell")
                                     : fmt::format("G {}, Y {}, O {}, R {} of {} feasible", share(regions.g),
                                                   share(regions.y), share(regions.o), share(regions.r),
                                                   regions.feasible);
  if (!crosses.empty()) out.shares += fmt::format(", {} undecided", crosses.size());
  return out;
}

/// What backs the O/R cells of a map, as its caption says it.
struct EvidenceCounts {
  std::size_t undecided = 0, certified = 0, unproven = 0;
  [[nodiscard]] std::string caption() const {
    std::string out;
    if (undecided > 0)
      out = fmt::format(" A cross marks the {} undecided O/R cells: a search found no avoidance, but nothing "
                        "proves that none exists.",
                        undecided);
    if (certified > 0)
      out += unproven == 0 ? fmt::format(" {} O/R cells ({}) are certified unavoidable.",
                                         undecided == 0 ? "All" : "The unmarked", certified)
                           : fmt::format(" {} O/R cells are certified unavoidable, {} carry no evidence.", certified,
                                         unproven);
    return out;
  }
};
EvidenceCounts count_evidence(const std::vector<CellRecord>& cells) {
  EvidenceCounts n;
  for (const auto& c : cells) {
    if (!is_o_or_r(c)) continue;
    n.undecided += is_undecided(c);
    n.certified += c.evidence == "certificate";
    n.unproven += c.evidence != "undecided" && c.evidence != "certificate";
  }
  return n;
}

/// The key of a region map: the regions, the stop boundary (`boundary` its label; none when empty),
/// and the cross when some cell is undecided.
std::vector<std::string> region_key(const std::string& boundary, bool undecided) {
  std::vector<std::string> key;
  for (const auto& s : kRegions)
    key.push_back(
        fmt::format("NaN with boxes fs solid 1.0 lc rgb {} title {}", single_quoted(s.colour), single_quoted(s.label)));
  if (!boundary.empty()) key.push_back(boundary_key_entry(boundary));
  if (undecided) key.push_back(fmt::format("NaN with points {} title {}", kCrossKeyStyle, double_quoted(kUndecidedLabel)));
  return key;
}

}  // namespace

// --- the mitigability map -----------------------------------------------------------------------

Figure draw_mitigability_map(const std::vector<CellRecord>& records, const fs::path& dir, const MapPanels& panels,
                             double latency_s) {
  Figure figure;
  figure.name = "mitigability_map";
  figure.title = "Mitigability regions";  // replaced by the full caption once drawn
  // Undecided O/R cells (a search found no avoidance, nothing proves there is none) carry a cross
  // over their region colour: their region is a search's verdict, not a proof.
  std::vector<CellRecord> mapped;
  for (const std::string& grid : {panels.coarse, panels.fine, panels.speed_mu, panels.ttc_mu})
    for (const auto& c : records)
      if (c.grid == grid) mapped.push_back(c);
  const EvidenceCounts evidence = count_evidence(mapped);
  const std::size_t undecided = evidence.undecided;
  const MapLayout layout = lay_out_map(records, panels, undecided == 0 ? 0.06 : 0.1);  // a third key row
  if (layout.panels.empty()) {
    figure.note = no_map_note("mitigability map", panels);
    return figure;
  }

  std::vector<core::Row> rows;
  std::vector<std::string> caption_parts;
  std::string data, panel_plots;
  for (const MapPanel& p : layout.panels) {
    const RegionPanel drawn = region_panel(layout, p, rows, data);
    caption_parts.push_back(panel_caption(p, drawn.shares));
    panel_plots += panel_script(layout, p, drawn.shares, drawn.layers, latency_s);
  }

  figure.note = core::join(layout.missing, "; ");
  figure.title = fmt::format(
      "Mitigability regions over {} simulated cells: {}. Each rectangle is one cell: G (green) fully avoidable, "
      "Y (yellow) aggressive avoidance required, O (orange) mitigatable, R (red) not mitigatable, grey infeasible. "
      "Dashed: the analytic stop boundary {} (g = {} m/s²) at the panel's fixed parameter.{}",
      layout.total_cells, core::join(caption_parts, "; "), boundary_text(latency_s), plot_number(sim::kGravity_mps2),
      evidence.caption());
  write_csv(figure, dir, {"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "evidence"}, rows);

  const std::vector<std::string> key = region_key("stop boundary " + boundary_text(latency_s), undecided > 0);
  const std::string body =
      map_script(layout, fmt::format("Mitigability regions ({} cells)", layout.total_cells), panel_plots, key,
                 undecided == 0 ? 2 : 3, undecided == 0 ? -6 : 0, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kMapWidthPx, kMapHeightPx, kMapFontPt);
  return figure;
}

// --- the harm-reduction map ----------------------------------------------------------------------

Figure draw_harm_reduction_map(const std::vector<CellRecord>& records, const fs::path& dir, const MapPanels& panels,
                               double latency_s) {
  Figure figure;
  figure.name = "harm_reduction_map";
  figure.title = "Harm reduction by the best strategy";  // replaced by the full caption once drawn
  // A taller key strip: the colour bar sits above the key entries.
  const MapLayout layout = lay_out_map(records, panels, 0.11);
  if (layout.panels.empty()) {
    figure.note = no_map_note("harm reduction map", panels);
    return figure;
  }
  // One scale for all panels, so that a colour means the same reduction everywhere.
  double largest = 0.0;
  for (const MapPanel& p : layout.panels)
    for (const auto& c : p.cells)
      if (c.feasible) largest = std::max(largest, c.p_mais3_reduction);

  std::vector<core::Row> rows;
  std::vector<std::string> caption_parts;
  std::string data, panel_plots;
  bool colour_bar = false;
  for (const MapPanel& p : layout.panels) {
    std::vector<std::string> reduced, infeasible;
    std::size_t feasible = 0, o_or_r = 0, o_or_r_reduced = 0, unsearched = 0;
    double sum = 0.0, most = 0.0;
    for (const auto& c : p.cells) {
      core::Row row = cell_columns(p, c);
      // Certified with the reference at L4: no search ran (the level cannot fall), so the reduction
      // is the emergency stop's, a lower bound on what a least-loss search might find.
      unsearched += c.feasible && c.evidence == "certificate" && c.mitigation_evidence == "proof";
      if (c.feasible) {
        for (const double v : {c.unmitigated_p_mais3, c.p_mais3_reduction, c.unmitigated_p_fatal, c.p_fatal_reduction})
          row.push_back(plot_number(v));
        reduced.push_back(fmt::format("{} {}", cell_box(p, c), plot_number(c.p_mais3_reduction)));
        ++feasible;
        sum += c.p_mais3_reduction;
        most = std::max(most, c.p_mais3_reduction);
        o_or_r += is_o_or_r(c);
        o_or_r_reduced += is_o_or_r(c) && c.p_mais3_reduction > 0.0;
      } else {
        row.insert(row.end(), 4, std::string());
        infeasible.push_back(fmt::format("{} {}", cell_box(p, c), rgb_value(region_colour("infeasible"))));
      }
      rows.push_back(std::move(row));
    }
    std::vector<std::string> layers;
    if (!reduced.empty()) {
      const std::string block = fmt::format("harm_{}", p.spec.letter);
      data += datablock(block, reduced);
      layers.push_back(boxes(block, "palette"));
    }
    if (!infeasible.empty()) {
      const std::string block = fmt::format("infeasible_{}", p.spec.letter);
      data += datablock(block, infeasible);
      layers.push_back(boxes(block, "rgb variable"));
    }
    const std::string summary =
        feasible == 0 ? std::string("no feasible cell")
                      : fmt::format("reduction mean {:.3f}, max {:.3f} over {} feasible; {} of {} O/R reduced",
                                    sum / static_cast<double>(feasible), most, feasible, o_or_r_reduced, o_or_r);
    caption_parts.push_back(panel_caption(
        p, unsearched == 0 ? summary
                           : fmt::format("{}; {} certified L4 cells not searched, their reduction the emergency "
                                         "stop's (a lower bound)",
                                         summary, unsearched)));
    // The colour bar is drawn once, with the first panel that has a feasible cell, in the key strip.
    const bool with_bar = !colour_bar && !reduced.empty();
    if (with_bar)
      panel_plots += fmt::format(
          "set colorbox user horizontal origin screen 0.42,0.075 size screen 0.36,0.018\n"
          "set label 80 {} at screen 0.41,0.084 right\n",
          single_quoted(kReductionLabel));
    panel_plots += panel_script(layout, p, summary, layers, latency_s);
    if (with_bar) panel_plots += "unset colorbox\nunset label 80\n";
    colour_bar = colour_bar || with_bar;
  }

  figure.note = core::join(layout.missing, "; ");
  figure.title = fmt::format(
      "Harm reduction by the best strategy over {} simulated cells: {}. Each feasible cell is coloured by the "
      "unmitigated reference's P(MAIS3+) minus the lowest P(MAIS3+) of the strategies (0 to {:.3f}): an avoided "
      "cell (G, Y) counts its whole unmitigated risk, an O or R cell the mitigation inside its loss level, which the "
      "mitigability map does not show. Grey: infeasible. Dashed: the analytic stop boundary {} at the panel's fixed "
      "parameter.",
      layout.total_cells, core::join(caption_parts, "; "), largest, boundary_text(latency_s));
  write_csv(figure, dir,
            {"panel", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "unmitigated_p_mais3",
             "p_mais3_reduction", "unmitigated_p_fatal", "p_fatal_reduction"},
            rows);

  // Sequential, light to dark, and apart from the region colours and the grey of infeasible cells.
  const std::string scale = fmt::format(
      "set palette defined (0 '#f2f0f7', 0.35 '#9e9ac8', 0.7 '#6a51a3', 1 '#3f007d')\nset cbrange [0:{}]\n"
      "set cbtics out\nset format cb '%g'\nunset colorbox\n",
      plot_number(largest > 0.0 ? largest : 1.0));
  const std::vector<std::string> key{fmt::format("NaN with boxes fs solid 1.0 lc rgb {} title 'infeasible'",
                                                 single_quoted(region_colour("infeasible"))),
                                     boundary_key_entry("stop boundary " + boundary_text(latency_s))};
  const std::string body = map_script(layout, fmt::format("Harm reduction by the best strategy ({} cells)",
                                                          layout.total_cells),
                                      scale + panel_plots, key, 1, 0, 0.035);
  render_png_and_svg(figure.png, figure.svg, data, body, kMapWidthPx, kMapHeightPx, kMapFontPt);
  return figure;
}

// --- the map under each actuation profile ---------------------------------------------------------

Figure draw_profile_maps(const std::vector<results::ProfileRun>& runs,
                         const std::vector<std::vector<CellRecord>>& records, const std::string& grid,
                         const fs::path& dir) {
  Figure figure;
  figure.name = "regions_by_profile";
  figure.title = "Mitigability regions under each actuation profile";
  const std::size_t shown = std::min<std::size_t>({runs.size(), records.size(), 4});
  std::vector<std::string> names;  // the panels' specs view these
  names.reserve(shown);
  for (std::size_t i = 0; i < shown; ++i) names.push_back("profile " + runs[i].name);
  MapLayout layout = empty_layout(0.08);
  std::vector<std::size_t> run_of;  // the run each drawn panel shows
  for (std::size_t i = 0; i < shown; ++i) {
    add_panel(layout, i, {static_cast<char>('a' + i), grid, Axis::kSpeed, Axis::kTtc, Axis::kMu, names[i]}, records[i]);
    if (layout.panels.size() > run_of.size()) run_of.push_back(i);
  }
  if (layout.panels.empty()) {
    figure.note = fmt::format("no profile sweep of grid '{}' in this folder (emrm reproduce writes them)", grid);
    return figure;
  }
  std::vector<core::Row> rows;
  std::vector<std::string> caption_parts;
  std::string data, panel_plots;
  bool undecided = false;
  for (std::size_t k = 0; k < layout.panels.size(); ++k) {
    const MapPanel& p = layout.panels[k];
    const results::ProfileRun& run = runs[run_of[k]];
    const auto& a = run.actuation;
    const double latency_s = a.perception_latency_s + a.brake_dead_time_s + 0.5 * a.brake_ramp_s;
    const std::size_t before = rows.size();
    const RegionPanel drawn = region_panel(layout, p, rows, data);
    for (std::size_t r = before; r < rows.size(); ++r) rows[r].insert(rows[r].begin() + 1, run.name);
    undecided = undecided || drawn.layers.size() > 1;
    caption_parts.push_back(panel_caption(p, fmt::format("{}; {}; stop boundary {}", drawn.shares, a.summary(),
                                                         boundary_text(latency_s))));
    panel_plots += panel_script(layout, p, drawn.shares, drawn.layers, latency_s);
  }
  if (runs.size() > shown) figure.note = fmt::format("{} profiles; the first {} are drawn", runs.size(), shown);
  figure.title = fmt::format(
      "The fine map under each actuation profile (docs/actuation.md): {}. Colours as in the mitigability map; each "
      "panel's dashed line is its own stop boundary (perception latency, brake dead time and half the ramp before "
      "v/(2μg)).",
      core::join(caption_parts, "; "));
  write_csv(figure, dir, {"panel", "profile", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "evidence"},
            rows);
  const std::string body = map_script(layout, "Mitigability regions under each actuation profile", panel_plots,
                                      region_key("stop boundary of the profile", undecided), 2, undecided ? 0 : -6,
                                      layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kMapWidthPx, kMapHeightPx, kMapFontPt);
  return figure;
}

// --- maps of any grid ------------------------------------------------------------------------------

namespace {

// The order in which a grid's factors become a map's axes: the first two that vary.
constexpr std::array<Axis, 5> kFactorOrder{Axis::kSpeed, Axis::kTtc, Axis::kMu, Axis::kPassage, Axis::kTruckSpeed};

/// The factor's key in a campaign file, as a figure's file name uses it.
std::string_view axis_key(Axis a) {
  switch (a) {
    case Axis::kSpeed:
      return "speed_kph";
    case Axis::kTtc:
      return "ttc_s";
    case Axis::kMu:
      return "mu";
    case Axis::kPassage:
      return "passage_m";
    case Axis::kTruckSpeed:
      return "truck_speed_kph";
  }
  return "";
}

/// How a grid is cut into maps: its axes, the factor the stop boundary holds fixed, and the factors
/// each slice holds fixed (`sliced` those of them that vary over the grid).
struct GridCut {
  Axis x = Axis::kSpeed, y = Axis::kTtc, fixed = Axis::kMu;
  std::vector<Axis> held, sliced;
};

/// The first two varying factors as axes (a constant one fills in for a 1-D or 0-D grid: a strip).
GridCut cut_grid(const std::vector<CellRecord>& cells) {
  std::vector<Axis> varying, constant;
  for (const Axis a : kFactorOrder) (distinct_values(cells, a).size() > 1 ? varying : constant).push_back(a);
  std::vector<Axis> order = varying;
  order.insert(order.end(), constant.begin(), constant.end());
  GridCut cut;
  cut.x = order[0];
  cut.y = order[1];
  cut.held.assign(order.begin() + 2, order.end());
  for (const Axis a : cut.held)
    if (std::find(varying.begin(), varying.end(), a) != varying.end()) cut.sliced.push_back(a);
  for (const Axis a : {Axis::kMu, Axis::kTtc, Axis::kSpeed})  // the boundary's third factor, when it has one
    if (a != cut.x && a != cut.y) cut.fixed = a;
  return cut;
}

/// The cells of a grid that share the values of every factor the cut holds fixed.
struct GridSlice {
  std::vector<CellRecord> cells;
  std::vector<double> held_values;  ///< in the order of GridCut::held
};

/// The grid's slices, ordered by their held values (factor by factor, ascending).
std::vector<GridSlice> slices_of(const std::vector<CellRecord>& cells, const GridCut& cut) {
  std::vector<std::vector<double>> distinct;
  for (const Axis a : cut.held) distinct.push_back(distinct_values(cells, a));
  std::map<std::vector<std::size_t>, GridSlice> by_key;
  for (const auto& c : cells) {
    std::vector<std::size_t> key;
    for (std::size_t i = 0; i < cut.held.size(); ++i) {
      const auto& values = distinct[i];
      const double v = value_of(c, cut.held[i]);
      key.push_back(static_cast<std::size_t>(
          std::lower_bound(values.begin(), values.end(), v - detail::kSameValue) - values.begin()));
    }
    GridSlice& slice = by_key[key];
    if (slice.cells.empty())
      for (std::size_t i = 0; i < key.size(); ++i) slice.held_values.push_back(distinct[i][key[i]]);
    slice.cells.push_back(c);
  }
  std::vector<GridSlice> out;
  for (auto& [key, slice] : by_key) out.push_back(std::move(slice));
  return out;
}

/// "μ = 0.5, passage 3 m" for `factors` of the cut at the slice's values.
std::string held_text(const GridCut& cut, const GridSlice& slice, const std::vector<Axis>& factors) {
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < cut.held.size(); ++i)
    if (std::find(factors.begin(), factors.end(), cut.held[i]) != factors.end())
      parts.push_back(fixed_text(cut.held[i], slice.held_values[i]));
  return core::join(parts, ", ");
}

/// "map_GRID", then "_FACTOR_VALUE" for each factor the slice is cut along.
std::string slice_stem(const std::string& grid, const GridCut& cut, const GridSlice& slice) {
  std::string stem = "map_" + file_stem(grid);
  for (std::size_t i = 0; i < cut.held.size(); ++i)
    if (std::find(cut.sliced.begin(), cut.sliced.end(), cut.held[i]) != cut.sliced.end())
      stem += fmt::format("_{}_{}", axis_key(cut.held[i]), file_stem(plot_number(slice.held_values[i])));
  return stem;
}

constexpr int kSliceWidthPx = 1000, kSliceHeightPx = 760;

/// One slice of a grid as a map of one panel, in the mitigability map's colours and crosses.
Figure draw_slice_map(const std::string& grid, const GridCut& cut, const GridSlice& slice, const std::string& name,
                      const fs::path& dir, double latency_s) {
  Figure figure;
  figure.name = name;
  const std::string slice_label = held_text(cut, slice, cut.sliced);
  const std::string what = fmt::format("grid '{}'{}", grid, slice_label.empty() ? "" : ", slice " + slice_label);
  const EvidenceCounts evidence = count_evidence(slice.cells);
  MapLayout layout = empty_layout(evidence.undecided == 0 ? 0.13 : 0.17);  // three key rows, or four
  layout.panel_w = 1.0;
  layout.cell_h = kMapTop - layout.key_h;
  layout.width_px = kSliceWidthPx;
  layout.height_px = kSliceHeightPx;
  const std::string panel_title = "Grid " + grid;  // the spec views it
  MapPanel p;
  p.spec = {'a', grid, cut.x, cut.y, cut.fixed, panel_title};
  p.lettered = false;
  p.origin_y = layout.key_h;
  fill_panel(p, slice.cells);
  p.held = held_text(cut, slice, cut.held);
  layout.total_cells = p.cells.size();

  std::vector<core::Row> rows;
  std::string data;
  const RegionPanel drawn = region_panel(layout, p, rows, data);
  for (auto& row : rows) row[0] = slice_label;
  const bool boundary = !boundary_function(p, latency_s).empty();
  figure.title = fmt::format(
      "Mitigability regions of {}: {} ({} cells; {}). Each rectangle is one cell: G (green) fully avoidable, "
      "Y (yellow) aggressive avoidance required, O (orange) mitigatable, R (red) not mitigatable, grey "
      "infeasible.{}{}",
      what, panel_extent(p), p.cells.size(), drawn.shares,
      boundary ? fmt::format(" Dashed: the analytic stop boundary {} (g = {} m/s²) at {}.", boundary_text(latency_s),
                             plot_number(sim::kGravity_mps2), fixed_text(p.spec.fixed, p.fixed))
               : std::string(),
      evidence.caption());
  write_csv(figure, dir, {"slice", "grid", "speed_kph", "ttc_s", "mu", "passage_m", "region", "evidence"}, rows);
  const std::vector<std::string> key =
      region_key(boundary ? "stop boundary " + boundary_text(latency_s) : std::string(), evidence.undecided > 0);
  const std::string body =
      map_script(layout, fmt::format("Mitigability regions, {}", enhanced_literal(what)),
                 panel_script(layout, p, drawn.shares, drawn.layers, latency_s), key,
                 evidence.undecided == 0 ? 3 : 4, 0, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kSliceWidthPx, kSliceHeightPx, kMapFontPt);
  return figure;
}

/// The report's entry for slices left undrawn: their count and values.
Figure undrawn_slices(const std::string& grid, const std::string& name, const GridCut& cut,
                      const std::vector<GridSlice>& slices, std::size_t drawn) {
  Figure figure;
  figure.name = name;
  figure.title = fmt::format("Mitigability regions of grid '{}', further slices", grid);
  std::vector<std::string> left;
  for (std::size_t i = drawn; i < slices.size(); ++i) left.push_back(held_text(cut, slices[i], cut.sliced));
  figure.note = fmt::format("grid '{}' has {} slices; the first {} are drawn, these not: {}", grid, slices.size(),
                            drawn, core::join(left, "; "));
  return figure;
}

}  // namespace

std::vector<Figure> draw_grid_maps(const std::vector<CellRecord>& records, const fs::path& dir,
                                   const GridMapOptions& options) {
  std::vector<Figure> figures;
  StemSet stems;
  for (const auto& grid : results::grid_names(records)) {
    if (std::find(options.skip.begin(), options.skip.end(), grid) != options.skip.end()) continue;
    const std::vector<CellRecord> cells = results::records_of_grid(records, grid);
    const GridCut cut = cut_grid(cells);
    const std::vector<GridSlice> slices = slices_of(cells, cut);
    const std::size_t drawn = std::min(slices.size(), options.max_slices_per_grid);
    for (std::size_t i = 0; i < drawn; ++i)
      figures.push_back(
          draw_slice_map(grid, cut, slices[i], stems.unique(slice_stem(grid, cut, slices[i])), dir, options.latency_s));
    if (drawn < slices.size())
      figures.push_back(undrawn_slices(grid, stems.unique("map_" + file_stem(grid) + "_more"), cut, slices, drawn));
  }
  return figures;
}

// --- a speed × TTC map with curves over it (boundary_figures.cpp) ----------------------------------

namespace detail {

namespace {
constexpr int kOverlaidWidthPx = 1300, kOverlaidHeightPx = 900;
constexpr std::size_t kOverlaidKeyColumns = 3;
constexpr int kOverlaidKeyWidthAdjust = 0;
}  // namespace

MapCaption draw_overlaid_map(const Figure& figure, const OverlaidMap& map) {
  const EvidenceCounts evidence = count_evidence(map.cells);
  std::vector<std::string> key = region_key("", evidence.undecided > 0);
  key.insert(key.end(), map.key.begin(), map.key.end());
  const std::size_t key_rows = (key.size() + kOverlaidKeyColumns - 1) / kOverlaidKeyColumns;
  MapLayout layout = empty_layout(0.025 + 0.03 * static_cast<double>(key_rows));
  layout.panel_w = 1.0;
  layout.cell_h = kMapTop - layout.key_h;
  layout.width_px = kOverlaidWidthPx;
  layout.height_px = kOverlaidHeightPx;
  layout.total_cells = map.cells.size();
  const std::string panel_title = "Grid " + map.grid;  // the spec views it
  MapPanel p;
  p.spec = {'a', map.grid, Axis::kSpeed, Axis::kTtc, Axis::kMu, panel_title};
  p.lettered = false;
  p.origin_y = layout.key_h;
  fill_panel(p, map.cells);
  p.held = map.held;

  std::vector<core::Row> cell_rows;  // the cells are in the store's exports; the figure's CSV is the caller's
  std::string data = map.data;
  RegionPanel drawn = region_panel(layout, p, cell_rows, data);
  drawn.layers.insert(drawn.layers.end(), map.layers.begin(), map.layers.end());
  const std::string body = map_script(layout, enhanced_literal(map.title), panel_plot(layout, p, drawn.shares, drawn.layers),
                                      key, static_cast<int>(key_rows), kOverlaidKeyWidthAdjust, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kOverlaidWidthPx, kOverlaidHeightPx, kMapFontPt);
  return {panel_extent(p), drawn.shares, evidence.caption()};
}

}  // namespace detail

}  // namespace emrm::report
