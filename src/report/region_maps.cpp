// The region maps (docs/report.md): the mitigability map over the paper's four grids, the map
// under each actuation profile, the maps of any other grid slice by slice, and the one-panel map
// the boundary figures draw their curves over. A cell is coloured by its region, an undecided O/R
// cell crossed; the panels are laid out as map_panels.hpp says.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/results/aggregate.hpp"
#include "emrm/sim/vehicle.hpp"
#include "figure_parts.hpp"
#include "map_panels.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;

// What the colours mean, and what R does not say: the region is about loss levels, so an R cell
// whose Δv the strategies lower by 20 km/h is R all the same (the harm-reduction map shows it).
constexpr std::string_view kRegionMeaning =
    "G (green) fully avoidable, Y (yellow) aggressive avoidance required, O (orange) mitigatable, R (red) not "
    "mitigatable, grey infeasible. O and R speak of loss levels only: R means no strategy brings the loss below the "
    "unmitigated level, not that nothing lowers the harm; the harm-reduction map shows how much the best strategy "
    "lowers P(MAIS3+) inside a level.";
using detail::add_panel;
using detail::Axis;
using detail::boundary_function;
using detail::boundary_key_entry;
using detail::boundary_text;
using detail::boxes;
using detail::cell_box;
using detail::cell_columns;
using detail::cell_header;
using detail::distinct_values;
using detail::empty_layout;
using detail::file_stem;
using detail::fill_panel;
using detail::fixed_text;
using detail::is_o_or_r;
using detail::is_undecided;
using detail::kMapFontPt;
using detail::kMapHeightPx;
using detail::kMapTop;
using detail::kMapWidthPx;
using detail::kRegions;
using detail::lay_out_map;
using detail::map_script;
using detail::MapLayout;
using detail::MapPanel;
using detail::no_map_note;
using detail::panel_caption;
using detail::panel_extent;
using detail::panel_script;
using detail::region_colour;
using detail::region_of;
using detail::StemSet;
using detail::value_label;
using detail::value_of;
using detail::write_csv;

constexpr std::string_view kUndecidedLabel = "undecided (no proof either way)";
constexpr std::string_view kCrossKeyStyle = "pt 2 ps 1.2 lw 1.5 lc rgb 'black'";
constexpr std::string_view kInferredLabel = "inferred, not simulated";
constexpr std::string_view kDotKeyStyle = "pt 7 ps 0.5 lc rgb 'black'";

/// The point size of a mark over a cell, sized by the cell on the page (a panel's plot area is
/// roughly 80 % of its width and 70 % of its height): readable on the fine grid's flat cells, and
/// not filling a coarse grid's cell.
double mark_size(const MapLayout& layout, const MapPanel& p) {
  const double cell_w_px = layout.panel_w * layout.width_px * 0.8 / static_cast<double>(p.xs.size());
  const double cell_h_px = layout.cell_h * layout.height_px * 0.7 / static_cast<double>(p.ys.size());
  constexpr double kPointPx = 9.0;  // about the size of a cross at point size 1 at this size and font
  return std::clamp(0.6 * std::sqrt(cell_w_px * cell_h_px) / kPointPx, 0.5, 1.5);
}
/// The cross over an undecided cell; the dot, smaller, over an inferred one.
std::string cross_style(const MapLayout& layout, const MapPanel& p) {
  return fmt::format("pt 2 ps {:.2f} lw 1.5 lc rgb 'black'", mark_size(layout, p));
}
std::string dot_style(const MapLayout& layout, const MapPanel& p) {
  return fmt::format("pt 7 ps {:.2f} lc rgb 'black'", 0.4 * mark_size(layout, p));
}

