#pragma once

// Private to the maps (map_panels.cpp, region_maps.cpp, harm_reduction_map.cpp): the panel layout
// the mitigability and harm-reduction maps share — grids, axes, cell rectangles, the stop
// boundary — and the region colours.

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/campaign/records.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "figure_parts.hpp"

namespace emrm::report::detail {

struct RegionStyle {
  std::string_view region;
  std::string_view colour;
  std::string_view label;
};
inline constexpr std::array<RegionStyle, 5> kRegions{{
    {"G", "#2ca02c", "G fully avoidable"},
    {"Y", "#ffdd57", "Y aggressive avoidance required"},
    {"O", "#ff7f0e", "O mitigatable"},
    {"R", "#d62728", "R not mitigatable"},
    {"infeasible", "#bdbdbd", "infeasible"},
}};

/// "v = 50 km/h", "μ = 1", …: the factor at the value, as a panel's heading says what it holds.
[[nodiscard]] std::string fixed_text(const sim::FactorTable& factors, Axis a, double v);
/// A factor's value as the figures write it: a categorical factor's level by name, else the number.
[[nodiscard]] std::string value_label(const sim::Factor& factor, double v);

/// The cell's region as a map shows it: G, Y, O, R, or "infeasible".
[[nodiscard]] std::string region_of(const campaign::CellRecord& r);

/// The region's colour "#rrggbb" (kRegions); the infeasible grey for any other name.
[[nodiscard]] std::string region_colour(std::string_view region);

struct PanelSpec {
  char letter = 0;
  std::string grid;
  Axis x, y, fixed;
  std::string name;  ///< "Speed × TTC, coarse grid"
};

/// One panel whose grid has cells: its cells, their extent, and where it sits on the page.
struct MapPanel {
  PanelSpec spec;
  sim::FactorTable factors;  ///< the scenario's: the axes' labels
  std::vector<campaign::CellRecord> cells;
  std::vector<double> xs, ys;  ///< the distinct values along each axis
  double hx = 0.0, hy = 0.0;   ///< half a cell's width and height
  double fixed = 0.0;          ///< the median of the factor the panel holds fixed
  std::string held;            ///< what the panel holds fixed, as its heading says it: "μ = 1"
  bool lettered = true;        ///< headed "(a) NAME" (a panel of the 2×2 layout), else "NAME"
  double origin_x = 0.0, origin_y = 0.0;
};

inline constexpr int kMapWidthPx = 1400, kMapHeightPx = 1000, kMapFontPt = 13;

/// A map's 2×2 layout above a key strip `key_h` high (screen units): the panels that have cells,
/// in order (a)–(d); a missing grid leaves its slot empty but for a label, and is said in `missing`.
struct MapLayout {
  sim::FactorTable factors;  ///< the scenario's, each panel's
  std::vector<MapPanel> panels;
  std::vector<std::string> missing;
  std::string missing_labels;  ///< gnuplot labels for the empty slots, drawn with the key strip
  std::size_t total_cells = 0;
  double key_h = 0.0, cell_h = 0.0;
  double panel_w = 0.5;  ///< a panel's width (screen units)
  int width_px = kMapWidthPx, height_px = kMapHeightPx;
};

/// Gives `p` its cells and their extent along the axes of its spec.
void fill_panel(MapPanel& p, std::vector<campaign::CellRecord> cells);

/// Puts panel `spec` in slot `i` (0–3, row by row) of `layout` with the cells of its grid in
/// `records`; a grid without cells leaves the slot empty but for a label.
void add_panel(MapLayout& layout, std::size_t i, const PanelSpec& spec,
               const std::vector<campaign::CellRecord>& records);

inline constexpr double kMapTop = 0.955;  // below the multiplot's title

/// A layout without panels: two rows of them above a key strip `key_h` high.
[[nodiscard]] MapLayout empty_layout(const sim::FactorTable& factors, double key_h);

/// The 2×2 layout of the paper's four grids `grids` over `records`, the key strip `key_h` high;
/// the one grid of the four in the store alone takes the whole page.
[[nodiscard]] MapLayout lay_out_map(const std::vector<campaign::CellRecord>& records, const sim::FactorTable& factors,
                                    const MapPanels& grids, double key_h);

/// The figure's note when none of the four grids is in the store.
[[nodiscard]] std::string no_map_note(std::string_view what, const MapPanels& grids);

/// "5 speeds × 6 TTCs, μ = 1": the panel's extent, as its heading and the caption state it.
[[nodiscard]] std::string panel_extent(const MapPanel& p);

/// The panel's part of the figure's caption, `detail` after its cell count.
[[nodiscard]] std::string panel_caption(const MapPanel& p, std::string_view detail);

/// The CSV columns every map starts a cell's row with: panel, grid, every factor, region.
[[nodiscard]] core::Row cell_columns(const MapPanel& p, const campaign::CellRecord& c);
/// A map CSV's header: `before`, the factors' keys, `after`.
[[nodiscard]] core::Row cell_header(const sim::FactorTable& factors, std::initializer_list<std::string> before,
                                    std::initializer_list<std::string> after);

/// A cell's rectangle, the start of its datablock line: x y half-width half-height.
[[nodiscard]] std::string cell_box(const MapPanel& p, const campaign::CellRecord& c);

/// The plot item drawing the rectangles of datablock `block` (x y hx hy COLOUR), coloured by `colour`
/// ("rgb variable", "palette"). Neighbours overlap by 3 % of a cell so that antialiased edges leave
/// no seams between them.
[[nodiscard]] std::string boxes(std::string_view block, std::string_view colour);

/// The stop boundary as the key and the captions say it: "TTC = v/(2μg)", or "TTC = L s + v/(2μg)".
[[nodiscard]] std::string boundary_text(double latency_s);

/// The dashed analytic stop boundary TTC = L + v/(2μg) as a gnuplot function of the panel's x;
/// "" when there is none to draw over the panel's factors, or none at all (a NaN latency: the scene's
/// family has no stop boundary).
[[nodiscard]] std::string boundary_function(const MapPanel& p, double latency_s);

/// One panel of the multiplot: its place, its heading with `subtitle` under it, its axes, then
/// `layers` (plot items over its cells, in drawing order).
[[nodiscard]] std::string panel_plot(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                                     const std::vector<std::string>& layers);

/// panel_plot with the closed-form stop boundary on top of `layers`.
[[nodiscard]] std::string panel_script(const MapLayout& layout, const MapPanel& p, std::string_view subtitle,
                                       std::vector<std::string> layers, double latency_s);

/// The key's entry for a dashed stop boundary titled `label`.
[[nodiscard]] std::string boundary_key_entry(const std::string& label);

/// The whole map: a multiplot titled `title` holding `panels` (panel_script), then the key strip
/// (`key` entries in at most `key_rows` rows, `strip_h` high) with the empty slots' labels.
[[nodiscard]] std::string map_script(const MapLayout& layout, std::string_view title, const std::string& panels,
                                     const std::vector<std::string>& key, int key_rows, int key_width_adjust,
                                     double strip_h);

/// The harm-reduction map's key strip (screen units): taller than the region maps', the colour bar
/// sits above the key entries, which take a second row when some of `cells` are inferred (an
/// adaptive sweep's: hatched, with no reduction to show).
[[nodiscard]] double harm_map_key_height(const std::vector<campaign::CellRecord>& cells);

/// The harm-reduction map (harm_reduction_map.cpp) of `layout`'s panels, with the stop boundary at
/// `latency_s`, written to `dir` as `name`.png|svg|csv. `what` ("grid 'wet', slice μ = 0.5") says
/// in its title what it maps; empty for the paper's four grids.
[[nodiscard]] Figure draw_harm_map(const MapLayout& layout, const std::filesystem::path& dir, double latency_s,
                                   const std::string& name, std::string_view what);

}  // namespace emrm::report::detail
