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
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/results/results_dir.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/scene.hpp"
#include "options.hpp"

namespace emrm::cli {

struct CellArgs {
  std::string scene_file;
  std::string profile;
  /// The factors given: key → the number a shorthand flag read, or the text of --factor KEY=VALUE
  /// (a number, or a categorical factor's level), read against the scene's family by cell_of.
  std::map<std::string, std::variant<double, std::string>> given;
  std::vector<std::string> required;  ///< the keys a cell must give: the ego's speed and the TTC
  std::uint64_t seed = 1;
};

/// The options CLI11 made, for commands that relate them to others (excludes, needs).
struct CellOptionSet {
  std::vector<CLI::Option*> factors;   ///< one per factor, in the factor table's order
  CLI::Option* seed = nullptr;         ///< only with_seed
  CLI::Option* assignments = nullptr;  ///< --factor KEY=VALUE
};

/// Records a factor's value, refusing one given twice (by its flag and by --factor, or twice).
inline void give_factor(CellArgs& args, const std::string& key, std::variant<double, std::string> value) {
  if (!args.given.emplace(key, std::move(value)).second)
    throw UsageError(fmt::format("the factor {} is given twice", key));
}

/// A factor's shorthand flag: its key with '-' for '_' (--speed-kph).
inline std::string shorthand_flag(const std::string& key) {
  std::string flag = "--" + key;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

/// Reads one --factor KEY=VALUE (the value is read by cell_of, against the factor it sets).
inline void give_assignment(CellArgs& args, const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == 0 || eq == std::string::npos || eq + 1 == text.size())
    throw UsageError(fmt::format("--factor: expected KEY=VALUE (speed_kph=80, obstacle=deer), got '{}'", text));
  give_factor(args, text.substr(0, eq), text.substr(eq + 1));
}

/// Adds --scene, --profile, --factor KEY=VALUE (any factor of the scene's family), a shorthand flag
/// per factor of the built-in scene (its key with '-' for '_': --speed-kph, --ttc-s, --mu, ...) and,
/// `with_seed`, --seed to `command`, filling `args`. The ego speed and the TTC must be given when
/// `required` (cell_of checks: a flag or --factor); the other factors default to the scene's.
inline CellOptionSet add_cell_options(CLI::App* command, const std::shared_ptr<CellArgs>& args, bool required,
                                      bool with_seed) {
  CellOptionSet o;
  command->add_option("--scene", args->scene_file,
                      "Scene file, or a results folder (the scene its sweep stored) (default: the built-in "
                      "T-junction, examples/tjunction/scene.yaml with instant actuators; pass that file for the "
                      "production car of the shipped campaigns)");
  o.assignments = command
                      ->add_option_function<std::vector<std::string>>(
                          "--factor",
                          [args](const std::vector<std::string>& all) {
                            for (const auto& text : all) give_assignment(*args, text);
                          },
                          "Set any factor of the scene's family by its key (repeatable; 'emrm families' lists them)")
                      ->type_name("KEY=VALUE")
                      ->expected(1)
                      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  // The shorthand flags are the default scene's factors (the T-junction's).
  const sim::FactorTable factors = sim::scenario_factors(sim::SceneConfig{});
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const sim::Factor& f = factors[i];
    const std::string flag = shorthand_flag(f.key);
    const bool method = i == sim::kEgoSpeedFactor || i == sim::kTtcFactor;
    const std::string help = fmt::format(
        "{}{}{}", f.what, f.unit == "1" ? "" : " (" + f.unit + ")",
        required && method ? ", required"
                           : fmt::format(", {}; default: the scene's, {:g}", f.inequality(), f.default_value));
    o.factors.push_back(command->add_option_function<double>(
        flag, [args, key = f.key](double v) { give_factor(*args, key, v); }, help));
    if (required && method) args->required.push_back(f.key);
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
  sim::SceneConfig config;
  if (const results::ResultsDir folder(args.scene_file);
      !args.scene_file.empty() && std::filesystem::is_directory(args.scene_file)) {
    // A results folder: the scene its sweep stored (profile included).
    if (!std::filesystem::is_regular_file(folder.store()))
      throw UsageError(
          fmt::format("--scene {}: a folder, but no results folder (it has no {}); expected a scene "
                      "file or a folder written by 'emrm sweep'",
                      args.scene_file, folder.store().filename().string()));
    config = sim::parse_stored_scene_config(campaign::read_meta(folder.store()).scene_yaml,
                                            folder.store().string() + " (scene)");
  } else if (!args.scene_file.empty()) {
    config = sim::load_scene_config(args.scene_file);
  }
  // A profile NAME is looked up beside the scene file (the current folder without one).
  if (!args.profile.empty())
    sim::apply_profile(config, args.profile, std::filesystem::path(args.scene_file).parent_path());
  return config;
}

/// The flag that gives a factor: "--speed-kph (or --factor speed_kph=VALUE)".
inline std::string factor_flag(const std::string& key) {
  return fmt::format("{} (or --factor {}=VALUE)", shorthand_flag(key), key);
}

/// The cell the options name: the scene's defaults, overlaid with the factors given. Throws
/// UsageError for a required factor not given, or one the scene's family does not have.
inline sim::CellInput cell_of(const CellArgs& args, const sim::SceneConfig& config) {
  for (const auto& key : args.required)
    if (!args.given.contains(key)) throw UsageError(fmt::format("{} is required", factor_flag(key)));
  const sim::FactorTable factors = sim::scenario_factors(config);
  sim::CellInput cell = factors.defaults();
  for (const auto& [key, value] : args.given) {
    const auto i = factors.find(key);
    if (!i)
      throw UsageError(fmt::format("the scene's family {} has no factor '{}' (its factors: {})", config.family, key,
                                   factors.key_list()));
    const auto* number = std::get_if<double>(&value);
    cell[*i] = number != nullptr ? *number : factors[*i].parse(std::get<std::string>(value));
  }
  return cell;
}

/// The scene a cell was judged in, as the output names it: the file (or "the built-in T-junction"),
/// its family, the profile and the actuation in effect. One line of text.
inline std::string scene_text(const CellArgs& args, const sim::SceneConfig& config) {
  return fmt::format(
      "Scene: {} (family {}{}); actuation: {}",
      args.scene_file.empty() ? std::string("the built-in T-junction, instant actuators") : args.scene_file,
      config.family, args.profile.empty() ? std::string() : ", profile " + args.profile, config.actuation.summary());
}

/// The same as JSON: {"file": path or null (the built-in scene), "family", "profile": name or null,
/// "actuation": {…}} (docs/simulate.md).
inline nlohmann::json scene_json(const CellArgs& args, const sim::SceneConfig& config) {
  nlohmann::json j;
  j["file"] = args.scene_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(args.scene_file);
  j["family"] = config.family;
  j["profile"] = args.profile.empty() ? nlohmann::json(nullptr) : nlohmann::json(args.profile);
  j["actuation"] = sim::to_json(config.actuation);
  return j;
}

}  // namespace emrm::cli