/// A panel's cells in their region colours, undecided O/R cells crossed, inferred cells dotted: its
/// plot items, appended to `data` as datablocks; one CSV row per cell (cell_columns, then evidence)
/// appended to `rows`.
struct RegionPanel {
  std::vector<std::string> layers;
  std::string shares;  ///< "G a %, Y b %, O c %, R d % of N feasible[, k undecided][, j inferred]"
  std::size_t undecided = 0, inferred = 0;
};
RegionPanel region_panel(const MapLayout& layout, const MapPanel& p, std::vector<core::Row>& rows, std::string& data) {
  const auto regions = results::count_regions(p.cells, p.spec.grid);  // throws on a corrupt region
  std::vector<std::string> lines, crosses, dots;
  for (const auto& c : p.cells) {
    core::Row row = cell_columns(p, c);
    row.push_back(c.feasible ? core::enum_text(c.evidence) : std::string());
    lines.push_back(fmt::format("{} {}", cell_box(p, c), rgb_value(region_colour(region_of(c)))));
    if (is_undecided(c))
      crosses.push_back(fmt::format("{} {}", plot_number(value_of(c, p.spec.x)), plot_number(value_of(c, p.spec.y))));
    else if (c.inferred())
      dots.push_back(fmt::format("{} {}", plot_number(value_of(c, p.spec.x)), plot_number(value_of(c, p.spec.y))));
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
  if (!dots.empty()) {
    const std::string dot_block = fmt::format("inferred_{}", p.spec.letter);
    data += datablock(dot_block, dots);
    out.layers.push_back(fmt::format("${} using 1:2 with points {} notitle", dot_block, dot_style(layout, p)));
  }
  const auto share = [&](std::size_t n) { return fmt::format("{:.1f} %", regions.pct(n)); };
  out.shares = regions.feasible == 0
                   ? std::string("no feasible cell")
                   : fmt::format("G {}, Y {}, O {}, R {} of {} feasible", share(regions.g), share(regions.y),
                                 share(regions.o), share(regions.r), regions.feasible);
  if (!crosses.empty()) out.shares += fmt::format(", {} undecided", crosses.size());
  if (!dots.empty()) out.shares += fmt::format(", {} inferred", dots.size());
  out.undecided = crosses.size();
  out.inferred = dots.size();
  return out;
}

/// What backs the O/R cells of a map, as its caption says it.
struct EvidenceCounts {
  std::size_t undecided = 0, certified = 0, unproven = 0, inferred = 0;
  [[nodiscard]] std::string caption() const {
    std::string out;
    if (undecided > 0)
      out = fmt::format(
          " A cross marks the {} undecided O/R cells: a search found no avoidance, but nothing "
          "proves that none exists.",
          undecided);
    if (certified > 0)
      out += unproven == 0
                 ? fmt::format(" {} O/R cells ({}) are certified unavoidable.", undecided == 0 ? "All" : "The unmarked",
                               certified)
                 : fmt::format(" {} O/R cells are certified unavoidable, {} carry no evidence.", certified, unproven);
    if (inferred > 0)
      out += fmt::format(
          " A dot marks the {} cells an adaptive sweep inferred from the simulated cells around them "
          "(docs/adaptive.md): their region, not a simulation of their own.",
          inferred);
    return out;
  }
};
EvidenceCounts count_evidence(const std::vector<CellRecord>& cells) {
  EvidenceCounts n;
  for (const auto& c : cells) {
    n.inferred += c.inferred();
    if (!is_o_or_r(c)) continue;
    n.undecided += is_undecided(c);
    n.certified += c.evidence == campaign::CellEvidence::kCertificate;
    n.unproven += c.evidence != campaign::CellEvidence::kUndecided &&
                  c.evidence != campaign::CellEvidence::kCertificate && c.evidence != campaign::CellEvidence::kInferred;
  }
  return n;
}

/// The key of a region map: the regions, the stop boundary (`boundary` its label; none when empty),
/// the dot when some cell is inferred, the cross when some cell is undecided.
std::vector<std::string> region_key(const std::string& boundary, bool undecided, bool inferred) {
  std::vector<std::string> key;
  for (const auto& s : kRegions)
    key.push_back(
        fmt::format("NaN with boxes fs solid 1.0 lc rgb {} title {}", single_quoted(s.colour), single_quoted(s.label)));
  if (!boundary.empty()) key.push_back(boundary_key_entry(boundary));
  if (inferred) key.push_back(fmt::format("NaN with points {} title {}", kDotKeyStyle, double_quoted(kInferredLabel)));
  if (undecided)
    key.push_back(fmt::format("NaN with points {} title {}", kCrossKeyStyle, double_quoted(kUndecidedLabel)));
  return key;
}

}  // namespace

