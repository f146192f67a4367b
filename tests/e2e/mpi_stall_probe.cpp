// A two-rank MPI program for MpiCli.ARankStoppedHalfWayThroughAMessageIsGivenUp: rank 1 starts
// sending a message far larger than a shared-memory fragment and stops itself (SIGSTOP) before
// pushing the rest; rank 0 receives it with cluster::detail::receive_bytes_within, which must give
// up within its patience instead of waiting for ever (the coordinator's hang this guards against),
// then lets rank 1 go on and both end. Prints one line; exit 0 when rank 0 gave up in time, 1 when
// it did not, 77 when the stop came before anything of the message had arrived (inconclusive).

#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>

#include "transport.hpp"

namespace {

constexpr int kTagPid = 1, kTagBig = 2;
constexpr std::size_t kBytes = std::size_t{64} << 20;

int rank_zero() {
  using Clock = std::chrono::steady_clock;
  int pid = 0;
  MPI_Recv(&pid, 1, MPI_INT, 1, kTagPid, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::optional<emrm::cluster::detail::Probed> probed;
  for (const auto until = Clock::now() + std::chrono::seconds(10); !probed && Clock::now() < until;) {
    probed = emrm::cluster::detail::probe(1, kTagBig);
    if (!probed) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  int code = 77;
  if (probed) {
    const auto start = Clock::now();
    const auto bytes = emrm::cluster::detail::receive_bytes_within(*probed, std::chrono::seconds(1));
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    // Rank 1 may have pushed it all before it stopped (a fast transport): then it arrived whole.
    code = bytes && bytes->size() == kBytes ? 77 : (!bytes && seconds < 5.0 ? 0 : 1);
    std::printf("%s after %.2f s\n", bytes ? "received" : "gave up", seconds);
  } else {
    std::printf("nothing of the message arrived before rank 1 stopped\n");
  }
  kill(pid, SIGCONT);
  return code;
}

void rank_one() {
  const int pid = static_cast<int>(getpid());
  MPI_Send(&pid, 1, MPI_INT, 0, kTagPid, MPI_COMM_WORLD);
  std::string big(kBytes, 'x');
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Isend(big.data(), static_cast<int>(big.size()), MPI_BYTE, 0, kTagBig, MPI_COMM_WORLD, &request);
  raise(SIGSTOP);  // half-way: rank 0 has the first fragment at most
  MPI_Wait(&request, MPI_STATUS_IGNORE);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int code = 0;
  if (rank == 0)
    code = rank_zero();
  else
    rank_one();
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);  // rank 0's progress lets rank 1's send finish
  MPI_Finalize();
  std::fflush(stdout);
  return code;
}
