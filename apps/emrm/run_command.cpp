// `emrm run SCENARIOS.csv -o DIR`: a planned scenario set through the campaign engine, with the
// statistics of the paper's §V-B (docs/plan.md). Exit 1 when the plan recorded shortfalls (repeated
// as warnings), as `emrm plan` exited 1 for them.

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/workflow/run.hpp"
#include "mpi_options.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

struct RunCommandOptions {
  std::string scenarios;
  std::string output_dir;
  std::string safety;
  int threads = 0;
  std::string profile;
  MpiOptions mpi;
};

// `ranks`: rank 0 of an MPI job (--mpi), whose other ranks simulate scenarios; null: this process alone.
int run(const RunCommandOptions& o, cluster::Ranks* ranks) {
  if (!std::filesystem::is_regular_file(o.scenarios))
    throw UsageError(fmt::format("emrm run: '{}' does not exist", o.scenarios));
  workflow::RunOptions options;
  options.scenarios_csv = o.scenarios;
  options.output_dir = o.output_dir;
  options.threads = o.threads;
  options.profile = o.profile;
  if (ranks != nullptr) options.distributor = &ranks->distributor();
  if (!o.safety.empty()) {
    if (!std::filesystem::is_regular_file(o.safety))
      throw UsageError(fmt::format("emrm run: --safety '{}' does not exist", o.safety));
    options.safety_file = o.safety;
  }
  const workflow::RunResult r = workflow::run_scenarios(options);
  fmt::print("{}", workflow::to_text(r, o.scenarios, o.output_dir));
  // The plan's shortfalls are the same exit 1 as `emrm plan` gave them: the evidence has gaps.
  return static_cast<int>(r.plan_shortfalls.empty() ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_run_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<RunCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Simulate a planned scenario set (scenarios.csv from `emrm plan`) and estimate per cell and per "
      "malfunction (Wilson, Hoeffding, weighted S(A)); resumable like `emrm sweep`.\n"
      "Exit 0: done; 1: done, but the plan fell short of its targets (warnings say where); 2: bad input.");
  cmd->add_option("SCENARIOS", options->scenarios, "scenarios.csv written by `emrm plan`")->required();
  cmd->add_option("-o,--output", options->output_dir, "output folder")->required();
  cmd->add_option("--safety", options->safety,
                  "safety case for the traceability matrix (default: the plan's, from scenarios.json)");
  add_threads_option(cmd, options->threads, "worker threads (0: all cores)");
  cmd->add_option(
      "--profile", options->profile,
      "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE (docs/actuation.md)");
  add_mpi_options(cmd, options->mpi, "mpirun -n N emrm run ... --mpi");
  cmd->callback([options, &exit_code] {
    const core::InterruptScope interrupts;  // Ctrl-C keeps what is done (docs/campaign.md)
    exit_code = on_ranks(options->mpi, options->threads, [&](cluster::Ranks* ranks) { return run(*options, ranks); });
  });
}

}  // namespace emrm::cli
