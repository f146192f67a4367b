// `emrm simulate`: one scenario cell under every strategy (paper Algorithm 1, step 7).

#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "options.hpp"
#include "emrm/report/trajectory_figure.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/text.hpp"

namespace emrm::cli {
namespace {

struct SimulateOptions {
  std::string scene_file;
  sim::CellInput cell;
  bool truck_speed_given = false;
  std::vector<std::string> strategies{"all"};
  std::uint64_t seed = 1;
  bool json = false;
  bool timing = false;
  bool paths = false;  // kept so that older scripts still run: the trajectories are always in the JSON
  bool no_certify = false;
  std::string figure;
  std::string profile;
};

int run(const SimulateOptions& options) {
  sim::SceneConfig config =
      options.scene_file.empty() ? sim::SceneConfig{} : sim::load_scene_config(options.scene_file);
  // A profile NAME is looked up beside the scene file (the current folder without one).
  if (!options.profile.empty())
    sim::apply_profile(config, options.profile, std::filesystem::path(options.scene_file).parent_path());
  sim::CellInput cell = options.cell;
  if (!options.truck_speed_given) cell.truck_speed_kph = config.truck.speed_kph;
  sim::CellOptions cell_options;
  cell_options.seed = options.seed;
  cell_options.keep_trees = !options.figure.empty();
  cell_options.certify = !options.no_certify;
  const bool all = std::find(options.strategies.begin(), options.strategies.end(), "all") != options.strategies.end();
  if (!all) {
    for (const auto& s : options.strategies) sim::validate_strategy(s);
    cell_options.strategies = options.strategies;
  }
  const sim::CellResult result = sim::simulate_cell(config, cell, cell_options);
  if (options.json) {
    std::cout << sim::to_json(result, sim::Scene(config, result.input), options.seed, {options.timing}).dump(2)
              << "\n";
  } else {
    std::cout << sim::to_text(result, config, options.seed);
  }
  if (!options.figure.empty()) {
    report::draw_cell_figure(result, config, options.figure);
    if (!options.json) std::cout << "Figure written to " << options.figure << "\n";
  }
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_simulate_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand("simulate",
                                 "Simulate one scenario cell of the T-junction under every strategy and report\n"
                                 "avoidance, impact, loss level and the cell's region (G, Y, O, R).");
  cmd->add_option("--scene", o->scene_file, "Scene file (default: the built-in T-junction, examples/tjunction/scene.yaml)");
  cmd->add_option("--speed-kph", o->cell.speed_kph, "Ego speed when the hazard appears (km/h)")->required();
  cmd->add_option("--ttc-s", o->cell.ttc_s, "Time to collision when the hazard appears (s)")->required();
  cmd->add_option("--mu", o->cell.mu, "Tire-road friction coefficient, (0, 2]")->capture_default_str();
  cmd->add_option("--passage-m", o->cell.passage_m, "Free gap beside the stopped truck (m)")->capture_default_str();
  cmd->add_option_function<double>(
      "--truck-speed-kph",
      [o](double v) {
        o->cell.truck_speed_kph = v;
        o->truck_speed_given = true;
      },
      "Truck crossing speed (km/h; default: the scene's, 10)");
  cmd->add_option("--strategy", o->strategies,
                  "emergency_stop, dodge, drift_to_avoid, drift_to_accident, emrm, or all (repeatable)")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random seed of the planners")->check(seed_value())->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the stable JSON form (docs/simulate.md)");
  cmd->add_flag("--timing", o->timing, "Add planner wall-clock times to the JSON (they vary run to run)");
  cmd->add_flag("--paths", o->paths, "Kept for older scripts: the JSON always has every trajectory");
  cmd->add_option("--profile", o->profile, "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE (docs/actuation.md)");
  cmd->add_flag("--no-certify", o->no_certify,
                "Search every cell in full, even where a certificate proves that nothing avoids (to check certificates)");
  cmd->add_option("--figure", o->figure, "Draw the trajectory trees to FILE.svg or FILE.png (gnuplot)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
