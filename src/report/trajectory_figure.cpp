// The trajectory figures: the ego's paths past the hazard and every other actor, titled by the
// T-junction's factors (sim::TJunctionCell) or, in another family, by the cell's own.

#include "emrm/report/trajectory_figure.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "emrm/core/process.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/gnuplot.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/strategy.hpp"

namespace emrm::report {
namespace {

// Speed along a path (viridis), the same in the figure of one cell and in the trajectory grid.
constexpr const char* kSpeedPalette =
    "set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')\n";

// The drivable road's two edges from x_lo to x_hi, as two gnuplot data blocks.
std::string road_edges(double x_lo, double x_hi, double y_min, double y_max) {
  return fmt::format("{0} {2}\n{1} {2}\n\n{0} {3}\n{1} {3}\n", x_lo, x_hi, y_min, y_max);
}

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
  if (!o.chosen_strategy.empty())
    text += " (chose " + o.chosen_strategy + ")";
  else if (!o.adopted_from.empty())
    text += " (as " + o.adopted_from + ")";
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
  const double y_min = scene.road().min_y_m;
  const double y_max = scene.road().max_y_m;
  const double x_lo = scene.ego_initial().x_m - config.ego.length_m;
  const double x_hi = scene.passed_x_m() + 3.0 * config.ego.length_m;
  const double truck_top = scene.hazard().y_extent_at(0.0).second;
  const std::string hazard = scene.hazard().body().name.empty() ? "hazard" : scene.hazard().body().name;

  std::string script = terminal + "\n";
  script += "set output " + single_quoted(drawing_path(dir.path(), output).string()) + "\n";
  script += fmt::format("set multiplot layout {},1 title '{}: region {}' noenhanced\n", panels,
                        sim::cell_text(sim::scenario_factors(config), result.input), sim::region_name(result.region));
  script += "set size ratio -1\nset key outside right top font ',8'\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n";
  script += fmt::format("set xrange [{:.2f}:{:.2f}]\nset yrange [{:.2f}:{:.2f}]\n", x_lo, x_hi, y_min - 1.0,
                        std::max(y_max, truck_top) + 1.0);
  script += kSpeedPalette;
  script += fmt::format("set cbrange [0:{:.3f}]\nset cblabel 'speed (m/s)'\n", v0);

  core::write_file(file("road.dat"), road_edges(x_lo, x_hi, y_min, y_max));
  core::write_file(file("centre.dat"), fmt::format("{0} 0\n{1} 0\n", x_lo, x_hi));
  core::write_file(file("truck0.dat"), outline(scene.hazard_at(0.0).box));

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
    core::write_file(file("truck_end" + tag + ".dat"), outline(scene.hazard_at(t_end).box));
    std::string ego = outline(scene.ego_box(scene.ego_initial()));
    if (!o.path.empty()) ego += outline(scene.ego_box(o.path.back().state));
    core::write_file(file("ego" + tag + ".dat"), ego);

    script += fmt::format("set title '{}: {}' noenhanced\n", o.strategy, outcome_text(o));
    script += fmt::format(
        "plot '{}' w l lc 'black' lw 1.5 notitle, '{}' w l lc 'gray50' dt 2 notitle, "
        "'{}' w l lc rgb '#2ca02c' lw 0.6 title 'goal tree', '{}' w l lc rgb '#ff7f0e' lw 0.6 title 'fail-safe', "
        "'{}' w l dt 2 lc 'gray40' title '{} t=0', '{}' w l lc 'gray20' lw 1.5 title '{} at end', "
        "'{}' w l lc rgb '#1f77b4' lw 1.2 title 'ego', '{}' u 1:2:3 w l lw 3 lc palette title 'executed'\n",
        file("road.dat"), file("centre.dat"), file("goal" + tag + ".dat"), file("failsafe" + tag + ".dat"),
        file("truck0.dat"), hazard, file("truck_end" + tag + ".dat"), hazard, file("ego" + tag + ".dat"),
        file("path" + tag + ".dat"));
  }
  script += "unset multiplot\n";
  run_gnuplot(script, dir.path(), {output});
}

}  // namespace emrm::report

