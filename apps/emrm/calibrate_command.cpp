// `emrm calibrate (--stops FILE | --decel-trace FILE | --regions FILE) --fit NAME[,NAME...] -o PROFILE.yaml`:
// fits actuation parameters to measured brake tests or to a grid's region fractions
// (docs/actuation.md, "Calibration" and "Calibrating to a map"). Exit 1
// when the fit did not converge (no profile written), or when a parameter is not identifiable, lies
// on its bound or is confounded with another (the profile is written with the warning in it).

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "emrm/calibration/calibrate.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/text.hpp"
#include "emrm/sim/scene.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

struct CalibrateOptions {
  std::string stops;
  std::string trace;
  std::string regions;
  std::vector<std::string> match;
  std::string campaign_file;
  int threads = 0;
  std::vector<std::string> fit;
  std::vector<std::string> bounds;
  std::string scene_file;
  std::string profile;
  std::string output;
  bool json = false;
  std::string command_line;
};

// NAME=LO:HI
std::pair<std::string, calibration::FitBounds> parse_bound(const std::string& text) {
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
  if (o.stops.empty() + o.trace.empty() + o.regions.empty() != 2)
    throw UsageError("emrm calibrate: give exactly one of --stops, --decel-trace and --regions");
  if (!o.match.empty() && o.regions.empty()) throw UsageError("--match needs --regions");
  if (!o.campaign_file.empty() && o.regions.empty()) throw UsageError("--campaign needs --regions");
  if (!o.regions.empty() && o.campaign_file.empty())
    throw UsageError("--regions needs --campaign FILE: the campaign whose grid the fractions are of");
  if (!o.regions.empty() && !o.scene_file.empty())
    throw UsageError("--regions takes its scene from --campaign; drop --scene");
  calibration::CalibrationRequest request;
  request.fit = o.fit;
  for (const auto& b : o.bounds) {
    const auto [name, bound] = parse_bound(b);
    request.bounds[name] = bound;
  }

  std::optional<calibration::RegionCalibration> regions;
  calibration::CalibrationResult r;
  if (!o.regions.empty()) {
    const calibration::RegionTarget target = calibration::read_region_target(o.regions);
    campaign::Campaign c = campaign::load_campaign(o.campaign_file);
    if (!o.profile.empty()) campaign::apply_profile(c, o.profile);
    request.start = c.scene.actuation;
    regions = calibration::calibrate_regions(c, target, o.match, request, o.threads);
    r = regions->calibration;
  } else {
    sim::SceneConfig scene = o.scene_file.empty() ? sim::SceneConfig{} : sim::load_scene_config(o.scene_file);
    if (!o.profile.empty()) sim::apply_profile(scene, o.profile, std::filesystem::path(o.scene_file).parent_path());
    request.start = scene.actuation;
    r = o.stops.empty() ? calibration::calibrate_trace(calibration::read_decel_trace(o.trace), request)
                        : calibration::calibrate_stops(calibration::read_stops(o.stops), request);
  }
  const std::string description =
      !o.regions.empty() ? fmt::format("fitted to the region fractions of {} (grid '{}')",
                                       std::filesystem::path(o.regions).filename().string(), regions->grid)
                         : fmt::format("fitted to the {} of {}", o.stops.empty() ? "speed trace" : "stops",
                                       std::filesystem::path(o.stops.empty() ? o.trace : o.stops).filename().string());
  if (r.converged) core::write_file(o.output, calibration::profile_yaml(r, o.command_line, description));

  const calibration::RegionCalibration* by_regions = regions ? &*regions : nullptr;
  if (o.json)
    fmt::print("{}\n", calibration::to_json(r, by_regions).dump(2));
  else if (!o.regions.empty())
    fmt::print("{}", calibration::to_text(r, by_regions, o.regions, "points", o.output));
  else
    fmt::print("{}", calibration::to_text(r, nullptr, o.stops.empty() ? o.trace : o.stops,
                                          o.stops.empty() ? "m/s" : "m", o.output));
  return static_cast<int>(r.converged && r.warnings.empty() ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_calibrate_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Fit the actuation (brake dead time, ramp, deceleration cap, perception latency) to measured stops, a speed\n"
      "trace or a grid's region fractions with NLopt; print each value with its 95 % profile-likelihood interval\n"
      "and write a profile for --profile");
  cmd->add_option("--stops", o->stops, "CSV of stops: speed_kph, mu, stop_distance_m[, time_to_stop_s]");
  cmd->add_option("--decel-trace", o->trace, "CSV of speed traces: run, t_s, speed_mps (t = 0 at the brake command)");
  cmd->add_option(
      "--regions", o->regions,
      "YAML of target region fractions of a grid: grid, regions_pct {G, Y, O, R} (or a paper_reference.yaml)");
  cmd->add_option("--match", o->match, "With --regions: the fractions to fit, e.g. G (default: all the file gives)")
      ->delimiter(',');
  cmd->add_option("--campaign", o->campaign_file, "With --regions: the campaign that defines the grid");
  add_threads_option(cmd, o->threads, "With --regions: threads for simulating the grid (0 = all cores)");
  cmd->add_option("--fit", o->fit,
                  "Parameters to fit: brake_dead_time_s, brake_ramp_s, max_decel_mps2, perception_latency_s")
      ->required()
      ->delimiter(',');
  cmd->add_option("--bounds", o->bounds, "Search range NAME=LO:HI (repeatable)");
  cmd->add_option("--scene", o->scene_file,
                  "Scene whose actuation gives the parameters not fitted (not with --regions)");
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
