// A worker's part of a job over the ranks (roles.hpp): the chunks rank 0 hands it, simulated with
// this rank's threads, their records sent back.

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "emrm/campaign/distribute.hpp"
#include "emrm/core/interrupt.hpp"
#include "roles.hpp"
#include "transport.hpp"
#include "wire.hpp"

namespace emrm::cluster::detail {
namespace {

using Clock = std::chrono::steady_clock;

// Simulates the chunks rank 0 sends with this rank's threads until it sends none. This thread
// talks to rank 0 while another simulates, so a chunk in reserve is always on its way.
void serve(const campaign::Campaign& campaign, int threads) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Chunk> todo;                       // received, not started
  std::deque<std::vector<Simulated>> finished;  // simulated, not sent
  bool closing = false;
  std::jthread simulating([&] {
    for (;;) {
      Chunk chunk;
      {
        std::unique_lock lock(mutex);
        wake.wait(lock, [&] { return !todo.empty() || closing; });
        if (todo.empty()) return;
        chunk = std::move(todo.front());
        todo.pop_front();
      }
      std::vector<std::optional<Simulated>> cells(chunk.size());
      tbb::parallel_for(std::size_t{0}, chunk.size(), [&](std::size_t i) {
        if (core::interrupt_signal() != 0) return;  // the cells not started are simulated by the rerun
        const auto start = Clock::now();
        campaign::CellRecord record = campaign::simulate_task(campaign, chunk[i]);
        cells[i] =
            Simulated{chunk[i].cost, std::chrono::duration<double>(Clock::now() - start).count(), std::move(record)};
      });
      std::vector<Simulated> done;
      for (auto& cell : cells)
        if (cell) done.push_back(std::move(*cell));
      std::lock_guard lock(mutex);
      finished.push_back(std::move(done));
    }
  });
  const auto stop_simulating = [&] {
    {
      std::lock_guard lock(mutex);
      closing = true;
    }
    wake.notify_one();
  };

  Results results;
  int unanswered = 0;    // requests rank 0 has not answered yet
  std::size_t held = 0;  // chunks received and not sent back
  bool no_more = false;  // rank 0 answered with no cells, or an interrupt came
  const auto report = [&](std::vector<Simulated> done, bool ask, bool returns_chunk) {
    for (const Simulated& cell : done) results.simulation_seconds += cell.seconds;
    results.cells += done.size();
    results.done = std::move(done);
    results.more = ask;
    results.returns_chunk = returns_chunk;
    send_archive(results, 0, kTagResults);
    unanswered += ask ? 1 : 0;
  };
  try {
    const bool ask = core::interrupt_signal() == 0;  // stopped before the job: no cells, only the last word
    report({}, ask, false);                          // one chunk to simulate
    report({}, ask, false);                          // and one in reserve
  } catch (...) {
    stop_simulating();
    throw;
  }
  Backoff backoff;
  while (unanswered > 0 || held > 0) {
    bool idle = true;
    const std::optional<Probed> probed = probe(0, kTagChunk);
    if (probed) {
      idle = false;
      --unanswered;
      auto chunk = from_archive<Chunk>(receive_bytes(*probed));
      if (chunk.empty()) {
        no_more = true;
      } else {
        ++held;
        {
          std::lock_guard lock(mutex);
          todo.push_back(std::move(chunk));
        }
        wake.notify_one();
      }
    }
    std::optional<std::vector<Simulated>> done;
    {
      std::lock_guard lock(mutex);
      if (!finished.empty()) {
        done = std::move(finished.front());
        finished.pop_front();
      }
    }
    if (done) {
      idle = false;
      --held;
      no_more = no_more || core::interrupt_signal() != 0;
      report(std::move(*done), !no_more, true);
    }
    if (idle) {
      backoff.wait();
    } else {
      backoff.reset();
    }
  }
  stop_simulating();
  results.last = true;
  report({}, false, false);
}

}  // namespace

// A worker's part of the command: the jobs rank 0 sends, until it sends the exit code.
int work(int threads) {
  for (;;) {
    Job job = from_archive<Job>(wait_for(0, kTagJob));
    if (!job.campaign) return job.exit_code;
    if (campaign::config_hash(*job.campaign) != job.hash) {  // the campaign changed on its way: a bug
      std::fprintf(stderr,
                   "emrm: internal error: a rank received another campaign than rank 0 sent (config hash %s, "
                   "rank 0's %s)\n",
                   campaign::config_hash(*job.campaign).c_str(), job.hash.c_str());
      std::fflush(nullptr);
      abort_job(70);
    }
    serve(*job.campaign, threads);
  }
}

}  // namespace emrm::cluster::detail
