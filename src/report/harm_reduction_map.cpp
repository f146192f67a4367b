// The harm-reduction map (docs/report.md): each feasible cell coloured by how much the best
// strategy lowers P(MAIS3+) below the unmitigated reference's, on one scale for all panels, in the
// panel layout the mitigability map shares (map_panels.hpp).

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/core/text.hpp"
#include "emrm/report/figures.hpp"
#include "emrm/report/gnuplot.hpp"
#include "figure_parts.hpp"
#include "map_panels.hpp"

namespace emrm::report {
namespace {

namespace fs = std::filesystem;
using campaign::CellRecord;
using detail::lay_out_map;
using detail::MapLayout;
using detail::no_map_note;

constexpr std::string_view kReductionLabel = "reduction of P(MAIS3+) by the best strategy";
// An inferred cell (an adaptive sweep's) has a region but no strategy outcome: no reduction to colour.
constexpr std::string_view kInferredFill = "fs pattern 2 noborder lc rgb '#8c8c8c'";
constexpr std::string_view kInferredLabel = "inferred region, not simulated";

// The key strip's rows below the colour bar: one, or two with the hatched inferred cells.
constexpr double kKeyRow = 0.03;
constexpr double kColourBarStrip = 0.075;  // the colour bar, its label and tics, above the rows

}  // namespace

namespace detail {

double harm_map_key_height(const std::vector<CellRecord>& cells) {
  const bool any_inferred = std::any_of(cells.begin(), cells.end(), [](const CellRecord& c) { return c.inferred(); });
  return kColourBarStrip + 0.005 + kKeyRow * (any_inferred ? 2 : 1);
}

Figure draw_harm_map(const MapLayout& layout, const fs::path& dir, double latency_s, const std::string& name,
                     std::string_view what) {
  Figure figure;
  figure.name = name;
  // One scale for all panels, so that a colour means the same reduction everywhere.
  double largest = 0.0;
  for (const MapPanel& p : layout.panels)
    for (const auto& c : p.cells)
      if (c.simulated()) largest = std::max(largest, c.p_mais3_reduction);

  std::vector<core::Row> rows;
  std::vector<std::string> caption_parts;
  std::string data, panel_plots;
  bool colour_bar = false;
  std::size_t inferred_cells = 0;
  for (const MapPanel& p : layout.panels) {
    std::vector<std::string> reduced, infeasible, unknown;
    std::size_t feasible = 0, o_or_r = 0, o_or_r_reduced = 0, unsearched = 0;
    double sum = 0.0, most = 0.0;
    for (const auto& c : p.cells) {
      core::Row row = cell_columns(p, c);
      // Certified with the reference at L4: no search ran (the level cannot fall), so the reduction
      // is the emergency stop's, a lower bound on what a least-loss search might find.
      unsearched += c.feasible && c.evidence == campaign::CellEvidence::kCertificate &&
                    c.mitigation_evidence == sim::MitigationEvidence::kProof;
      if (c.inferred()) {
        row.insert(row.end(), 4, std::string());
        unknown.push_back(fmt::format("{} 0", cell_box(p, c)));
      } else if (c.feasible) {
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
    if (!unknown.empty()) {
      const std::string block = fmt::format("inferred_{}", p.spec.letter);
      data += datablock(block, unknown);
      layers.push_back(
          fmt::format("${} using 1:2:($3*1.03):($4*1.03) with boxxyerror {} notitle", block, kInferredFill));
      inferred_cells += unknown.size();
    }
    std::string summary = feasible == 0
                              ? std::string("no simulated feasible cell")
                              : fmt::format("reduction mean {:.3f}, max {:.3f} over {} {}; {} of {} O/R reduced",
                                            sum / static_cast<double>(feasible), most, feasible,
                                            unknown.empty() ? "feasible" : "simulated", o_or_r_reduced, o_or_r);
    if (!unknown.empty()) summary += fmt::format("; {} inferred, not simulated", unknown.size());
    caption_parts.push_back(panel_caption(
        p, unsearched == 0 ? summary
                           : fmt::format("{}; {} certified L4 cells not searched, their reduction the emergency "
                                         "stop's (a lower bound)",
                                         summary, unsearched)));
    // The colour bar is drawn once, with the first panel that has a feasible cell, in the key strip.
    const bool with_bar = !colour_bar && !reduced.empty();
    const double bar_y = layout.key_h - kColourBarStrip + 0.04;
    if (with_bar)
      panel_plots += fmt::format(
          "set colorbox user horizontal origin screen 0.42,{} size screen 0.36,0.018\n"
          "set label 80 {} at screen 0.41,{} right\n",
          plot_number(bar_y), single_quoted(kReductionLabel), plot_number(bar_y + 0.009));
    panel_plots += panel_script(layout, p, summary, layers, latency_s);
    if (with_bar) panel_plots += "unset colorbox\nunset label 80\n";
    colour_bar = colour_bar || with_bar;
  }

  figure.note = core::join(layout.missing, "; ");
  figure.title = fmt::format(
      "Harm reduction by the best strategy{} over {} cells: {}. Each feasible cell is coloured by the "
      "unmitigated reference's P(MAIS3+) minus the lowest P(MAIS3+) of the strategies (0 to {:.3f}): an avoided "
      "cell (G, Y) counts its whole unmitigated risk, an O or R cell the mitigation inside its loss level, which the "
      "mitigability map does not show. Grey: infeasible.{} Dashed: the analytic stop boundary {} at the panel's "
      "fixed parameter.",
      what.empty() ? std::string() : fmt::format(" in {}", what), layout.total_cells, core::join(caption_parts, "; "),
      largest,
      inferred_cells == 0
          ? std::string()
          : fmt::format(" Hatched: the {} cells an adaptive sweep inferred (docs/adaptive.md); they have a region but "
                        "no strategy outcome, so no reduction, and the means above are over the simulated cells only.",
                        inferred_cells),
      boundary_text(latency_s));
  write_csv(
      figure, dir,
      cell_header(layout.factors, {"panel", "grid"},
                  {"region", "unmitigated_p_mais3", "p_mais3_reduction", "unmitigated_p_fatal", "p_fatal_reduction"}),
      rows);

  // Sequential, light to dark, and apart from the region colours and the grey of infeasible cells.
  const std::string scale = fmt::format(
      "set palette defined (0 '#f2f0f7', 0.35 '#9e9ac8', 0.7 '#6a51a3', 1 '#3f007d')\nset cbrange [0:{}]\n"
      "set cbtics out\nset format cb '%g'\nunset colorbox\n",
      plot_number(largest > 0.0 ? largest : 1.0));
  std::vector<std::string> key{fmt::format("NaN with boxes fs solid 1.0 lc rgb {} title 'infeasible'",
                                           single_quoted(region_colour("infeasible"))),
                               boundary_key_entry("stop boundary " + boundary_text(latency_s))};
  if (inferred_cells > 0)
    key.insert(key.begin() + 1,
               fmt::format("NaN with boxes {} title {}", kInferredFill, single_quoted(kInferredLabel)));
  const std::string body =
      map_script(layout,
                 what.empty() ? fmt::format("Harm reduction by the best strategy ({} cells)", layout.total_cells)
                              : fmt::format("Harm reduction by the best strategy, {}", enhanced_literal(what)),
                 scale + panel_plots, key, inferred_cells > 0 ? 2 : 1, 0, layout.key_h - kColourBarStrip);
  render_png_and_svg(figure.png, figure.svg, data, body, layout.width_px, layout.height_px, kMapFontPt);
  return figure;
}

}  // namespace detail

Figure draw_harm_reduction_map(const std::vector<CellRecord>& records, const sim::FactorTable& factors,
                               const fs::path& dir, const MapPanels& panels, double latency_s) {
  const MapLayout layout = lay_out_map(records, factors, panels, detail::harm_map_key_height(records));
  if (layout.panels.empty()) {
    Figure figure;
    figure.name = "harm_reduction_map";
    figure.title = "Harm reduction by the best strategy";
    figure.note = no_map_note("harm reduction map", panels);
    return figure;
  }
  return detail::draw_harm_map(layout, dir, latency_s, "harm_reduction_map", "");
}

}  // namespace emrm::report