namespace emrm::report {
namespace {

// The outcome whose trees a panel shows: the planned strategy emrm chose, else the first planned
// strategy in evaluation order that has trees (dodge), else any with trees.
const campaign::OutcomeRecord* tree_source(const campaign::CellRecord& r, const campaign::OutcomeRecord& emrm) {
  const auto find = [&](const std::string& name) -> const campaign::OutcomeRecord* {
    for (const auto& o : r.outcomes)
      if (o.strategy == name && (!o.goal_tree.empty() || !o.failsafe_tree.empty())) return &o;
    return nullptr;
  };
  if (const auto* chosen = find(emrm.chosen_strategy)) return chosen;
  for (const auto& entry : sim::registered_strategies().entries())
    if (!entry.info.planner.empty())
      if (const auto* planned = find(entry.info.name)) return planned;
  for (const auto& o : r.outcomes)
    if (!o.goal_tree.empty() || !o.failsafe_tree.empty()) return &o;
  return nullptr;
}

// The outcome a panel draws: the controller's (EMRM's), whose path is what the car would do (not
// the oracle's, which picks in hindsight).
bool is_chooser(std::string_view strategy) {
  const sim::StrategyTable registered = sim::registered_strategies();
  const sim::StrategyInfo* info = registered.info(strategy);
  return info != nullptr && info->role == sim::StrategyRole::kChooser && !info->hindsight;
}

// The factors a panel's row names: the T-junction's speed, TTC, friction and passage (its truck's
// speed is its motion, not a label); another family's every factor.
std::vector<std::size_t> shown_factors(const sim::FactorTable& factors, bool tjunction) {
  if (tjunction) return {sim::tjunction::kSpeed, sim::tjunction::kTtc, sim::tjunction::kMu, sim::tjunction::kPassage};
  std::vector<std::size_t> all(factors.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = f;
  return all;
}

std::string outcome_label(const campaign::OutcomeRecord& o) {
  std::string text = o.avoided ? "avoided" : fmt::format("{:.0f} km/h, L{}", o.impact_speed_kph, o.loss_level);
  if (!o.chosen_strategy.empty()) text += " (" + o.chosen_strategy + ")";
  return text;
}

// A panel of another family than the T-junction in three lines: the method's factors, the
// family's own, and the outcome ("\n" is a line break in a gnuplot title).
std::string panel_title(const sim::FactorTable& factors, const campaign::CellRecord& cell,
                        const campaign::OutcomeRecord& emrm) {
  std::vector<std::string> method, own;
  for (std::size_t f = 0; f < factors.size() && f < cell.factors.size(); ++f)
    (f < sim::kMethodFactors ? method : own).push_back(factors[f].format(factors[f].brief, cell.factors[f]));
  return fmt::format("{}\\n{}\\n{}", core::join(method, ", "), core::join(own, ", "), outcome_label(emrm));
}

}  // namespace

Figure draw_trajectory_grid(const std::vector<campaign::CellRecord>& records, const sim::SceneConfig& config,
                            const std::string& grid, const std::filesystem::path& dir) {
  Figure figure;
  figure.name = "trajectory_grid";
  figure.title =
      "RRT validation scenarios: goal tree (green), fail-safe tree (orange) and the executed EMRM "
      "path coloured by speed, per canonical scenario";
  struct Panel {
    const campaign::CellRecord* cell;
    const campaign::OutcomeRecord* emrm;
    const campaign::OutcomeRecord* trees;
  };
  std::vector<Panel> panels;
  for (const auto& r : records) {
    if (r.grid != grid || !r.feasible) continue;
    for (const auto& o : r.outcomes)
      if (is_chooser(o.strategy) && !o.path.empty()) panels.push_back({&r, &o, tree_source(r, o)});
  }
  if (panels.empty()) {
    figure.note = fmt::format("no stored trajectories for grid '{}' (sweep it with keep_trees: true)", grid);
    return figure;
  }
  // The T-junction's panels keep their own titles and columns; another family's name every factor.
  const bool tjunction = sim::has_tjunction_analytics(config);
  const sim::FactorTable factors = sim::scenario_factors(config);

  std::filesystem::create_directories(dir);
  figure.png = dir / (figure.name + ".png");
  figure.svg = dir / (figure.name + ".svg");
  figure.csv = dir / (figure.name + ".csv");
  core::TempDir work("emrm-trajectories");
  const auto file = [&](const std::string& name) { return (work.path() / name).string(); };

  std::vector<core::Row> csv;
  double v_max = 0.0;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const auto& [cell, emrm, trees] = panels[k];
    const std::string tag = std::to_string(k);
    core::Row lead{tag, std::to_string(cell->index)};
    for (const std::size_t f : shown_factors(factors, tjunction)) lead.push_back(fmt::format("{:g}", cell->factors[f]));
    lead.insert(lead.end(), {core::enum_text(cell->region), outcome_label(*emrm)});
    const auto rows_of = [&](const campaign::Polyline& line, const std::string& kind, std::size_t edge) {
      std::string data;
      for (const auto& p : line) {
        data += fmt::format("{:.2f} {:.2f} {:.2f}\n", p[1], p[2], p[3]);
        core::Row row = lead;
        row.insert(row.end(), {kind, std::to_string(edge), fmt::format("{:.2f}", p[0]), fmt::format("{:.2f}", p[1]),
                               fmt::format("{:.2f}", p[2]), fmt::format("{:.2f}", p[3])});
        csv.push_back(std::move(row));
        v_max = std::max(v_max, p[3]);
      }
      return data + "\n";
    };
    std::string goal, failsafe;
    if (trees) {
      for (std::size_t e = 0; e < trees->goal_tree.size(); ++e) goal += rows_of(trees->goal_tree[e], "goal", e);
      for (std::size_t e = 0; e < trees->failsafe_tree.size(); ++e)
        failsafe += rows_of(trees->failsafe_tree[e], "failsafe", e);
    }
    core::write_file(file("goal" + tag + ".dat"), goal.empty() ? "nan nan nan\n" : goal);
    core::write_file(file("failsafe" + tag + ".dat"), failsafe.empty() ? "nan nan nan\n" : failsafe);
    core::write_file(file("path" + tag + ".dat"), rows_of(emrm->path, "path", 0));

    // Every actor at the start and at the end of the path (the T-junction's one: its truck).
    const sim::Scene scene(config, cell->factors);
    std::string start, end;
    for (const sim::Actor& actor : scene.actors()) {
      start += outline(actor.at(0.0).box);
      end += outline(actor.at(emrm->path.back()[0]).box);
    }
    core::write_file(file("truck0_" + tag + ".dat"), start);
    core::write_file(file("truck1_" + tag + ".dat"), end);
  }
  // The factors the drawing shows, by their keys.
  core::Row header{"panel", "cell_index"};
  for (const std::size_t f : shown_factors(factors, tjunction)) header.push_back(factors[f].key);
  header.insert(header.end(), {"region", "outcome", "kind", "edge", "t_s", "x_m", "y_m", "speed_mps"});
  core::write_file(figure.csv, core::csv_table(header, csv));

