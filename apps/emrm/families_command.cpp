// `emrm families`: the registered scenario families and their factors (docs/families.md).

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/json.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::cli {
namespace {

// A scene of the family with every other setting at its default: the factors' limits and defaults
// as a scene file that names only its family gets them.
sim::SceneConfig scene_of(const sim::ScenarioFamilyInfo& family) {
  sim::SceneConfig config;
  config.family = family.name;
  return config;
}

int run(bool json) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& family : sim::registered_families()) {
    const sim::FactorTable factors = family->factors(scene_of(*family));
    if (json) {
      out.push_back({{"name", family->name},
                     {"description", family->description},
                     {"certificate", family->tjunction_analytics},
                     {"factors", sim::to_json(factors)}});
      continue;
    }
    std::cout << fmt::format("{}: {}\n", family->name, family->description);
    for (const sim::Factor& f : factors)
      std::cout << fmt::format("  {:<20} {:<6} {:<22} {:<40} default {}\n", f.key, f.unit == "1" ? "" : f.unit, f.what,
                               f.inequality(), f.value_text(f.default_value));
  }
  if (json) std::cout << nlohmann::json{{"families", out}}.dump(2) << "\n";
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_families_command(CLI::App& app, int& exit_code) {
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("families",
                                 "List the scenario families a scene file can name (family: NAME) and the factors\n"
                                 "of each: their keys (for --factor, campaign grids and ODDs), units, limits and\n"
                                 "defaults (docs/families.md).");
  cmd->add_flag("--json", *json, "Print them as JSON");
  cmd->callback([json, &exit_code] { exit_code = run(*json); });
}

}  // namespace emrm::cli
