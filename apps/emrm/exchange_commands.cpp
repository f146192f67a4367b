// `emrm export` and `emrm assess` (docs/openscenario.md): a cell or a plan as OpenSCENARIO XML and
// OpenDRIVE for another simulator, and a trajectory recorded there judged by emrm's own models.

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "cell_options.hpp"
#include "commands.hpp"
#include "emrm/campaign/plan_settings.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/exchange/assess.hpp"
#include "emrm/exchange/ego_trajectory.hpp"
#include "emrm/exchange/openscenario.hpp"
#include "emrm/exchange/plan_export.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/simulate.hpp"

namespace emrm::cli {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::shared_ptr<CellArgs> cell = std::make_shared<CellArgs>();
  CellOptionSet cell_options;
  std::string format = "openscenario";
  std::string output;
  std::string plan_dir;
  std::string strategy;
  double tolerance_m = 0.0;
};

std::string written(const std::vector<fs::path>& files) {
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(f.string());
  return core::join(names, ", ");
}

int run_plan_export(const ExportOptions& options, const exchange::ExportOptions& export_options) {
  const scenario::PlanDir plan_dir(options.plan_dir);
  const fs::path csv = plan_dir.scenarios_csv();
  if (!fs::is_regular_file(csv))
    throw UsageError(
        fmt::format("emrm export: {} is not a plan folder: it has no scenarios.csv (write one with "
                    "'emrm plan ODD.yaml -o DIR')",
                    plan_dir.root().string()));
  CellArgs args = *options.cell;
  // The plan's own scene unless --scene names one.
  if (args.scene_file.empty() && fs::is_regular_file(plan_dir.scenarios_json())) {
    const campaign::PlanSettings settings = campaign::read_plan_settings(plan_dir.scenarios_json());
    if (settings.scene_file) args.scene_file = settings.scene_file->string();
  }
  const sim::SceneConfig config = load_scene(args);
  const scenario::ScenarioFile scenarios = scenario::read_scenarios_csv(csv);
  const exchange::PlanExport out = exchange::export_plan(options.output, config, scenarios, export_options);
  if (out.logical)
    fmt::print("Exported {} as one logical scenario: {}, {} and {} in {}\n",
               core::counted(out.scenarios, "scenario", "scenarios"), exchange::kScenarioFile,
               exchange::kDistributionFile, core::counted(out.road_networks, "road network", "road networks"),
               options.output);
  else
    fmt::print("Exported {} as concrete scenarios, each ID/{} beside its road ID/{}, in {}\n",
               core::counted(out.scenarios, "scenario", "scenarios"), exchange::scenario_file_of(config),
               exchange::road_file_of(config), options.output);
  return static_cast<int>(ExitCode::kSuccess);
}

int run_export(const ExportOptions& options) {
  exchange::ExportOptions export_options;
  export_options.tolerance_m = options.tolerance_m;
  if (!options.plan_dir.empty()) return run_plan_export(options, export_options);
  const sim::SceneConfig config = load_scene(*options.cell);
  const sim::FactorTable method = sim::scenario_factors(config);
  if (!options.cell->given.contains(method[sim::kEgoSpeedFactor].key) ||
      !options.cell->given.contains(method[sim::kTtcFactor].key))
    throw UsageError("emrm export: give a cell (--speed-kph and --ttc-s) or a plan (--plan PLAN_DIR)");
  const sim::CellInput cell = cell_of(*options.cell, config);
  std::unique_ptr<exchange::EgoTrajectory> trajectory;
  if (!options.strategy.empty()) {
    sim::validate_strategy(options.strategy);
    sim::CellOptions cell_options;
    cell_options.seed = options.cell->seed;
    cell_options.strategies = {options.strategy};
    const sim::CellResult result = sim::simulate_cell(config, cell, cell_options);
    const auto it = std::find_if(result.strategies.begin(), result.strategies.end(),
                                 [&](const sim::StrategyOutcome& o) { return o.strategy == options.strategy; });
    if (it != result.strategies.end() && !it->path.empty())
      trajectory = std::make_unique<exchange::EgoTrajectory>(exchange::EgoTrajectory{it->strategy, it->path});
  }
  const auto files = exchange::export_cell(options.output, config, cell, trajectory.get(), export_options);
  std::string note;
  if (trajectory)
    note = fmt::format(" (the ego follows its {} trajectory, {} points)", trajectory->strategy,
                       exchange::ego_vertices(config, *trajectory, export_options).size());
  else if (!options.strategy.empty())
    note = fmt::format(" ({} executed no trajectory in this cell: the ego keeps its speed)", options.strategy);
  fmt::print("Wrote {}{}\n", written(files), note);
  return static_cast<int>(ExitCode::kSuccess);
}