// --- the mitigability map -----------------------------------------------------------------------

Figure draw_mitigability_map(const std::vector<CellRecord>& records, const sim::FactorTable& factors,
                             const fs::path& dir, const MapPanels& panels, double latency_s) {
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
  const std::vector<std::string> key =
      region_key("stop boundary " + boundary_text(latency_s), evidence.undecided > 0, evidence.inferred > 0);
  const bool third_row = key.size() > 6;  // the cross or the dot: a third key row
  const MapLayout layout = lay_out_map(records, factors, panels, third_row ? 0.1 : 0.06);
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
      "Mitigability regions over {} cells: {}. Each rectangle is one cell: {} Dashed: the analytic stop "
      "boundary {} (g = {} m/s²) at the panel's fixed parameter.{}",
      layout.total_cells, core::join(caption_parts, "; "), kRegionMeaning, boundary_text(latency_s),
      plot_number(sim::kGravity_mps2), evidence.caption());
  write_csv(figure, dir, cell_header(factors, {"panel", "grid"}, {"region", "evidence"}), rows);

  const std::string body = map_script(layout, fmt::format("Mitigability regions ({} cells)", layout.total_cells),
                                      panel_plots, key, third_row ? 3 : 2, third_row ? 0 : -6, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kMapWidthPx, kMapHeightPx, kMapFontPt);
  return figure;
}

// --- the map under each actuation profile ---------------------------------------------------------

Figure draw_profile_maps(const std::vector<results::ProfileRun>& runs,
                         const std::vector<std::vector<CellRecord>>& records, const sim::FactorTable& factors,
                         const std::string& grid, const fs::path& dir) {
  Figure figure;
  figure.name = "regions_by_profile";
  figure.title = "Mitigability regions under each actuation profile";
  const std::size_t shown = std::min<std::size_t>({runs.size(), records.size(), 4});
  std::vector<std::string> names;  // the panels' specs view these
  names.reserve(shown);
  for (std::size_t i = 0; i < shown; ++i) names.push_back("profile " + runs[i].name);
  MapLayout layout = empty_layout(factors, 0.08);
  std::vector<std::size_t> run_of;  // the run each drawn panel shows
  for (std::size_t i = 0; i < shown; ++i) {
    add_panel(layout, i, {static_cast<char>('a' + i), grid, Axis::kSpeed, Axis::kTtc, Axis::kFriction, names[i]},
              records[i]);
    if (layout.panels.size() > run_of.size()) run_of.push_back(i);
  }
  if (layout.panels.empty()) {
    figure.note = fmt::format("no profile sweep of grid '{}' in this folder (emrm reproduce writes them)", grid);
    return figure;
  }
  std::vector<core::Row> rows;
  std::vector<std::string> caption_parts;
  std::string data, panel_plots;
  bool undecided = false, inferred = false;
  for (std::size_t k = 0; k < layout.panels.size(); ++k) {
    const MapPanel& p = layout.panels[k];
    const results::ProfileRun& run = runs[run_of[k]];
    const auto& a = run.actuation;
    const double latency_s = a.perception_latency_s + a.brake_dead_time_s + 0.5 * a.brake_ramp_s;
    const std::size_t before = rows.size();
    const RegionPanel drawn = region_panel(layout, p, rows, data);
    for (std::size_t r = before; r < rows.size(); ++r) rows[r].insert(rows[r].begin() + 1, run.name);
    undecided = undecided || drawn.undecided > 0;
    inferred = inferred || drawn.inferred > 0;
    caption_parts.push_back(
        panel_caption(p, fmt::format("{}; {}; stop boundary {}", drawn.shares, a.summary(), boundary_text(latency_s))));
    panel_plots += panel_script(layout, p, drawn.shares, drawn.layers, latency_s);
  }
  if (runs.size() > shown) figure.note = fmt::format("{} profiles; the first {} are drawn", runs.size(), shown);
  figure.title = fmt::format(
      "The fine map under each actuation profile (docs/actuation.md): {}. Colours as in the mitigability map; each "
      "panel's dashed line is its own stop boundary (perception latency, brake dead time and half the ramp before "
      "v/(2μg)).",
      core::join(caption_parts, "; "));
  write_csv(figure, dir, cell_header(factors, {"panel", "profile", "grid"}, {"region", "evidence"}), rows);
  const std::string body = map_script(layout, "Mitigability regions under each actuation profile", panel_plots,
                                      region_key("stop boundary of the profile", undecided, inferred), 2,
                                      undecided || inferred ? 0 : -6, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kMapWidthPx, kMapHeightPx, kMapFontPt);
  return figure;
}