  // One frame for every panel: the widest scene of the grid (the T-junction's up the side road its
  // truck comes from; another family's over its road, its actors and its paths).
  double x_lo = 0.0, x_hi = 0.0;
  const sim::Road road = sim::Scene(config, panels.front().cell->factors).road();
  double y_min = road.min_y_m - 1.0;
  double y_max = tjunction ? road.max_y_m + config.truck.length_m : road.max_y_m + 1.0;
  for (const auto& p : panels) {
    const sim::Scene scene(config, p.cell->factors);
    x_lo = std::min(x_lo, scene.ego_initial().x_m - config.ego.length_m);
    x_hi = std::max(x_hi, scene.passed_x_m() + 2.0 * config.ego.length_m);
    if (tjunction) continue;
    const double end_s = p.emrm->path.back()[0];
    x_hi = std::max(x_hi, scene.passed_x_m(end_s) + 2.0 * config.ego.length_m);
    for (const auto& point : p.emrm->path) x_hi = std::max(x_hi, point[1] + config.ego.length_m);
    for (const sim::Actor& actor : scene.actors())
      for (const double t : {0.0, end_s}) {
        const auto [low, high] = actor.y_extent_at(t);
        y_min = std::min(y_min, low - 0.5);
        y_max = std::max(y_max, high + 0.5);
        const double reach = 0.5 * std::max(actor.body().length_m, actor.body().width_m) + 1.0;
        x_lo = std::min(x_lo, actor.at(t).box.center.x - reach);
        x_hi = std::max(x_hi, actor.at(t).box.center.x + reach);
      }
  }
  core::write_file(file("road.dat"), road_edges(x_lo, x_hi, road.min_y_m, road.max_y_m));

