// `emrm import`: an OpenSCENARIO scenario as a scene of the family openscenario, and its storyboard
// played open loop as a trace (docs/import.md).

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "emrm/core/text.hpp"
#include "emrm/openscenario/family.hpp"
#include "emrm/openscenario/import.hpp"
#include "emrm/openscenario/player.hpp"
#include "emrm/openscenario/reader.hpp"
#include "emrm/openscenario/trace.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::cli {
namespace {

struct ImportOptions {
  std::string scenario;
  std::string ego;
  std::vector<std::string> factors;
  std::vector<openscenario::FactorSweep> ranges;
  std::string output;
  std::string campaign;
  std::string trace;
  double trace_s = 10.0;
};

std::string describe(const std::vector<openscenario::FactorSweep>& sweeps) {
  std::vector<std::string> keys;
  for (const auto& s : sweeps) keys.push_back(s.factor);
  return fmt::format("{}", fmt::join(keys, " × "));
}

int run(const ImportOptions& o) {
  if (!o.campaign.empty() && o.output.empty())
    throw UsageError("--campaign needs -o SCENE.yaml: the campaign names the scene file");
  const openscenario::ImportedScenario imported =
      openscenario::import_scenario(o.scenario, {.ego = o.ego, .factors = o.factors}, o.ranges);
  sim::SceneConfig config = imported.scene;
  // Everything is read and checked before anything is written.
  std::string trace;
  if (!o.trace.empty()) {
    openscenario::PlayOptions play;
    play.dt_s = config.simulation.dt_s;
    play.duration_s = o.trace_s;
    std::ostringstream csv;
    openscenario::write_trace_csv(
        csv, openscenario::play(openscenario::load_openscenario(config.openscenario.file,
                                                                {.overrides = {}, .ego = config.openscenario.ego}),
                                play));
    trace = csv.str();
  }
  if (!o.output.empty()) {
    // The scenario relative to the scene file, so that the two move together.
    const std::filesystem::path folder = std::filesystem::absolute(o.output).parent_path();
    config.openscenario.file = std::filesystem::path(config.openscenario.file).lexically_relative(folder).string();
    core::write_file(
        o.output, fmt::format("# {} imported by `emrm import` (docs/import.md)\n{}", o.scenario, sim::to_yaml(config)));
    const sim::OpenScenarioConfig& block = config.openscenario;
    std::cout << fmt::format(
        "Scene written to {} (family openscenario, ego {}, {} factor{} besides speed, TTC and μ{})\n", o.output,
        block.ego, block.factors.size(), block.factors.size() == 1 ? "" : "s",
        block.speed_parameter.empty() ? std::string() : fmt::format("; speed_kph sets {}", block.speed_parameter));
  } else {
    std::cout << sim::to_yaml(config);
  }
  if (!o.campaign.empty()) {
    const std::filesystem::path scene_ref =
        std::filesystem::absolute(o.output).lexically_relative(std::filesystem::absolute(o.campaign).parent_path());
    core::write_file(o.campaign, openscenario::campaign_yaml(imported, scene_ref.string()));
    std::cout << fmt::format("Campaign written to {} ({}{})\n", o.campaign,
                             imported.value_sets.empty()
                                 ? std::string("one grid")
                                 : fmt::format("{} grids, one per value set", imported.value_sets.size()),
                             imported.sweeps.empty() ? std::string(", over the TTC only")
                                                     : fmt::format(" over {}", describe(imported.sweeps)));
  }
  if (!o.trace.empty()) {
    core::write_file(o.trace, trace);
    if (!o.output.empty()) std::cout << fmt::format("Trace of the first {:g} s written to {}\n", o.trace_s, o.trace);
  }
  return static_cast<int>(ExitCode::kSuccess);
}

}  // namespace

void register_import_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ImportOptions>();
  auto* cmd = app.add_subcommand("import",
                                 "Import an ASAM OpenSCENARIO scenario (.xosc, with its OpenDRIVE road) as a scene of\n"
                                 "the family openscenario that every command takes (docs/import.md); `--scene\n"
                                 "FILE.xosc` works directly too.");
  cmd->add_option("scenario", o->scenario, "The scenario (.xosc), or a ParameterValueDistribution file naming one")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--ego", o->ego, "The entity the EMRM drives (default: Ego, ego or hero, else the first vehicle)");
  cmd->add_option("--factors", o->factors,
                  "The declared numeric parameters the scene makes factors, comma-separated (default: every one the "
                  "scenario refers to; at most 5)")
      ->delimiter(',');
  cmd->add_option_function<std::vector<std::string>>(
      "--factor-range",
      [o](const std::vector<std::string>& all) {
        for (const auto& text : all) o->ranges.push_back(openscenario::parse_factor_range(text));
      },
      "KEY=FROM:TO:STEP: the values the campaign sweeps a factor over (repeatable; any factor of the scene, "
      "speed_kph in km/h; replaces a parameter distribution's)");
  cmd->add_option("-o,--output", o->output, "Write the scene here (default: print it)");
  cmd->add_option("--campaign", o->campaign,
                  "Also write a campaign over the scene (needs -o): the ranges of a ParameterValueDistribution file "
                  "and of --factor-range, the TTC over 0.1-2 s unless given");
  cmd->add_option("--trace", o->trace,
                  "Also write every entity's open-loop trajectory as CSV (t, actor, x, y, heading, speed; OpenDRIVE "
                  "world frame), to compare with another engine's recording");
  cmd->add_option("--trace-s", o->trace_s, "How long the trace runs (s)")->check(CLI::PositiveNumber);
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
