#pragma once

// The options that name one scenario cell and its scene, shared by `emrm simulate`, `emrm export`
// and `emrm assess`: one set of flags, defaults and checks.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "emrm/sim/scene.hpp"
#include "options.hpp"

namespace emrm::cli {

struct CellArgs {
  std::string scene_file;
  std::string profile;
  sim::CellInput cell;
  bool truck_speed_given = false;
  std::uint64_t seed = 1;
};

/// The options CLI11 made, for commands that relate them to others (excludes, needs).
struct CellOptionSet {
  CLI::Option* speed = nullptr;
  CLI::Option* ttc = nullptr;
  CLI::Option* mu = nullptr;
  CLI::Option* passage = nullptr;
  CLI::Option* truck_speed = nullptr;
  CLI::Option* seed = nullptr;  ///< only with_seed
};

/// Adds --scene, --profile, --speed-kph, --ttc-s (both required when `required`), --mu, --passage-m,
/// --truck-speed-kph and, `with_seed`, --seed to `command`, filling `args`.
inline CellOptionSet add_cell_options(CLI::App* command, const std::shared_ptr<CellArgs>& args, bool required,
                                      bool with_seed) {
  CellOptionSet o;
  command->add_option("--scene", args->scene_file,
                      "Scene file (default: the built-in T-junction, examples/tjunction/scene.yaml with instant "
                      "actuators; pass that file for the production car of the shipped campaigns)");
  o.speed = command->add_option("--speed-kph", args->cell.speed_kph, "Ego speed when the hazard appears (km/h)");
  o.ttc = command->add_option("--ttc-s", args->cell.ttc_s, "Time to collision when the hazard appears (s)");
  if (required) {
    o.speed->required();
    o.ttc->required();
  }
  o.mu = command->add_option("--mu", args->cell.mu, "Tire-road friction coefficient, (0, 2]")->capture_default_str();
  o.passage = command->add_option("--passage-m", args->cell.passage_m, "Free gap beside the stopped truck (m)")
                  ->capture_default_str();
  o.truck_speed = command->add_option_function<double>(
      "--truck-speed-kph",
      [args](double v) {
        args->cell.truck_speed_kph = v;
        args->truck_speed_given = true;
      },
      "Truck crossing speed (km/h; default: the scene's, 10)");
  if (with_seed)
    o.seed = command->add_option("--seed", args->seed, "Random seed of the planners")
                 ->check(seed_value())
                 ->capture_default_str();
  command->add_option("--profile", args->profile,
                      "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE "
                      "(docs/actuation.md)");
  return o;
}

/// The scene the options name, with the profile applied.
inline sim::SceneConfig load_scene(const CellArgs& args) {
  sim::SceneConfig config = args.scene_file.empty() ? sim::SceneConfig{} : sim::load_scene_config(args.scene_file);
  // A profile NAME is looked up beside the scene file (the current folder without one).
  if (!args.profile.empty())
    sim::apply_profile(config, args.profile, std::filesystem::path(args.scene_file).parent_path());
  return config;
}

/// The cell the options name; the truck's speed is the scene's unless given.
inline sim::CellInput cell_of(const CellArgs& args, const sim::SceneConfig& config) {
  sim::CellInput cell = args.cell;
  if (!args.truck_speed_given) cell.truck_speed_kph = config.truck.speed_kph;
  return cell;
}

}  // namespace emrm::cli
