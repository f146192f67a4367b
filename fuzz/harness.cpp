#include "harness.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "emrm/calibration/calibrate.hpp"
#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/exports.hpp"
#include "emrm/campaign/plan_settings.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/exchange/assess.hpp"
#include "emrm/fsm/load.hpp"
#include "emrm/report/plan_figures.hpp"
#include "emrm/report/report.hpp"
#include "emrm/results/paper_reference.hpp"
#include "emrm/results/run_estimates.hpp"
#include "emrm/safety/analysis.hpp"
#include "emrm/safety/load.hpp"
#include "emrm/safety/traceability.hpp"
#include "emrm/scenario/odd.hpp"
#include "emrm/scenario/pict_model.hpp"
#include "emrm/scenario/plan_io.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::fuzz {
namespace {

namespace fs = std::filesystem;

// A folder of this process's own for the readers that take a path; emptied before each input.
const fs::path& scratch() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("emrm-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

fs::path fresh_scratch() {
  for (const auto& entry : fs::directory_iterator(scratch())) fs::remove_all(entry.path());
  return scratch();
}

void write(const fs::path& path, std::string_view data) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary).write(data.data(), static_cast<std::streamsize>(data.size()));
}

// Where the files an input names (a scene, a safety case) are looked up: the shipped example, so a
// seed from it reaches past its first reference.
fs::path example_dir() { return fs::path(EMRM_SOURCE_DIR) / "examples" / "tjunction"; }

// Each reader on its own: one refusing the input must not keep the next from seeing it.
template <typename F>
void refused_or_read(F&& read) {
  try {
    read();
  } catch (const Error&) {
  } catch (const fs::filesystem_error&) {
  }
}

void safety_case(std::string_view data) {
  safety::SafetyCase sc = safety::parse_safety_case(std::string(data), "safety.yaml");
  (void)safety::analyze(std::move(sc));
}

void fsm_file(std::string_view data) {
  refused_or_read([&] { (void)fsm::parse_generator(std::string(data), "fsm.yaml"); });
  refused_or_read([&] { (void)fsm::parse_traces(std::string(data), "traces.yaml"); });
}

void odd_file(std::string_view data) { (void)scenario::parse_odd(std::string(data), "odd.yaml", example_dir()); }

void scene_file(std::string_view data) { (void)sim::parse_scene_config(std::string(data), "scene.yaml"); }

void campaign_file(std::string_view data) {
  (void)campaign::parse_campaign(std::string(data), "campaign.yaml", example_dir(), /*force=*/false);
}

void pict_model(std::string_view data) { (void)scenario::parse_pict_model(data, "model.pict"); }

// scenarios.json and coverage.json of `emrm plan`.
void plan_json(std::string_view data) {
  const fs::path file = fresh_scratch() / "scenarios.json";
  write(file, data);
  refused_or_read([&] { (void)campaign::read_plan_settings(file); });
  refused_or_read([&] { (void)scenario::parse_coverage_json(std::string(data), "coverage.json"); });
}

void scenarios_csv(std::string_view data) {
  const fs::path file = fresh_scratch() / "scenarios.csv";
  write(file, data);
  (void)scenario::read_scenarios_csv(file);
}

void results_store(std::string_view data) {
  const fs::path file = fresh_scratch() / "results.sqlite";
  write(file, data);
  refused_or_read([&] { (void)campaign::read_meta(file); });
  refused_or_read([&] { (void)campaign::read_results(file); });
  refused_or_read([&] { campaign::write_exports(file, file.parent_path() / "exports"); });
}

// The report's side files: the input stands for each of them at once (what one rejects another
// may take), read as `emrm report` reads them.
void report_side_files(std::string_view data) {
  const fs::path dir = fresh_scratch();
  for (const char* name : {"estimates.json", "diagnostics.json", "verify.json", "analysis/findings.json",
                           "plan/coverage.json", "traceability.csv", "outcomes.csv"})
    write(dir / name, data);
  refused_or_read([&] { (void)report::side_files_html(dir); });
  refused_or_read([&] { (void)safety::read_traceability_csv(dir / "traceability.csv"); });
  refused_or_read([&] { (void)report::read_planned_run(results::find_run_estimates(dir)); });
}

// `emrm calibrate`'s measurements and the paper's reference data.
void measurements(std::string_view data) {
  const fs::path file = fresh_scratch() / "measured";
  write(file, data);
  refused_or_read([&] { (void)calibration::read_stops(file); });
  refused_or_read([&] { (void)calibration::read_decel_trace(file); });
  refused_or_read([&] { (void)calibration::read_region_target(file); });
  refused_or_read([&] { (void)results::parse_paper_reference(std::string(data), "paper_reference.yaml"); });
}

// `emrm assess`'s recorded trajectories, in both formats, judged in one cell of the default scene.
void trajectory_csv(std::string_view data) {
  const sim::SceneConfig config;
  const sim::CellInput cell{50.0, 1.0, 0.8, 3.0, 10.0};
  for (const auto format : {exchange::TrajectoryFormat::kEmrm, exchange::TrajectoryFormat::kEsmini})
    refused_or_read([&] {
      const auto trajectory = exchange::parse_trajectory_csv(data, "trajectory.csv", format, config);
      (void)exchange::assess(config, cell, trajectory);
    });
}

// The command line: the input is the arguments, separated by NUL bytes. Every check of the
// arguments runs, no command does (cli::Mode::kParseOnly); an exit code other than 0, 1 or 2 is a
// bug like a crash.
void command_line(std::string_view data) {
  std::vector<std::string> words{"emrm"};
  std::size_t start = 0;
  while (start <= data.size() && words.size() < 64) {
    const std::size_t end = std::min(data.find('\0', start), data.size());
    words.emplace_back(data.substr(start, end - start));
    start = end + 1;
  }
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const int code = cli::run_cli(static_cast<int>(words.size()), argv.data(), cli::Mode::kParseOnly);
  if (code != 0 && code != 1 && code != 2) std::abort();
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all{
      {"safety", safety_case},
      {"fsm", fsm_file},
      {"odd", odd_file},
      {"scene", scene_file},
      {"campaign", campaign_file},
      {"pict", pict_model},
      {"plan_json", plan_json},
      {"scenarios_csv", scenarios_csv},
      {"results_store", results_store},
      {"report_side_files", report_side_files},
      {"measurements", measurements},
      {"trajectory_csv", trajectory_csv},
      {"cli", command_line},
  };
  return all;
}

const Target* find_target(std::string_view name) {
  for (const Target& t : targets())
    if (t.name == name) return &t;
  return nullptr;
}

void run_one(const Target& target, std::string_view data) {
  refused_or_read([&] { target.run(data); });
}

}  // namespace emrm::fuzz
