// `emrm simulate`: one scenario cell under every strategy (paper Algorithm 1, step 7).

#include <fmt/format.h>

#include <iostream>

#include "cell_options.hpp"
#include "commands.hpp"
#include "emrm/core/text.hpp"
#include "emrm/report/trajectory_figure.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/simulate.hpp"
#include "emrm/sim/text.hpp"

namespace emrm::cli {
namespace {

struct SimulateOptions {
  std::shared_ptr<CellArgs> cell = std::make_shared<CellArgs>();
  std::vector<std::string> strategies{"all"};
  bool json = false;
  bool timing = false;
  bool paths = false;  // kept so that older scripts still run: the trajectories are always in the JSON
  bool no_certify = false;
  std::string figure;
};

int run(const SimulateOptions& options) {
  const sim::SceneConfig config = load_scene(*options.cell);
  const sim::CellInput cell = cell_of(*options.cell, config);
  const std::uint64_t seed = options.cell->seed;
  sim::CellOptions cell_options;
  cell_options.seed = seed;
  cell_options.keep_trees = !options.figure.empty();
  cell_options.certify = !options.no_certify;
  const bool all = std::find(options.strategies.begin(), options.strategies.end(), "all") != options.strategies.end();
  if (!all) {
    for (const auto& s : options.strategies) sim::validate_strategy(s);
    cell_options.strategies = options.strategies;
  }
  const sim::CellResult result = sim::simulate_cell(config, cell, cell_options);
  if (options.json) {
    nlohmann::json j = sim::to_json(result, sim::Scene(config, result.input), seed, {options.timing});
    j["scene"] = scene_json(*options.cell, config);
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << scene_text(*options.cell, config) << "\n" << sim::to_text(result, config, seed);
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
  add_cell_options(cmd, o->cell, true, true);
  cmd->add_option("--strategy", o->strategies, core::join(sim::strategy_names(), ", ") + ", or all (repeatable)")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the stable JSON form (docs/simulate.md)");
  cmd->add_flag("--timing", o->timing, "Add planner wall-clock times to the JSON (they vary run to run)");
  cmd->add_flag("--paths", o->paths, "Kept for older scripts: the JSON always has every trajectory");
  cmd->add_flag(
      "--no-certify", o->no_certify,
      "Search every cell in full, even where a certificate proves that nothing avoids (to check certificates)");
  cmd->add_option("--figure", o->figure, "Draw the trajectory trees to FILE.svg or FILE.png (gnuplot)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