// --- maps of any grid ------------------------------------------------------------------------------

namespace {

/// How a grid is cut into maps: its axes, the factor the stop boundary holds fixed, and the factors
/// each slice holds fixed (`sliced` those of them that vary over the grid).
struct GridCut {
  Axis x = Axis::kSpeed, y = Axis::kTtc, fixed = Axis::kFriction;
  std::vector<Axis> held, sliced;
};

/// The first two varying factors, in the factor table's order, as axes (a constant one fills in for
/// a 1-D or 0-D grid: a strip).
GridCut cut_grid(const std::vector<CellRecord>& cells, const sim::FactorTable& factors) {
  std::vector<Axis> varying, constant;
  for (std::size_t i = 0; i < factors.size(); ++i)
    (distinct_values(cells, Axis{i}).size() > 1 ? varying : constant).push_back(Axis{i});
  std::vector<Axis> order = varying;
  order.insert(order.end(), constant.begin(), constant.end());
  GridCut cut;
  cut.x = order[0];
  cut.y = order[1];
  cut.held.assign(order.begin() + 2, order.end());
  for (const Axis a : cut.held)
    if (std::find(varying.begin(), varying.end(), a) != varying.end()) cut.sliced.push_back(a);
  for (const Axis a : {Axis::kFriction, Axis::kTtc, Axis::kSpeed})  // the boundary's third factor, when it has one
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
      key.push_back(static_cast<std::size_t>(std::lower_bound(values.begin(), values.end(), v - detail::kSameValue) -
                                             values.begin()));
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
std::string held_text(const sim::FactorTable& table, const GridCut& cut, const GridSlice& slice,
                      const std::vector<Axis>& factors) {
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < cut.held.size(); ++i)
    if (std::find(factors.begin(), factors.end(), cut.held[i]) != factors.end())
      parts.push_back(fixed_text(table, cut.held[i], slice.held_values[i]));
  return core::join(parts, ", ");
}

/// "map_GRID", then "_FACTOR_VALUE" for each factor the slice is cut along (a categorical factor's
/// value by its level's name).
std::string slice_stem(const sim::FactorTable& factors, const std::string& grid, const GridCut& cut,
                       const GridSlice& slice) {
  std::string stem = "map_" + file_stem(grid);
  for (std::size_t i = 0; i < cut.held.size(); ++i)
    if (std::find(cut.sliced.begin(), cut.sliced.end(), cut.held[i]) != cut.sliced.end()) {
      const sim::Factor& f = factor_of(factors, cut.held[i]);
      stem += fmt::format("_{}_{}", f.key, file_stem(value_label(f, slice.held_values[i])));
    }
  return stem;
}

constexpr int kSliceWidthPx = 1000, kSliceHeightPx = 760;

/// "grid 'wet'", "grid 'wet', slice μ = 0.5": what a slice's maps show.
std::string slice_what(const sim::FactorTable& factors, const std::string& grid, const GridCut& cut,
                       const GridSlice& slice) {
  const std::string slice_label = held_text(factors, cut, slice, cut.sliced);
  return fmt::format("grid '{}'{}", grid, slice_label.empty() ? "" : ", slice " + slice_label);
}

/// A slice of a grid as the one panel of a page, above a key strip `key_h` high.
MapLayout slice_layout(const sim::FactorTable& factors, const std::string& grid, const GridCut& cut,
                       const GridSlice& slice, double key_h) {
  MapLayout layout = empty_layout(factors, key_h);
  layout.panel_w = 1.0;
  layout.cell_h = kMapTop - layout.key_h;
  layout.width_px = kSliceWidthPx;
  layout.height_px = kSliceHeightPx;
  const std::string panel_title = "Grid " + grid;  // the spec views it
  MapPanel p;
  p.spec = {'a', grid, cut.x, cut.y, cut.fixed, panel_title};
  p.factors = factors;
  p.lettered = false;
  p.origin_y = layout.key_h;
  fill_panel(p, slice.cells);
  p.held = held_text(factors, cut, slice, cut.held);
  layout.total_cells = p.cells.size();
  layout.panels.push_back(std::move(p));
  return layout;
}

/// One slice of a grid as a map of one panel, in the mitigability map's colours and crosses.
Figure draw_slice_map(const sim::FactorTable& factors, const std::string& grid, const GridCut& cut,
                      const GridSlice& slice, const std::string& name, const fs::path& dir, double latency_s) {
  Figure figure;
  figure.name = name;
  const std::string slice_label = held_text(factors, cut, slice, cut.sliced);
  const std::string what = slice_what(factors, grid, cut, slice);
  const EvidenceCounts evidence = count_evidence(slice.cells);
  // The key in two columns: three rows, or four with the cross or the dot (the key's height does
  // not move whether the panel has a stop boundary).
  const auto laid_out = [&](int key_rows) { return slice_layout(factors, grid, cut, slice, 0.01 + 0.04 * key_rows); };
  const bool boundary = !boundary_function(laid_out(3).panels.front(), latency_s).empty();
  const std::vector<std::string> key =
      region_key(boundary ? "stop boundary " + boundary_text(latency_s) : std::string(), evidence.undecided > 0,
                 evidence.inferred > 0);
  const int key_rows = std::max(3, static_cast<int>((key.size() + 1) / 2));
  const MapLayout layout = laid_out(key_rows);
  const MapPanel& p = layout.panels.front();

  std::vector<core::Row> rows;
  std::string data;
  const RegionPanel drawn = region_panel(layout, p, rows, data);
  for (auto& row : rows) row[0] = slice_label;
  figure.title = fmt::format(
      "Mitigability regions of {}: {} ({} cells; {}). Each rectangle is one cell: {}{}{}", what, panel_extent(p),
      p.cells.size(), drawn.shares, kRegionMeaning,
      boundary ? fmt::format(" Dashed: the analytic stop boundary {} (g = {} m/s²) at {}.", boundary_text(latency_s),
                             plot_number(sim::kGravity_mps2), fixed_text(factors, p.spec.fixed, p.fixed))
               : std::string(),
      evidence.caption());
  write_csv(figure, dir, cell_header(factors, {"slice", "grid"}, {"region", "evidence"}), rows);
  const std::string body =
      map_script(layout, fmt::format("Mitigability regions, {}", enhanced_literal(what)),
                 panel_script(layout, p, drawn.shares, drawn.layers, latency_s), key, key_rows, 0, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kSliceWidthPx, kSliceHeightPx, kMapFontPt);
  return figure;
}

/// The report's entry for slices left undrawn: their count and values.
Figure undrawn_slices(const sim::FactorTable& factors, const std::string& grid, const std::string& name,
                      const GridCut& cut, const std::vector<GridSlice>& slices, std::size_t drawn) {
  Figure figure;
  figure.name = name;
  figure.title = fmt::format("Mitigability regions of grid '{}', further slices", grid);
  std::vector<std::string> left;
  for (std::size_t i = drawn; i < slices.size(); ++i) left.push_back(held_text(factors, cut, slices[i], cut.sliced));
  figure.note = fmt::format("grid '{}' has {} slices; the first {} are drawn, these not: {}", grid, slices.size(),
                            drawn, core::join(left, "; "));
  return figure;
}

}  // namespace

