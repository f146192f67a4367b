// The MPI side of cluster/mpi_sweep.hpp (built only with EMRM_WITH_MPI; without_mpi.cpp otherwise),
// and the only file of emrm that includes <mpi.h>: the session, the point-to-point messages of
// transport.hpp, and run_on_ranks, which gives each rank its part (roles.hpp). The messages are in
// wire.hpp.

#include "emrm/cluster/mpi_sweep.hpp"

#include <mpi.h>
#include <oneapi/tbb/info.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "emrm/core/error.hpp"
#include "roles.hpp"
#include "transport.hpp"

namespace emrm::cluster {
namespace detail {

void send_bytes(const std::string& bytes, int to, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

namespace {

Probed probed_of(const MPI_Status& status) {
  int size = 0;
  MPI_Get_count(&status, MPI_BYTE, &size);
  return {status.MPI_SOURCE, status.MPI_TAG, size};
}

}  // namespace

std::optional<Probed> probe(int source, int tag) {
  int arrived = 0;
  MPI_Status status;
  MPI_Iprobe(source, tag, MPI_COMM_WORLD, &arrived, &status);
  if (arrived == 0) return std::nullopt;
  return probed_of(status);
}

std::optional<Probed> probe_any(int tag) { return probe(MPI_ANY_SOURCE, tag); }

namespace {

// Receives into `bytes` until done or past `deadline`; false then, with the receive left pending.
bool receive_into(std::string& bytes, const Probed& probed,
                  std::optional<std::chrono::steady_clock::time_point> deadline) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Irecv(bytes.data(), probed.size, MPI_BYTE, probed.source, probed.tag, MPI_COMM_WORLD, &request);
  for (int tests = 0;; ++tests) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done != 0) return true;
    if (deadline && std::chrono::steady_clock::now() > *deadline) {
      MPI_Request_free(&request);  // legal for an active receive: MPI completes it when it can
      return false;
    }
    if (tests < 8)
      std::this_thread::yield();
    else
      std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
}

}  // namespace

std::string receive_bytes(const Probed& probed) {
  std::string bytes(static_cast<std::size_t>(probed.size), '\0');
  receive_into(bytes, probed, std::nullopt);
  return bytes;
}

std::optional<std::string> receive_bytes_within(const Probed& probed, std::chrono::steady_clock::duration patience) {
  // On the heap and never freed when given up: MPI may still write the rest of the message into it.
  auto bytes = std::make_unique<std::string>(static_cast<std::size_t>(probed.size), '\0');
  if (receive_into(*bytes, probed, std::chrono::steady_clock::now() + patience)) return std::move(*bytes);
  (void)bytes.release();  // NOLINT(bugprone-unused-return-value): deliberately kept for MPI
  return std::nullopt;
}

std::string wait_for(int source, int tag) {
  Backoff backoff;
  for (;;) {
    if (const auto probed = probe(source, tag)) return receive_bytes(*probed);
    backoff.wait();
  }
}

void abort_job(int exit_code) { MPI_Abort(MPI_COMM_WORLD, exit_code); }

}  // namespace detail

namespace {

using Json = nlohmann::json;
using detail::kTagHello;

// The hello message (wire.hpp) as MessagePack JSON.
void send(const Json& message, int to, int tag) {
  const std::vector<std::uint8_t> bytes = Json::to_msgpack(message);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

Json receive(const MPI_Status& probed) { return Json::from_msgpack(detail::receive_bytes(detail::probed_of(probed))); }

int thread_count(int requested) { return requested > 0 ? requested : tbb::info::default_concurrency(); }

}  // namespace

bool mpi_built() noexcept { return true; }

MpiSession::MpiSession() {
  if (const auto reason = mpi_unavailable([](const char* name) { return std::getenv(name); }))
    throw UsageError(*reason);
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (abort_code_) {  // a hung rank would never reach MPI_Finalize: end them all, with this exit code
    std::fflush(nullptr);
    MPI_Abort(MPI_COMM_WORLD, *abort_code_);
  }
  MPI_Finalize();
}

int run_on_ranks(MpiSession& session, int threads, double hung_after_s, const std::function<int(Ranks&)>& command) {
  if (session.rank() != 0) {
    send(Json{{"threads", thread_count(threads)}}, 0, kTagHello);
    return detail::work(threads);
  }
  std::vector<int> rank_threads(static_cast<std::size_t>(session.size()), thread_count(threads));
  for (int r = 1; r < session.size(); ++r) {
    MPI_Status status;
    MPI_Probe(r, kTagHello, MPI_COMM_WORLD, &status);
    rank_threads[static_cast<std::size_t>(r)] = receive(status)["threads"].get<int>();
  }
  return detail::coordinate(session, rank_threads, hung_after_s, command);
}

}  // namespace emrm::cluster
