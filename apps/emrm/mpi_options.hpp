#pragma once

// --mpi and --mpi-hung-after, for the commands that run sweeps over the ranks of an MPI job
// (`emrm sweep`, `run`, `reproduce`; docs/cluster.md).

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "cli.hpp"
#include "emrm/cluster/mpi_sweep.hpp"

namespace emrm::cli {

struct MpiOptions {
  bool mpi = false;
  double hung_after_s = cluster::kDefaultHungAfterSeconds;
};

/// Adds --mpi (`usage`: how the command is started, "mpirun -n N emrm sweep ... --mpi") and
/// --mpi-hung-after to `command`.
inline void add_mpi_options(CLI::App* command, MpiOptions& options, const std::string& usage) {
  command->add_flag("--mpi", options.mpi,
                    "Run as one rank of an MPI job (" + usage +
                        "): rank 0 keeps the store, every rank simulates cells it hands out (docs/cluster.md)");
  command
      ->add_option("--mpi-hung-after", options.hung_after_s,
                   "With --mpi: seconds a rank holding cells may say nothing before rank 0 gives its cells to "
                   "the other ranks (docs/cluster.md)")
      ->check(CLI::Range(1.0, 1e6, "1 to 1000000"))
      ->capture_default_str();
}

/// `command` on this process alone (given no ranks), or with --mpi on rank 0 of the MPI job while
/// the other ranks simulate the cells of its sweeps and then return its exit code
/// (cluster::run_on_ranks); with --mpi, an error of the command is printed on rank 0 and its exit
/// code returned. Throws UsageError (exit 2) for --mpi without MPI or without a launcher.
inline int on_ranks(const MpiOptions& options, int threads, const std::function<int(cluster::Ranks*)>& command) {
  if (!options.mpi) return command(nullptr);
  cluster::MpiSession session;
  return cluster::run_on_ranks(session, threads, options.hung_after_s, [&](cluster::Ranks& ranks) {
    try {
      return command(&ranks);
    } catch (...) {           // printed before the other ranks learn the exit code: a rank that exits non-zero
      return report_error();  // first makes the launcher end the job, rank 0 with it
    }
  });
}

}  // namespace emrm::cli