std::vector<Figure> draw_grid_maps(const std::vector<CellRecord>& records, const sim::FactorTable& factors,
                                   const fs::path& dir, const GridMapOptions& options) {
  std::vector<Figure> figures;
  StemSet stems;
  for (const auto& grid : results::grid_names(records)) {
    if (std::find(options.skip.begin(), options.skip.end(), grid) != options.skip.end()) continue;
    const std::vector<CellRecord> cells = results::records_of_grid(records, grid);
    const GridCut cut = cut_grid(cells, factors);
    const std::vector<GridSlice> slices = slices_of(cells, cut);
    const std::size_t drawn = std::min(slices.size(), options.max_slices_per_grid);
    for (std::size_t i = 0; i < drawn; ++i) {
      const std::string stem = stems.unique(slice_stem(factors, grid, cut, slices[i]));
      figures.push_back(draw_slice_map(factors, grid, cut, slices[i], stem, dir, options.latency_s));
      // Beside it the harm reduction, which the regions hide inside a loss level (an R cell whose
      // Δv the strategies lower by 20 km/h is R all the same).
      figures.push_back(detail::draw_harm_map(
          slice_layout(factors, grid, cut, slices[i], detail::harm_map_key_height(slices[i].cells)), dir,
          options.latency_s, stems.unique("harm_" + stem), slice_what(factors, grid, cut, slices[i])));
    }
    if (drawn < slices.size())
      figures.push_back(
          undrawn_slices(factors, grid, stems.unique("map_" + file_stem(grid) + "_more"), cut, slices, drawn));
  }
  return figures;
}

