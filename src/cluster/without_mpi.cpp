// cluster/mpi_sweep.hpp in a build without MPI (EMRM_WITH_MPI off): --mpi is refused, exit 2.

#include <cstdlib>

#include "emrm/cluster/mpi_sweep.hpp"
#include "emrm/core/error.hpp"

namespace emrm::cluster {

bool mpi_built() noexcept { return false; }

MpiSession::MpiSession() {
  throw UsageError(*mpi_unavailable([](const char* name) { return std::getenv(name); }));
}

MpiSession::~MpiSession() = default;

std::optional<ClusterSummary> sweep(MpiSession&, const std::function<campaign::Campaign()>&,
                                    const campaign::SweepOptions&, double, bool& refused) {
  refused = true;  // unreachable: no MpiSession exists without MPI
  return std::nullopt;
}

}  // namespace emrm::cluster
