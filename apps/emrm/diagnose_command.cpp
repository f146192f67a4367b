// `emrm diagnose DIR`: the campaign diagnostics of `emrm reproduce` on any results store
// (docs/results.md, "Diagnostics"): the stop boundary, monotonicity, the RRT against the reference
// planner on a sample, FSM transition coverage. Writes DIR/diagnostics.json and DIR/fsm/; the
// report shows them. Exit 1 when the stored regions contradict the analytic stop boundary.

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "emrm/campaign/store.hpp"
#include "emrm/core/error.hpp"
#include "emrm/results/diagnostics.hpp"
#include "emrm/sim/scene.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

namespace fs = std::filesystem;

struct DiagnoseOptions {
  std::string dir;
  std::size_t sample = 40;
  std::optional<std::uint64_t> seed;
  int threads = 0;
};

int run(const DiagnoseOptions& options) {
  const fs::path dir(options.dir);
  const fs::path store = campaign::results_store_in(dir, "emrm diagnose");
  const campaign::CampaignMeta meta = campaign::read_meta(store);
  const sim::SceneConfig scene = sim::parse_stored_scene_config(meta.scene_yaml, store.string() + " (scene)");
  const auto records = campaign::read_results(store);
  results::DiagnosticsOptions diagnostics_options;
  diagnostics_options.reference_sample = options.sample;
  diagnostics_options.seed = options.seed.value_or(meta.seed);
  diagnostics_options.threads = options.threads;
  const auto diagnostics = results::run_diagnostics(records, scene, diagnostics_options);
  results::write_diagnostics(dir, diagnostics);
  fmt::print("Diagnostics of {} ({} cells): {}\n", dir.string(), records.size(), results::summary(diagnostics));
  fmt::print("Wrote {}/diagnostics.json and {}/fsm; `emrm report {}` shows them\n", dir.string(), dir.string(),
             dir.string());
  if (!results::contradicts_physics(diagnostics)) return static_cast<int>(ExitCode::kSuccess);
  fmt::print(
      "diagnose: stored regions contradict the analytic stop boundary; the cells are listed in "
      "diagnostics.json (exit 1)\n");
  return static_cast<int>(ExitCode::kFindings);
}

}  // namespace

void register_diagnose_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose",
      "Diagnose a results store: regions against the analytic stop boundary, monotonicity in TTC and mu,\n"
      "the RRT against the reference planner on a sample of cells, FSM transition coverage. Writes\n"
      "DIR/diagnostics.json and DIR/fsm/; exit 1 when a region contradicts the stop boundary");
  cmd->add_option("DIR", o->dir, "results folder written by emrm sweep, run or reproduce")->required();
  cmd->add_option("--sample", o->sample, "Cells the reference planner re-checks (0: none)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{100000}));
  cmd->add_option("--seed", o->seed, "Seed of the sample (default: the campaign's)")->check(seed_value());
  add_threads_option(cmd, o->threads, "Worker threads (0: all cores)");
  cmd->callback([o, &exit_code] { exit_code = run(*o); });
}

}  // namespace emrm::cli
