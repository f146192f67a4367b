// The brakes' sensitivity figure (docs/actuation.md, "Sensitivity"): G of a grid against the brake
// dead time and against the peak deceleration, from the stop's closed form.

#include <fmt/format.h>

#include <cmath>

#include "emrm/report/figures.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/results/sensitivity.hpp"
#include "figure_parts.hpp"

namespace emrm::report {

Figure draw_brake_sensitivity(const std::vector<campaign::CellRecord>& records, const std::string& grid,
                              const sim::ActuationConfig& actuation, const std::filesystem::path& dir) {
  Figure figure;
  figure.name = "brake_sensitivity";
  figure.title = fmt::format("Brake sensitivity on grid '{}'", grid);
  const results::BrakeSensitivity s = results::brake_sensitivity(records, grid, actuation);
  if (std::isnan(s.base_g_pct)) {
    figure.note = fmt::format("no brake sensitivity: grid '{}' has no feasible cell in the store", grid);
    return figure;
  }
  std::vector<core::Row> rows;
  std::vector<std::string> dead, cap;
  for (std::size_t k = 0; k < s.dead_times_s.size(); ++k) {
    rows.push_back({"brake_dead_time_s", plot_number(s.dead_times_s[k]), plot_percent(s.dead_time_g_pct[k])});
    dead.push_back(fmt::format("{} {}", plot_number(s.dead_times_s[k]), plot_percent(s.dead_time_g_pct[k])));
  }
  for (std::size_t k = 0; k < s.peak_decels_mps2.size(); ++k) {
    rows.push_back({"max_decel_mps2", plot_number(s.peak_decels_mps2[k]), plot_percent(s.peak_decel_g_pct[k])});
    cap.push_back(fmt::format("{} {}", plot_number(s.peak_decels_mps2[k]), plot_percent(s.peak_decel_g_pct[k])));
  }
  detail::write_csv(figure, dir, {"parameter", "value", "g_pct"}, rows);
  figure.title = fmt::format(
      "G (the emergency stop avoids) on grid '{}' against the brake dead time (left) and the peak deceleration "
      "(right), one parameter changed at a time from the scene's brakes (dashed: the scene's G, {:.1f} %); "
      "computed from the stop's closed form, not swept.",
      grid, s.base_g_pct);
  const std::string body = fmt::format(
      "set multiplot layout 1,2 title {1} font ',16'\n"
      "set tics out nomirror\nset border 3\nset key off\nset grid lc rgb '#dddddd'\nset yrange [0:100]\n"
      "set ylabel 'G (% of feasible cells)'\n"
      "set title 'Brake dead time'\nset xlabel 'brake dead time (s)'\nset xrange [0:0.6]\n"
      "plot $dead using 1:2 with linespoints lw 2 pt 7 lc rgb '#2e7d32', {0} with lines dt 2 lc rgb '#555555'\n"
      "set title 'Peak deceleration'\nset xlabel 'peak deceleration (m/s²)'\nset xrange [{2}:{3}]\n"
      "plot $cap using 1:2 with linespoints lw 2 pt 7 lc rgb '#2e7d32', {0} with lines dt 2 lc rgb '#555555'\n"
      "unset multiplot\n",
      plot_number(s.base_g_pct), single_quoted(fmt::format("How the brakes move G, grid '{}'", enhanced_literal(grid))),
      plot_number(s.peak_decels_mps2.back()), plot_number(s.peak_decels_mps2.front()));
  render_png_and_svg(figure.png, figure.svg, datablock("dead", dead) + datablock("cap", cap), body, 1300, 600, 13);
  return figure;
}

}  // namespace emrm::report
