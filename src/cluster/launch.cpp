#include <algorithm>
#include <optional>
#include <string>

#include "emrm/cluster/mpi_sweep.hpp"

namespace emrm::cluster {

std::optional<std::string> mpi_unavailable(const std::function<const char*(const char*)>& environment) {
  if (!mpi_built())
    return "--mpi: this emrm was built without MPI (EMRM_WITH_MPI is off: install Open MPI with "
           "scripts/install-deps.sh and rebuild); run without --mpi on one machine (emrm sweep can also split a "
           "campaign with --shard K/N, joined by emrm merge)";
  // Checked before MPI_Init: started alone, Open MPI would quietly run a job of one rank.
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (environment(launched) != nullptr) return std::nullopt;
  return "--mpi: not started by an MPI launcher; run `mpirun -n N emrm ... --mpi` (srun under Slurm, "
         "docs/cluster.md), or leave out --mpi to use this machine's cores";
}

double busiest_above_mean(const std::vector<RankStats>& ranks) {
  if (ranks.size() < 2) return 0.0;
  double busiest = 0.0;
  double total = 0.0;
  for (const RankStats& rank : ranks) {
    const double per_thread = rank.simulation_seconds / std::max(rank.threads, 1);
    busiest = std::max(busiest, per_thread);
    total += per_thread;
  }
  const double mean = total / static_cast<double>(ranks.size());
  return mean > 0.0 ? busiest / mean - 1.0 : 0.0;
}

}  // namespace emrm::cluster
