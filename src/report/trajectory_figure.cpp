#include "emrm/report/trajectory_figure.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"

namespace emrm::report {
namespace {

std::string outline(const core::OrientedBox& box) {
  std::string out;
  const auto corners = box.corners();
  for (int i = 0; i <= 4; ++i) out += fmt::format("{:.4f} {:.4f}\n", corners[i % 4].x, corners[i % 4].y);
  return out + "\n";
}

std::string edges_of(const std::vector<sim::TreeEdge>& tree, bool fail_safe) {
  std::string out;
  for (const auto& edge : tree) {
    if (edge.fail_safe != fail_safe) continue;
    for (const auto& p : edge.points) out += fmt::format("{:.4f} {:.4f}\n", p.state.x_m, p.state.y_m);
    out += "\n";
  }
  return out.empty() ? "nan nan\n" : out;  // gnuplot refuses an empty data file
}

std::string outcome_text(const sim::StrategyOutcome& o) {
  std::string text = o.avoided ? "avoided"
                               : fmt::format("{} at {:.1f} km/h, L{}", o.contact ? "contact" : "road departure",
                                             o.impact.impact_speed_mps * 3.6, o.impact.loss_level);
  if (!o.chosen_strategy.empty()) text += " (chose " + o.chosen_strategy + ")";
  else if (!o.adopted_from.empty()) text += " (as " + o.adopted_from + ")";
  return text;
}

}  // namespace

void draw_cell_figure(const sim::CellResult& result, const sim::SceneConfig& config,
                      const std::filesystem::path& output) {
  const int panels = std::max<int>(1, static_cast<int>(result.strategies.size()));
  const std::string terminal = gnuplot_terminal(output, 1000, 330 * panels);
  core::TempDir dir("emrm-figure");
  const auto file = [&](const std::string& name) { return (dir.path() / name).string(); };

  const sim::Scene scene(config, result.input);
  const double v0 = scene.initial_speed_mps();
  const double y_min = config.road.drivable_min_y_m();
  const double y_max = config.road.drivable_max_y_m();
  const double x_lo = scene.ego_initial().x_m - config.ego.length_m;
  const double x_hi = scene.truck_far_x_m() + 3.0 * config.ego.length_m;
  const double truck_top = scene.truck_at(0.0).box.center.y + config.truck.length_m / 2.0;

  std::string script = terminal + "\n";
  script += fmt::format("set output '{}'\n", output.string());
  script += fmt::format("set multiplot layout {},1 title '{:.0f} km/h, TTC {:.2f} s, {} {:.2f}, passage {:.2f} m: region {}'\n",
                        panels, result.input.speed_kph, result.input.ttc_s, "{/Symbol m}", result.input.mu,
                        result.input.passage_m, sim::region_name(result.region));
  script += "set size ratio -1\nset key outside right top font ',8'\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n";
  script += fmt::format("set xrange [{:.2f}:{:.2f}]\nset yrange [{:.2f}:{:.2f}]\n", x_lo, x_hi, y_min - 1.0,
                        std::max(y_max, truck_top) + 1.0);
  script += "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n";
  script += fmt::format("set cbrange [0:{:.3f}]\nset cblabel 'speed (m/s)'\n", v0);

  core::write_file(file("road.dat"), fmt::format("{0} {2}\n{1} {2}\n\n{0} {3}\n{1} {3}\n", x_lo, x_hi, y_min, y_max));
  core::write_file(file("centre.dat"), fmt::format("{0} 0\n{1} 0\n", x_lo, x_hi));
  core::write_file(file("truck0.dat"), outline(scene.truck_at(0.0).box));

  for (std::size_t i = 0; i < result.strategies.size(); ++i) {
    const auto& o = result.strategies[i];
    const std::string tag = std::to_string(i);
    core::write_file(file("goal" + tag + ".dat"), edges_of(o.tree, false));
    core::write_file(file("failsafe" + tag + ".dat"), edges_of(o.tree, true));
    std::string path;
    for (const auto& p : o.path)
      path += fmt::format("{:.4f} {:.4f} {:.4f}\n", p.state.x_m, p.state.y_m, p.state.speed_mps());
    core::write_file(file("path" + tag + ".dat"), path.empty() ? "nan nan nan\n" : path);
    const double t_end = o.path.empty() ? 0.0 : o.path.back().t_s;
    core::write_file(file("truck_end" + tag + ".dat"), outline(scene.truck_at(t_end).box));
    std::string ego = outline(scene.ego_box(scene.ego_initial()));
    if (!o.path.empty()) ego += outline(scene.ego_box(o.path.back().state));
    core::write_file(file("ego" + tag + ".dat"), ego);

    script += fmt::format("set title '{}: {}' noenhanced\n", o.strategy, outcome_text(o));
    script += fmt::format(
        "plot '{}' w l lc 'black' lw 1.5 notitle, '{}' w l lc 'gray50' dt 2 notitle, "
        "'{}' w l lc rgb '#2ca02c' lw 0.6 title 'goal tree', '{}' w l lc rgb '#ff7f0e' lw 0.6 title 'fail-safe', "
        "'{}' w l dt 2 lc 'gray40' title 'truck t=0', '{}' w l lc 'gray20' lw 1.5 title 'truck at end', "
        "'{}' w l lc rgb '#1f77b4' lw 1.2 title 'ego', '{}' u 1:2:3 w l lw 3 lc palette title 'executed'\n",
        file("road.dat"), file("centre.dat"), file("goal" + tag + ".dat"), file("failsafe" + tag + ".dat"),
        file("truck0.dat"), file("truck_end" + tag + ".dat"), file("ego" + tag + ".dat"), file("path" + tag + ".dat"));
  }
  script += "unset multiplot\n";
  if (output.has_parent_path()) std::filesystem::create_directories(output.parent_path());
  run_gnuplot(script, dir.path());
}

}  // namespace emrm::report
