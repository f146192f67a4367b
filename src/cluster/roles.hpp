#pragma once

// The two parts a rank plays in run_on_ranks (mpi_sweep.cpp): rank 0 runs the command and hands
// cells out (distributor.cpp), every other rank simulates what it is handed (worker.cpp). Internal
// to src/cluster.

#include <functional>
#include <vector>

#include "emrm/cluster/mpi_sweep.hpp"

namespace emrm::cluster::detail {

/// Rank 0's part: runs `command` with a distributor over the ranks, whose threads `rank_threads`
/// gives (rank 0's first), and ends the job: what run_on_ranks returns on rank 0.
int coordinate(MpiSession& session, const std::vector<int>& rank_threads, double hung_after_s,
               const std::function<int(Ranks&)>& command);

/// A worker's part of the command: the jobs rank 0 sends, until it sends the exit code.
int work(int threads);

}  // namespace emrm::cluster::detail