struct AssessOptions {
  std::shared_ptr<CellArgs> cell = std::make_shared<CellArgs>();
  std::string file;
  std::string format = "emrm";
  std::string strategy;
  bool json = false;
};

int run_assess(const AssessOptions& options) {
  if (!options.strategy.empty()) sim::validate_strategy(options.strategy);
  // The car, its actuators and the hazard decide the contact, the Δv and the loss: judged against the
  // built-in car, a recording of the production car reads several km/h off without a word.
  if (options.cell->scene_file.empty())
    throw UsageError(
        "emrm assess: name the scene the trajectory was driven in with --scene FILE (its car, actuators and hazard "
        "decide the contact, the delta-v and the loss; examples/tjunction/scene.yaml is the shipped production car, "
        "and --scene DIR takes the scene a results folder's sweep stored)");
  const sim::SceneConfig config = load_scene(*options.cell);
  const sim::CellInput cell = cell_of(*options.cell, config);
  sim::validate_cell(config, cell);
  const auto format =
      options.format == "esmini" ? exchange::TrajectoryFormat::kEsmini : exchange::TrajectoryFormat::kEmrm;
  const exchange::RecordedTrajectory trajectory = exchange::read_trajectory_csv(options.file, format, config);
  const exchange::Assessment a = exchange::assess(config, cell, trajectory);
  if (options.json) {
    nlohmann::ordered_json j =
        exchange::to_json(a, trajectory, format, sim::scenario_factors(config), cell, options.strategy);
    j["scene"] = scene_json(*options.cell, config);
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << scene_text(*options.cell, config) << "\n"
              << "Cell: " << sim::cell_text(sim::scenario_factors(config), cell) << "\n"
              << exchange::to_text(a, trajectory, options.strategy);
  }
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_export_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Export a scenario cell (its flags as in 'emrm simulate') or a plan (--plan PLAN_DIR) as OpenSCENARIO XML 1.2\n"
      "and OpenDRIVE 1.6 for another simulator: OUT/tjunction.xosc and OUT/tjunction.xodr; with --strategy, the ego\n"
      "follows the trajectory that strategy executed; a plan adds OUT/tjunction_distribution.xosc and OUT/roads/\n"
      "(docs/openscenario.md)");
  cmd->add_option("--format", o->format, "Output format (openscenario)")
      ->check(CLI::IsMember({"openscenario"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "Output folder")->required();
  o->cell_options = add_cell_options(cmd, o->cell, false, true);
  CLI::Option* plan = cmd->add_option("--plan", o->plan_dir, "Plan folder written by 'emrm plan' (scenarios.csv)");
  CLI::Option* strategy = cmd->add_option(
      "--strategy", o->strategy, "Strategy whose executed trajectory the ego follows (emergency_stop, dodge, …)");
  cmd->add_option("--tolerance-m", o->tolerance_m,
                  "Thin the trajectory: drop vertices the polyline passes within this distance (m; 0 keeps every step)")
      ->check(finite_in(0.0, 1.0))
      ->capture_default_str();
  std::vector<CLI::Option*> cell_flags = o->cell_options.factors;
  cell_flags.insert(cell_flags.end(), {o->cell_options.assignments, o->cell_options.seed, strategy});
  for (CLI::Option* cell_option : cell_flags) plan->excludes(cell_option);
  cmd->callback([o, &exit_code] { exit_code = run_export(*o); });
}

void register_assess_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<AssessOptions>();
  CLI::App* cmd = app.add_subcommand(
      "assess",
      "Judge a trajectory recorded by another simulator with emrm's collision, road-departure and loss models:\n"
      "contact time and point, impact speed, delta-v, injury risks, loss level, safe state. The cell (its flags\n"
      "as in 'emrm simulate') gives the truck's motion unless the file records it (docs/openscenario.md)");
  cmd->add_option("TRAJECTORIES", o->file,
                  "CSV file: t, x, y, psi, v (the ego's CG), optional truck_x, truck_y, "
                  "truck_psi, steer; or esmini's dat2csv output with --format esmini")
      ->required();
  add_cell_options(cmd, o->cell, true, false);
  // A trajectory is judged in the scene it was driven in: no built-in default here (run_assess).
  cmd->get_option("--scene")->description(
      "Scene file the trajectory was driven in, or a results folder (the scene its sweep stored); required");
  cmd->add_option("--format", o->format, "emrm or esmini")
      ->check(CLI::IsMember({"emrm", "esmini"}))
      ->capture_default_str();
  cmd->add_option("--strategy", o->strategy, "Name the outcome after a strategy (as 'emrm simulate --json' keys it)");
  cmd->add_flag("--json", o->json, "Print the outcome as JSON (docs/openscenario.md)");
  cmd->callback([o, &exit_code] { exit_code = run_assess(*o); });
}

}  // namespace emrm::cli
