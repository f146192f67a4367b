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

int run_on_ranks(MpiSession&, int, double, const std::function<int(Ranks&)>&) {
  return 2;  // unreachable: no MpiSession exists without MPI
}

}  // namespace emrm::cluster