// --- a speed × TTC map with curves over it (boundary_figures.cpp) ----------------------------------

namespace detail {

namespace {
constexpr int kOverlaidWidthPx = 1300, kOverlaidHeightPx = 900;
constexpr std::size_t kOverlaidKeyColumns = 3;
constexpr std::size_t kThreeColumnTitle = 40;  // characters of the longest title three columns fit
constexpr int kOverlaidKeyWidthAdjust = 0;
}  // namespace

MapCaption draw_overlaid_map(const Figure& figure, const OverlaidMap& map) {
  const EvidenceCounts evidence = count_evidence(map.cells);
  std::vector<std::string> key = region_key("", evidence.undecided > 0, evidence.inferred > 0);
  key.insert(key.end(), map.key.begin(), map.key.end());
  // Gnuplot lays the key out in as many columns as its longest title lets fit across the figure:
  // three up to about 40 characters, two beyond ("oracle (best strategy in hindsight) avoids
  // above"); the strip is given the rows that takes, or the last rows fall off the figure.
  std::size_t longest = 0;
  for (const auto& entry : key)
    if (const auto at = entry.rfind(" title "); at != std::string::npos)
      longest = std::max(longest, entry.size() - at - std::string_view(" title ''").size());
  const std::size_t columns = longest > kThreeColumnTitle ? kOverlaidKeyColumns - 1 : kOverlaidKeyColumns;
  const std::size_t key_rows = (key.size() + columns - 1) / columns;
  MapLayout layout = empty_layout(map.factors, 0.025 + 0.03 * static_cast<double>(key_rows));
  layout.panel_w = 1.0;
  layout.cell_h = kMapTop - layout.key_h;
  layout.width_px = kOverlaidWidthPx;
  layout.height_px = kOverlaidHeightPx;
  layout.total_cells = map.cells.size();
  const std::string panel_title = "Grid " + map.grid;  // the spec views it
  MapPanel p;
  p.spec = {'a', map.grid, Axis::kSpeed, Axis::kTtc, Axis::kFriction, panel_title};
  p.factors = map.factors;
  p.lettered = false;
  p.origin_y = layout.key_h;
  fill_panel(p, map.cells);
  p.held = map.held;

  std::vector<core::Row> cell_rows;  // the cells are in the store's exports; the figure's CSV is the caller's
  std::string data = map.data;
  RegionPanel drawn = region_panel(layout, p, cell_rows, data);
  drawn.layers.insert(drawn.layers.end(), map.layers.begin(), map.layers.end());
  const std::string body =
      map_script(layout, enhanced_literal(map.title), panel_plot(layout, p, drawn.shares, drawn.layers), key,
                 static_cast<int>(key_rows), kOverlaidKeyWidthAdjust, layout.key_h);
  render_png_and_svg(figure.png, figure.svg, data, body, kOverlaidWidthPx, kOverlaidHeightPx, kMapFontPt);
  return {panel_extent(p), drawn.shares, evidence.caption()};
}

}  // namespace detail

}  // namespace emrm::report
