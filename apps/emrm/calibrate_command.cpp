// `emrm calibrate (--stops FILE | --decel-trace FILE) --fit NAME[,NAME...] -o PROFILE.yaml`: fits the
// brakes' actuation parameters to measured brake tests (docs/actuation.md, "Calibration"). Exit 1
// when the fit did not converge (no profile written), or when a parameter is not identifiable, lies
// on its bound or is confounded with another (the profile is written with the warning in it).

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "emrm/campaign/calibrate.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::cli {
namespace {

struct CalibrateOptions {
  std::string stops;
  std::string trace;
  std::vector<std::string> fit;
  std::vector<std::string> bounds;
  std::string scene_file;
  std::string profile;
  std::string output;
  bool json = false;
  std::string command_line;
};

// NAME=LO:HI
std::pair<std::string, campaign::FitBounds> parse_bound(const std::string& text) {
  const auto eq = text.find('=');
  const auto colon = text.find(':', eq == std::string::npos ? 0 : eq);
  const auto number = [&](const std::string& s) {
    const std::optional<double> v = core::parse_finite_number(s);
    if (!v) throw UsageError(fmt::format("--bounds: expected NAME=LO:HI with numbers, got '{}'", text));
    return *v;
  };
  if (eq == std::string::npos || colon == std::string::npos)
    throw UsageError(fmt::format("--bounds: expected NAME=LO:HI, got '{}'", text));
  return {text.substr(0, eq), {number(text.substr(eq + 1, colon - eq - 1)), number(text.substr(colon + 1))}};
}

int run(const CalibrateOptions& o) {
  if (o.stops.empty() == o.trace.empty()) throw UsageError("emrm calibrate: give exactly one of --stops and --decel-trace");
  campaign::CalibrationRequest request;
  request.fit = o.fit;
  for (const auto& b : o.bounds) {
    const auto [name, bound] = parse_bound(b);
    request.bounds[name] = bound;
  }
  sim::SceneConfig scene = o.scene_file.empty() ? sim::SceneConfig{} : sim::load_scene_config(o.scene_file);
  if (!o.profile.empty())
    sim::apply_profile(scene, o.profile, std::filesystem::path(o.scene_file).parent_path());
  request.start = scene.actuation;

  const campaign::CalibrationResult r = o.stops.empty()
                                            ? campaign::calibrate_trace(campaign::read_decel_trace(o.trace), request)
                                            : campaign::calibrate_stops(campaign::read_stops(o.stops), request);
  if (r.converged) core::write_file(o.output, campaign::profile_yaml(r, o.command_line));

  if (o.json) {
    nlohmann::ordered_json j;
    j["fitted"] = nlohmann::ordered_json::object();
    for (const auto& [name, v] : r.fitted)
      j["fitted"][name] = {{"value", v.value}, {"ci_low", v.ci_low}, {"ci_high", v.ci_high}, {"identifiable", v.identifiable}};
    j["residual_rms"] = r.residual_rms;
    j["observations"] = r.observations;
    j["converged"] = r.converged;
    j["warnings"] = r.warnings;
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("Calibrated from {} ({} observations), residual RMS {:.4g} {}:\n", o.stops.empty() ? o.trace : o.stops,
               r.observations, r.residual_rms, o.stops.empty() ? "m/s" : "m");
    for (const auto& [name, v] : r.fitted)
      fmt::print("  {:<22} {:>9.4f}   95 % interval [{:.4f}, {:.4f}]{}\n", name, v.value, v.ci_low, v.ci_high,
                 v.identifiable ? "" : "   NOT IDENTIFIABLE");
    for (const auto& w : r.warnings) fmt::print("warning: {}\n", w);
    if (r.converged) fmt::print("Wrote {}\n", o.output);
    else fmt::print("The fit did not converge: no profile written.\n");
  }
  return static_cast<int>(r.converged && r.warnings.empty() ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_calibrate_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Fit the brakes' actuation (dead time, ramp, deceleration cap) to measured stops or a speed trace with\n"
      "NLopt; print each value with its 95 % profile-likelihood interval and write a profile for --profile");
  cmd->add_option("--stops", o->stops, "CSV of stops: speed_kph, mu, stop_distance_m[, time_to_stop_s]")
      ->check(CLI::ExistingFile);
  cmd->add_option("--decel-trace", o->trace, "CSV of speed traces: run, t_s, speed_mps (t = 0 at the brake command)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--fit", o->fit, "Parameters to fit: brake_dead_time_s, brake_ramp_s, max_decel_mps2")
      ->required()
      ->delimiter(',');
  cmd->add_option("--bounds", o->bounds, "Search range NAME=LO:HI (repeatable)");
  cmd->add_option("--scene", o->scene_file, "Scene whose actuation gives the parameters not fitted")
      ->check(CLI::ExistingFile);
  cmd->add_option("--profile", o->profile, "Profile overlaying that scene first (NAME or FILE)");
  cmd->add_option("-o,--output", o->output, "Profile YAML to write")->required();
  cmd->add_flag("--json", o->json, "Print {fitted: {NAME: {value, ci_low, ci_high}}, residual_rms, converged}");
  cmd->callback([o, cmd, &exit_code] {
    o->command_line = "emrm calibrate";
    for (const auto& opt : cmd->get_options()) {
      if (opt->count() == 0 || opt->get_name() == "--help") continue;
      if (opt->get_type_size() == 0) {
        o->command_line += " " + opt->get_name();
        continue;
      }
      for (const auto& value : opt->results()) o->command_line += " " + opt->get_name() + " " + value;
    }
    exit_code = run(*o);
  });
}

}  // namespace emrm::cli
