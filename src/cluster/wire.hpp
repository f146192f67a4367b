#pragma once

// The messages between the ranks of `--mpi` (docs/cluster.md) and their encoding. Internal to
// src/cluster; no MPI here: they are sent and received through transport.hpp.
//
// Messages:
//   hello   worker → 0   {threads}: how many threads it simulates with (MessagePack JSON), once
//   job     0 → worker   Job: a campaign to sweep (its cells come in chunks), or the end of the
//                        command with its exit code (a cereal binary archive)
//   results worker → 0   Results: the records of a finished chunk (none in the first two), whether
//                        it asks for another chunk, whether it is its last message of the job (a
//                        cereal binary archive: every double and integer exactly, infinities
//                        included, without building a document first)
//   chunk   0 → worker   the answer to each request: cells to simulate; none: no more (the same)
// A worker asks for two chunks at the start of a job and for one more each time it finishes one,
// so it always holds one in reserve and never waits for rank 0; rank 0 then need not answer at
// once, and probes for messages every few milliseconds instead of spinning. An adaptive search
// asks for its cells one by one as it goes: rank 0 then answers a request once a cell is asked
// for. A worker leaves a job only once every request is answered and its last message sent, so
// no message is left unmatched at MPI_Finalize.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/distribute.hpp"
#include "emrm/campaign/records.hpp"

namespace emrm::cluster::detail {

// A simulated cell as a worker sends it back.
struct Simulated {
  int cost = 0;
  double seconds = 0.0;
  campaign::CellRecord record;
  template <class Archive>
  void serialize(Archive& archive) {
    archive(cost, seconds, record);
  }
};

// A worker's message to rank 0: at the start, after each chunk, and at the end.
struct Results {
  bool more = true;                 ///< asks for another chunk (answered with one, maybe empty)
  bool last = false;                ///< the worker leaves: no chunk in hand, no request unanswered
  bool returns_chunk = false;       ///< `done` is its oldest chunk in hand, finished
  std::uint64_t cells = 0;          ///< simulated so far
  double simulation_seconds = 0.0;  ///< thread-seconds spent on them
  std::vector<Simulated> done;      ///< a finished chunk's cells (after an interrupt, those started)
  template <class Archive>
  void serialize(Archive& archive) {
    archive(more, last, returns_chunk, cells, simulation_seconds, done);
  }
};

using Chunk = std::vector<campaign::CellTask>;

// Rank 0's word to the workers: sweep this campaign, or the command ended with this exit code.
struct Job {
  std::optional<campaign::Campaign> campaign;
  std::string hash;  ///< the campaign's config hash on rank 0
  int exit_code = 0;
  template <class Archive>
  void serialize(Archive& archive) {
    archive(campaign, hash, exit_code);
  }
};

constexpr int kTagHello = 1;
constexpr int kTagJob = 2;
constexpr int kTagResults = 3;
constexpr int kTagChunk = 4;

/// A job, a chunk or results as a cereal portable binary archive (wire.cpp), and back.
template <class Message>
[[nodiscard]] std::string to_archive(const Message& message);
template <class Message>
[[nodiscard]] Message from_archive(const std::string& bytes);

}  // namespace emrm::cluster::detail
