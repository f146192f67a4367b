#pragma once

// Point-to-point messages between the ranks: what the coordinator (distributor.cpp) and the workers
// (worker.cpp) send and receive, and how they wait. Internal to src/cluster; the MPI calls behind it
// are in mpi_sweep.cpp, the only file that includes <mpi.h>.

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <thread>

#include "wire.hpp"

namespace emrm::cluster::detail {

/// A message that has arrived and is not received yet: its sender, tag and size in bytes.
struct Probed {
  int source = 0;
  int tag = 0;
  int size = 0;
};

/// MPI_Send of `bytes` to rank `to`.
void send_bytes(const std::string& bytes, int to, int tag);

template <class Message>
void send_archive(const Message& message, int to, int tag) {
  send_bytes(to_archive(message), to, tag);
}

/// A message with `tag` from `source` that has arrived (MPI_Iprobe), or none.
[[nodiscard]] std::optional<Probed> probe(int source, int tag);
/// The same from any rank.
[[nodiscard]] std::optional<Probed> probe_any(int tag);

/// Receives a probed message. A message larger than the transport's eager limit comes in fragments
/// as its sender pushes them; MPI_Recv would spin for them on this process's core, which on rank 0
/// its own simulating threads share: the wait yields it instead.
[[nodiscard]] std::string receive_bytes(const Probed& probed);
/// The same, or none when the message has not all arrived within `patience`: its sender stopped
/// half-way through it (a hung rank, which the caller gives up). The receive is then left to MPI
/// with a buffer that lives as long as the process, should the sender ever go on.
[[nodiscard]] std::optional<std::string> receive_bytes_within(const Probed& probed,
                                                              std::chrono::steady_clock::duration patience);

// Open MPI's blocking calls poll the network without pause; a rank waiting so would take a core
// from the threads simulating beside it. So waits probe and sleep, from 50 µs up to 1 ms.
// Every chunk has one in reserve behind it, so a probe every few milliseconds delays no rank.
class Backoff {
 public:
  /// `longest`: shorter where a wait delays a search that waits for each cell.
  explicit Backoff(std::chrono::microseconds longest = std::chrono::microseconds(5000)) : longest_(longest) {}
  void reset() noexcept { pause_ = kShortest; }
  void wait() {
    std::this_thread::sleep_for(pause_);
    pause_ = std::min(pause_ * 2, longest_);
  }

 private:
  static constexpr std::chrono::microseconds kShortest{50};
  std::chrono::microseconds longest_;
  std::chrono::microseconds pause_ = kShortest;
};

/// The next message with `tag` from `source`, probing with a Backoff between probes.
[[nodiscard]] std::string wait_for(int source, int tag);

/// MPI_Abort of the whole job with `exit_code`.
void abort_job(int exit_code);

}  // namespace emrm::cluster::detail
