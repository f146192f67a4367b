// `emrm reproduce -o DIR` (workflow::reproduce): exit 1 when the analysis finds errors, an FSM check
// fails, the plan misses C1-C4 or a claim of the store does not verify; bad input escapes as
// emrm::InputError / UsageError (exit 2).

#include <unistd.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "emrm/workflow/reproduce.hpp"
#include "mpi_options.hpp"
#include "options.hpp"

namespace emrm::cli {
namespace {

struct ReproduceOptions {
  std::string output_dir;
  std::string examples_dir;  // empty: search (workflow::find_examples)
  int threads = 0;
  std::size_t sample = 40;
  std::string profile;
  MpiOptions mpi;
};

int run(const ReproduceOptions& options, campaign::Distributor* distributor) {
  workflow::ReproduceOptions o;
  o.output_dir = options.output_dir;
  o.examples_dir = options.examples_dir;
  o.threads = options.threads;
  o.sample = options.sample;
  o.profile = options.profile;
  o.progress = ::isatty(STDERR_FILENO) != 0;
  return static_cast<int>(workflow::reproduce(o, distributor) ? ExitCode::kSuccess : ExitCode::kFindings);
}

}  // namespace

void register_reproduce_command(CLI::App& app, int& exit_code) {
  auto options = std::make_shared<ReproduceOptions>();
  auto* cmd = app.add_subcommand(
      "reproduce",
      "Run the paper's whole case study on the shipped T-junction example: analysis, FSM checks, the "
      "campaign\n"
      "sweep (resumable), tables beside the paper's numbers and diagnostics (docs/results.md).\n"
      "Exit 0: done; 1: the analysis found errors, an FSM check failed or the scenario plan misses C1-C4;\n"
      "2: bad input.");
  cmd->add_option("-o,--output", options->output_dir, "Output folder (a rerun resumes the sweep stored there)")
      ->required()
      ->type_name("DIR");
  add_threads_option(cmd, options->threads, "Worker threads (0: all cores)");
  cmd->add_option(
      "--profile", options->profile,
      "Actuation profile overlaying the scene: a NAME in the scene's profiles/ folder or a FILE (docs/actuation.md)");
  cmd->add_option("--examples", options->examples_dir,
                  "Example folder (default: examples/tjunction here or above, or beside the executable)")
      ->type_name("DIR");
  cmd->add_option("--sample", options->sample, "Cells checked against the reference planner (default 40)")
      ->type_name("N");
  add_mpi_options(cmd, options->mpi, "mpirun -n N emrm reproduce ... --mpi");
  cmd->callback([options, &exit_code] {
    const core::InterruptScope interrupts;  // Ctrl-C keeps what is done (docs/campaign.md)
    exit_code = on_ranks(options->mpi, options->threads, [&](cluster::Ranks* ranks) {
      return run(*options, ranks != nullptr ? &ranks->distributor() : nullptr);
    });
  });
}

}  // namespace emrm::cli