  // The actors drawn: the T-junction's truck, or every actor of another family's cell.
  const std::string actors_label = tjunction ? "truck" : "actors";
  const int columns = 4;
  const int rows = static_cast<int>((panels.size() + columns - 1) / columns);
  for (const auto& output : {figure.png, figure.svg}) {
    std::string script = gnuplot_terminal(output, 1600, 330 * rows + 60) + "\n";
    script += "set output " + single_quoted(drawing_path(work.path(), output).string()) + "\n";
    script += fmt::format(
        "set multiplot layout {},{} title 'RRT validation scenarios (grid {}): goal tree, "
        "fail-safe tree, executed EMRM path' noenhanced\n",
        rows, columns, grid);
    script += "unset key\nset xtics font ',7'\nset ytics font ',7'\n";
    script += fmt::format("set xrange [{:.2f}:{:.2f}]\nset yrange [{:.2f}:{:.2f}]\n", x_lo, x_hi, y_min, y_max);
    script += kSpeedPalette;
    script += fmt::format("set cbrange [0:{:.2f}]\nset cblabel 'speed (m/s)' font ',8'\n", std::max(v_max, 1.0));
    for (std::size_t k = 0; k < panels.size(); ++k) {
      const auto& [cell, emrm, trees] = panels[k];
      const std::string tag = std::to_string(k);
      // One colour bar, beside the last panel of each row.
      script += (k % columns == columns - 1 || k + 1 == panels.size()) ? "set colorbox\n" : "unset colorbox\n";
      if (tjunction) {
        const sim::TJunctionCell named = sim::TJunctionCell::of(cell->factors);
        script += fmt::format("set title \"{:.1f} km/h, mu {:.2f}, passage {:.1f} m: {}\" font ',8' noenhanced\n",
                              named.speed_kph, named.mu, named.passage_m, outcome_label(*emrm));
      } else {
        script += fmt::format("set title \"{}\" font ',8' noenhanced\n", panel_title(factors, *cell, *emrm));
      }
      // Each curve titled (the key is off; an SVG names its curves by their titles, which would
      // otherwise be the temporary files' paths, a new name every run).
      script += fmt::format(
          "plot '{}' t 'road' w l lc 'black' lw 1.2, '{}' t 'goal tree' w l lc rgb '#2ca02c' lw 0.5, "
          "'{}' t 'fail-safe tree' w l lc rgb '#ff7f0e' lw 0.5, '{}' t '{} at the start' w l dt 2 lc 'gray40', "
          "'{}' t '{} at the end' w l lc 'gray20' lw 1.2, '{}' u 1:2:3 t 'EMRM path' w l lw 2.5 lc palette\n",
          file("road.dat"), file("goal" + tag + ".dat"), file("failsafe" + tag + ".dat"),
          file("truck0_" + tag + ".dat"), actors_label, file("truck1_" + tag + ".dat"), actors_label,
          file("path" + tag + ".dat"));
    }
    script += "unset multiplot\n";
    run_gnuplot(script, work.path(), {output});
  }
  return figure;
}

}  // namespace emrm::report
