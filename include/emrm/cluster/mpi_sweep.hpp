#pragma once

// Campaign sweeps over the ranks of an MPI job (docs/cluster.md): rank 0 runs the command —
// campaign::sweep() owns the results store, resumes, refuses another configuration and writes the
// exports — and hands cells out in chunks on demand to every rank, itself included, with the
// campaign they belong to; the records come back to it and are committed in its batches. Results
// are byte for byte those of one process.
//
// Nothing here names an MPI type: without MPI (EMRM_WITH_MPI off) the same functions exist and
// refuse with a UsageError, so the command line builds either way.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/distribute.hpp"
#include "emrm/campaign/sweep.hpp"

namespace emrm::cluster {

/// Whether this build has MPI (the CMake option EMRM_WITH_MPI).
[[nodiscard]] bool mpi_built() noexcept;

/// Why --mpi cannot run in this process, or none: not built with MPI, or not started by an MPI
/// launcher (mpirun, mpiexec, srun: they set OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_RANK).
/// `environment` looks a variable up (std::getenv; a test passes its own).
[[nodiscard]] std::optional<std::string> mpi_unavailable(const std::function<const char*(const char*)>& environment);

/// MPI for the life of the object (MPI_Init_thread, funneled: only this thread calls MPI;
/// MPI_Finalize when destroyed). One per process. Throws UsageError (exit 2) with
/// mpi_unavailable()'s reason.
class MpiSession {
 public:
  MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  // MPI_Finalize (or MPI_Abort) with MPI; defaulted in the build without it (without_mpi.cpp).
  ~MpiSession();  // NOLINT(performance-trivially-destructible)
  [[nodiscard]] int rank() const noexcept { return rank_; }
  [[nodiscard]] int size() const noexcept { return size_; }
  /// End with MPI_Abort(exit_code) instead of MPI_Finalize, which waits for every rank: a rank
  /// given up as hung would never come.
  void abort_at_exit(int exit_code) noexcept { abort_code_ = exit_code; }

 private:
  int rank_ = 0;
  int size_ = 1;
  std::optional<int> abort_code_;
};

/// What each rank did, gathered on rank 0: the load-balance and overhead figures of the summary.
struct RankStats {
  std::size_t cells = 0;            ///< cells it simulated
  double simulation_seconds = 0.0;  ///< thread-seconds spent simulating them
  int threads = 0;
};

struct ClusterSummary {
  campaign::SweepSummary sweep;
  std::vector<RankStats> ranks;  ///< by rank; rank 0's own threads first
  std::size_t chunks = 0;        ///< chunks handed to other ranks
  std::size_t cells_sent = 0;    ///< cells in them
  /// CPU seconds of rank 0's coordinating thread, without its commits: answering messages
  /// (receiving, decoding, choosing and sending chunks) plus probing for them between messages.
  double coordination_seconds = 0.0;
  /// Of that, answering messages alone: the work per cell that bounds how many ranks one
  /// coordinator can serve (docs/cluster.md, "Scaling").
  double handling_seconds = 0.0;
  /// CPU seconds the coordinating thread spent committing batches (which any sweep spends somewhere).
  double committing_seconds = 0.0;
  /// Ranks given up as hung (silent for `hung_after_s` while holding cells, or while rank 0 awaited
  /// only their last message); their cells were simulated by the others. The process then ends by
  /// MPI_Abort, exit code 0.
  std::vector<int> lost_ranks;
};

/// Seconds a rank holding cells may stay silent before rank 0 gives them to the others.
inline constexpr double kDefaultHungAfterSeconds = 600.0;

/// How much the busiest rank's simulation time per thread exceeds the mean over the ranks that
/// simulated: 0.05 is 5 % above. 0 for fewer than two ranks.
[[nodiscard]] double busiest_above_mean(const std::vector<RankStats>& ranks);

/// Rank 0's view of the job while its command runs.
class Ranks {
 public:
  virtual ~Ranks() = default;
  /// Hands the cells of every sweep it is given to (campaign::SweepOptions::distributor) to all
  /// ranks; an adaptive search's simulations too.
  [[nodiscard]] virtual campaign::Distributor& distributor() noexcept = 0;
  [[nodiscard]] virtual int size() const noexcept = 0;
  /// The figures of the last sweep distributed, `sweep` being what campaign::sweep() returned.
  [[nodiscard]] virtual ClusterSummary summary(const campaign::SweepSummary& sweep) const = 0;
};

/// A command over every rank of `session` (`emrm sweep`, `run` and `reproduce` with --mpi,
/// docs/cluster.md). Every rank calls it with the same arguments. Rank 0 runs `command` and
/// returns what it returns; each sweep the command runs with Ranks::distributor() sends its
/// campaign to the other ranks, which simulate the cells they are handed with `threads` threads
/// (0: every core) until rank 0's command ends, and then return its exit code, having printed
/// nothing. A rank silent for `hung_after_s` while it holds cells is given up
/// (ClusterSummary::lost_ranks): its cells go to the others, and the job ends by MPI_Abort with
/// the command's exit code.
///
/// Throws on rank 0 what `command` throws (the other ranks return the exit code the command line
/// gives it: 2 for emrm::Error, 128 + signal for core::Interrupted, 70 otherwise); a sweep whose
/// cells handed to other ranks did not all come back (a rank stopped on its own) throws
/// core::Interrupted, everything that came back committed.
int run_on_ranks(MpiSession& session, int threads, double hung_after_s, const std::function<int(Ranks&)>& command);

}  // namespace emrm::cluster
