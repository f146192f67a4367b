#pragma once

// The options that name one scenario cell and its scene, shared by `emrm simulate`, `emrm export`
// and `emrm assess`: one set of flags, defaults and checks.

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/sim/scene.hpp"
#include "options.hpp"

namespace emrm::cli {

struct CellArgs {
  std::string scene_file;
  std::string profile;
  std::map<std::string, double> given;  ///< the factor flags given: key → value
  std::uint64_t seed = 1;
};

/// The options CLI11 made, for commands that relate them to others (excludes, needs).
struct CellOptionSet {
  std::vector<CLI::Option*> factors;  ///< one per factor, in the factor table's order
  CLI::Option* seed = nullptr;        ///< only with_seed
  [[nodiscard]] CLI::Option* speed() const { return factors[sim::kEgoSpeedFactor]; }
  [[nodiscard]] CLI::Option* ttc() const { return factors[sim::kTtcFactor]; }
};

/// Adds --scene, --profile, a flag per factor of the scene (its key with '-' for '_': --speed-kph,
/// --ttc-s, --mu, ...; the ego speed and the TTC required when `required`; the others default to
/// the scene's) and, `with_seed`, --seed to `command`, filling `args`.
inline CellOptionSet add_cell_options(CLI::App* command, const std::shared_ptr<CellArgs>& args, bool required,
                                      bool with_seed) {
  CellOptionSet o;
  command->add_option("--scene", args->scene_file,
                      "Scene file (default: the built-in T-junction, examples/tjunction/scene.yaml with instant "
                      "actuators; pass that file for the production car of the shipped campaigns)");
  // The flags are the default scene's factors (a scene file, read after parsing, keeps their keys).
  const sim::FactorTable factors = sim::scenario_factors(sim::SceneConfig{});
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const sim::Factor& f = factors[i];
    std::string flag = "--" + f.key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    const bool method = i == sim::kEgoSpeedFactor || i == sim::kTtcFactor;
    const std::string help = fmt::format(
        "{}{}{}", f.what, f.unit == "1" ? "" : " (" + f.unit + ")",
        required && method ? "" : fmt::format(", {}; default: the scene's, {:g}", f.inequality(), f.default_value));
    CLI::Option* option = command->add_option_function<double>(
        flag, [args, key = f.key](double v) { args->given[key] = v; }, help);
    if (required && method) option->required();
    o.factors.push_back(option);
  }
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

/// The cell the options name: the scene's defaults, overlaid with the factors given. Throws
/// UsageError for a factor flag the scene has no factor for.
inline sim::CellInput cell_of(const CellArgs& args, const sim::SceneConfig& config) {
  const sim::FactorTable factors = sim::scenario_factors(config);
  sim::CellInput cell = factors.defaults();
  for (const auto& [key, value] : args.given)
    if (!factors.set(cell, key, value))
      throw UsageError(fmt::format("the scene has no factor '{}' (its factors: {})", key, factors.key_list()));
  return cell;
}

}  // namespace emrm::cli
