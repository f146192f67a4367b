// Rank 0's part of a job over the ranks (roles.hpp): the distributor that hands cells out in chunks
// and takes the records back, and the command's end told to every rank.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "emrm/campaign/distribute.hpp"
#include "emrm/cluster/mpi_sweep.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"
#include "roles.hpp"
#include "transport.hpp"
#include "wire.hpp"

namespace emrm::cluster::detail {
namespace {

using Clock = std::chrono::steady_clock;

// A chunk holds about this many seconds of simulation per thread of the rank it goes to: long
// enough that the coordinator's work per chunk (about 0.1 ms a message) is noise, short enough
// that the last chunks end close together.
constexpr double kChunkSecondsPerThread = 0.25;
// A cell of a class not seen yet is assumed this dear: the first chunk of each rank is one cell.
constexpr double kUnknownCellSeconds = 1.0;
constexpr std::size_t kMaxChunkCells = 4096;
constexpr std::size_t kTrustedCells = 8;
// The tail of a sweep: no more cells left than this many per thread of the job.
constexpr std::size_t kTailCellsPerThread = 4;
// After an interrupt rank 0 waits this long for the chunks in flight. A rank that died (mpirun
// then ends the job) never answers; what it had is simulated again by the rerun.
constexpr auto kInterruptGrace = std::chrono::seconds(5);

// CPU seconds the calling thread has used: what coordination costs the node, whether or not the
// thread waited for a core (on a node whose cores all simulate, wall time would count the waits).
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Hands cells out to the other ranks on demand, sized by what cells of each cost class took so
// far, and delivers their records to the sweep's committer. A rank silent for `hung_after` while
// it holds cells is given up: its cells go to the next ranks that ask (or are simulated here at the
// end), and whatever it sends later is dropped, so no cell is stored twice. Cells a rank hands back
// unsimulated (it was stopped on its own) go to the others the same way.
class MpiDistributor final : public campaign::Distributor, public Ranks {
 public:
  MpiDistributor(int ranks, std::vector<int> threads, Clock::duration hung_after)
      : threads_(std::move(threads)),
        hung_after_(hung_after),
        stats_(static_cast<std::size_t>(ranks)),
        handed_(static_cast<std::size_t>(ranks)),
        returned_(static_cast<std::size_t>(ranks)),
        in_hand_(static_cast<std::size_t>(ranks)),
        deferred_(static_cast<std::size_t>(ranks), 0),
        heard_(static_cast<std::size_t>(ranks), Clock::now()),
        lost_(static_cast<std::size_t>(ranks), 0) {
    for (int t : threads_) total_threads_ += static_cast<std::size_t>(std::max(t, 1));
    for (int r = 1; r < ranks; ++r) stats_[static_cast<std::size_t>(r)].threads = threads_[static_cast<std::size_t>(r)];
  }

  void distribute(const campaign::Campaign& campaign, campaign::TaskQueue& queue) override {
    start_job(campaign);
    serve_until_stopped(queue, kInterruptGrace);
  }

  [[nodiscard]] int threads() const noexcept override {
    int sum = 0;
    for (std::size_t r = 1; r < threads_.size(); ++r) sum += lost_[r] != 0 ? 0 : std::max(threads_[r], 1);
    return sum;
  }

  [[nodiscard]] campaign::Distributor& distributor() noexcept override { return *this; }
  [[nodiscard]] int size() const noexcept override { return static_cast<int>(threads_.size()); }

  [[nodiscard]] ClusterSummary summary(const campaign::SweepSummary& sweep) const override {
    ClusterSummary summary;
    summary.sweep = sweep;
    summary.ranks = stats_;
    summary.ranks[0].threads = threads_[0];
    summary.ranks[0].simulation_seconds = sweep.simulation_seconds + stranded_seconds_;
    std::size_t remote = 0;
    for (std::size_t r = 1; r < summary.ranks.size(); ++r) remote += summary.ranks[r].cells;
    summary.ranks[0].cells = sweep.cells_simulated - std::min(sweep.cells_simulated, remote);
    summary.chunks = chunks_;
    summary.cells_sent = cells_sent_;
    summary.coordination_seconds = cpu_seconds_ - committing_seconds_;
    summary.handling_seconds = handling_seconds_ - committing_seconds_;
    summary.committing_seconds = committing_seconds_;
    summary.lost_ranks = lost_ranks_;
    return summary;
  }

  /// The command ended with `exit_code`: the ranks still serving a job are answered with no
  /// cells (a sweep that failed while it distributed), then every rank not given up is told.
  void finish(int exit_code) noexcept {
    try {
      reissue_.clear();
      if (active_ > 0) {
        class NoCells final : public campaign::TaskQueue {
         public:
          std::optional<campaign::CellTask> next() override { return std::nullopt; }
          [[nodiscard]] std::size_t remaining() const override { return 0; }
          void deliver(campaign::CellRecord, int, double) override {}
        } none;
        serve_until_stopped(none, Clock::duration::zero());
      }
      Job end;
      end.exit_code = exit_code;
      for (std::size_t r = 1; r < lost_.size(); ++r)
        if (lost_[r] == 0) send_archive(end, static_cast<int>(r), kTagJob);
    } catch (...) {  // the error being reported matters more than this one
    }
  }

  /// The ranks given up as hung, in the order they were.
  [[nodiscard]] const std::vector<int>& lost_ranks() const noexcept { return lost_ranks_; }

 private:
  // Sends the campaign to every rank not given up and starts counting this job's cells.
  void start_job(const campaign::Campaign& campaign) {
    campaign_ = &campaign;
    Job job;
    job.campaign = campaign;
    job.hash = campaign::config_hash(campaign);
    active_ = 0;
    for (std::size_t r = 1; r < lost_.size(); ++r) {
      handed_[r] = returned_[r] = 0;
      in_hand_[r].clear();
      deferred_[r] = 0;
      heard_[r] = Clock::now();
      stats_[r].cells = 0;
      stats_[r].simulation_seconds = 0.0;
      if (lost_[r] != 0) continue;
      send_archive(job, static_cast<int>(r), kTagJob);
      ++active_;
    }
    reissue_.clear();
    chunks_ = cells_sent_ = 0;
    cpu_seconds_ = handling_seconds_ = committing_seconds_ = stranded_seconds_ = 0.0;
  }

  // Answers results with chunks until every rank is done with the job; after an interrupt (or
  // with a zero `grace`, at once) gives up `grace` after the last message came.
  void serve_until_stopped(campaign::TaskQueue& queue, Clock::duration grace) {
    const double cpu_start = thread_cpu_seconds();
    std::optional<Clock::time_point> quiet_since;
    Backoff backoff(queue.open() ? std::chrono::microseconds(1000) : std::chrono::microseconds(5000));
    while (active_ > 0) {
      const std::optional<Probed> probed = probe_any(kTagResults);
      if (!probed) {
        give_up_on_hung_ranks(queue);
        const bool answered = answer_waiting(queue, grace);
        if (core::interrupt_signal() != 0 || grace == Clock::duration::zero()) {
          if (!quiet_since) quiet_since = Clock::now();
          if (Clock::now() - *quiet_since > std::max<Clock::duration>(grace, std::chrono::seconds(2))) break;
        }
        if (!answered && !simulate_one_stranded(queue)) backoff.wait();
        continue;
      }
      backoff.reset();
      quiet_since.reset();
      const double handling = thread_cpu_seconds();
      const int rank = probed->source;
      const auto r = static_cast<std::size_t>(rank);
      // A rank that stops half-way through sending is hung: wait for the rest no longer than that.
      const std::optional<std::string> bytes = receive_bytes_within(*probed, hung_after_);
      if (!bytes) {
        if (lost_[r] == 0) give_up(r);
        continue;
      }
      Results message = from_archive<Results>(*bytes);
      heard_[r] = Clock::now();
      if (lost_[r] != 0) {  // its cells went to others: drop them, let it go
        if (message.more) send_archive(Chunk{}, rank, kTagChunk);
        handling_seconds_ += thread_cpu_seconds() - handling;
        continue;
      }
      if (message.returns_chunk && !in_hand_[r].empty()) {
        reissue_unsimulated(in_hand_[r].front(), message.done);
        in_hand_[r].pop_front();
      }
      RankStats& stats = stats_[r];
      stats.cells = message.cells;
      stats.simulation_seconds = message.simulation_seconds;
      returned_[r] += message.done.size();
      for (Simulated& cell : message.done) {
        learn(cell.cost, cell.seconds);
        const double delivering = thread_cpu_seconds();
        // Sometimes commits a batch, as any thread of a sweep does.
        queue.deliver(std::move(cell.record), cell.cost, cell.seconds);
        committing_seconds_ += thread_cpu_seconds() - delivering;
      }
      deferred_[r] += message.more ? 1 : 0;
      answer(queue, rank, grace);
      if (message.last) --active_;
      if (queue.open()) answer_waiting(queue, grace);
      handling_seconds_ += thread_cpu_seconds() - handling;
    }
    cpu_seconds_ += thread_cpu_seconds() - cpu_start;
    while (simulate_one_stranded(queue)) {
    }
  }

  // Answers what rank `rank` asked for and may have now. Near the end a chunk in reserve would keep
  // cells from a rank that has none, so a rank still holding one waits for its next chunk until it
  // returns that one; so does every rank while cells are asked for one by one (an open queue).
  // While the queue is open and has no cell, a request waits. True when a chunk was sent.
  bool answer(campaign::TaskQueue& queue, int rank, Clock::duration grace) {
    const auto r = static_cast<std::size_t>(rank);
    const bool tail = queue.open() || (grace != Clock::duration::zero() &&
                                       queue.remaining() + reissue_.size() <= kTailCellsPerThread * total_threads_);
    bool sent = false;
    while (deferred_[r] > 0 && (in_hand_[r].empty() || !tail)) {
      Chunk chunk = next_chunk(queue, rank);
      if (chunk.empty() && queue.open() && core::interrupt_signal() == 0) break;  // a cell may yet be asked for
      --deferred_[r];
      handed_[r] += chunk.size();
      send_archive(chunk, rank, kTagChunk);
      sent = sent || !chunk.empty();
      if (!chunk.empty()) in_hand_[r].push_back(std::move(chunk));
    }
    return sent;
  }

  // The requests that wait for cells (an open queue), or for its end.
  bool answer_waiting(campaign::TaskQueue& queue, Clock::duration grace) {
    bool sent = false;
    for (std::size_t r = 1; r < deferred_.size(); ++r)
      if (deferred_[r] > 0 && lost_[r] == 0) sent = answer(queue, static_cast<int>(r), grace) || sent;
    return sent;
  }

  // The cells of a returned chunk that came back without a record (the rank was stopped before it
  // started them) go to the others.
  void reissue_unsimulated(const Chunk& chunk, const std::vector<Simulated>& done) {
    if (done.size() == chunk.size()) return;
    std::set<std::pair<std::string, std::int64_t>> back;
    for (const Simulated& cell : done) back.emplace(cell.record.grid, cell.record.index);
    for (const campaign::CellTask& task : chunk)
      if (back.count({campaign_->grids[task.grid].name, task.index}) == 0) reissue_.push_back(task);
  }

  // A rank is given up when silent for hung_after_ while it holds cells, or once nothing is left
  // to hand out and only its last message is awaited.
  void give_up_on_hung_ranks(const campaign::TaskQueue& queue) {
    const auto now = Clock::now();
    const bool nothing_left = !queue.open() && queue.remaining() == 0 && reissue_.empty();
    for (std::size_t r = 1; r < in_hand_.size(); ++r)
      if (lost_[r] == 0 && now - heard_[r] >= hung_after_ && (!in_hand_[r].empty() || nothing_left)) give_up(r);
  }

  // Rank r's cells go to the others; nothing it sends is used from now on.
  void give_up(std::size_t r) {
    lost_[r] = 1;
    lost_ranks_.push_back(static_cast<int>(r));
    --active_;
    for (const Chunk& chunk : in_hand_[r]) reissue_.insert(reissue_.end(), chunk.begin(), chunk.end());
    in_hand_[r].clear();
    handed_[r] = returned_[r];  // its cells are the others' now
  }

  // A cell of a hung or stopped rank that no other rank asked for: simulated on this thread, at
  // the end of a sweep or while cells are asked for one by one (a search waits for it). False when
  // there is none.
  bool simulate_one_stranded(campaign::TaskQueue& queue) {
    if (reissue_.empty() || core::interrupt_signal() != 0 || (active_ > 0 && !queue.open())) return false;
    const campaign::CellTask task = reissue_.front();
    reissue_.pop_front();
    const auto start = Clock::now();
    campaign::CellRecord record = campaign::simulate_task(*campaign_, task);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    stats_[0].cells += 1;
    stranded_seconds_ += seconds;
    queue.deliver(std::move(record), task.cost, seconds);
    return true;
  }

  void learn(int cost, double seconds) {
    const auto c = static_cast<std::size_t>(std::clamp(cost, 0, 2));
    class_seconds_[c] += seconds;
    class_dearest_[c] = std::max(class_dearest_[c], seconds);
    ++class_cells_[c];
  }

  // A class's mean once it rests on kTrustedCells cells; before, its dearest cell (the cells of a
  // class can differ a hundredfold, and a chunk sized by one cheap cell would hold dear ones).
  [[nodiscard]] double expected_seconds(int cost) const {
    const auto c = static_cast<std::size_t>(std::clamp(cost, 0, 2));
    if (class_cells_[c] == 0) return kUnknownCellSeconds;
    if (class_cells_[c] < kTrustedCells) return class_dearest_[c];
    return class_seconds_[c] / static_cast<double>(class_cells_[c]);
  }

  // About kChunkSecondsPerThread of work per thread of the rank, and no more than a quarter of a
  // fair share of the cells left per thread, so that the ranks finish together (guided
  // self-scheduling). Cells asked for one by one: a cell per thread of the rank, as many as wait.
  Chunk next_chunk(campaign::TaskQueue& queue, int rank) {
    const int threads = std::max(threads_[static_cast<std::size_t>(rank)], 1);
    const bool open = queue.open();
    const double budget = open ? std::numeric_limits<double>::infinity() : kChunkSecondsPerThread * threads;
    const std::size_t share = std::max<std::size_t>(1, (queue.remaining() + reissue_.size()) / (4 * total_threads_));
    const std::size_t limit = open ? static_cast<std::size_t>(threads) : std::min(share, kMaxChunkCells);
    Chunk chunk;
    double expected = 0.0;
    while (chunk.size() < limit && expected < budget && core::interrupt_signal() == 0) {
      std::optional<campaign::CellTask> task;
      if (!reissue_.empty()) {  // a hung rank's cells first
        task = reissue_.front();
        reissue_.pop_front();
      } else {
        task = queue.next();
      }
      if (!task) break;
      chunk.push_back(*task);
      expected += expected_seconds(task->cost);
    }
    if (!chunk.empty()) ++chunks_;
    cells_sent_ += chunk.size();
    return chunk;
  }

  const campaign::Campaign* campaign_ = nullptr;  ///< of the job being served
  std::vector<int> threads_;
  Clock::duration hung_after_;
  std::vector<RankStats> stats_;
  std::vector<std::size_t> handed_, returned_;  ///< cells per rank
  std::vector<std::deque<Chunk>> in_hand_;      ///< per rank: chunks sent and not returned, oldest first
  std::vector<int> deferred_;                   ///< per rank: requests not answered yet (the tail)
  std::vector<Clock::time_point> heard_;        ///< per rank: its last message
  std::vector<char> lost_;                      ///< per rank: given up as hung
  std::vector<int> lost_ranks_;
  std::deque<campaign::CellTask> reissue_;  ///< a hung or stopped rank's cells, for the next ranks that ask
  int active_ = 0;                          ///< ranks that have not sent their last message of the job
  std::size_t total_threads_ = 0;
  std::array<double, 3> class_seconds_{};
  std::array<double, 3> class_dearest_{};
  std::array<std::size_t, 3> class_cells_{};
  std::size_t chunks_ = 0;
  std::size_t cells_sent_ = 0;
  double cpu_seconds_ = 0.0;
  double handling_seconds_ = 0.0;
  double committing_seconds_ = 0.0;
  double stranded_seconds_ = 0.0;  ///< rank 0's coordinating thread simulating a hung rank's cells
};

// The exit code the command line gives an error (apps/emrm/cli.cpp).
int exit_code_of(const std::exception& error) {
  if (const auto* interrupted = dynamic_cast<const core::Interrupted*>(&error)) return 128 + interrupted->signal();
  if (dynamic_cast<const Error*>(&error) != nullptr) return 2;
  if (dynamic_cast<const std::filesystem::filesystem_error*>(&error) != nullptr) return 2;
  return 70;
}

}  // namespace

int coordinate(MpiSession& session, const std::vector<int>& rank_threads, double hung_after_s,
               const std::function<int(Ranks&)>& command) {
  MpiDistributor distributor(session.size(), rank_threads,
                             std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(hung_after_s)));
  int exit_code = 0;
  try {
    exit_code = command(distributor);
  } catch (const std::exception& e) {  // another configuration in the store, an interrupt, a disk full
    distributor.finish(exit_code_of(e));
    if (!distributor.lost_ranks().empty()) {
      // The job ends by MPI_Abort, before the command line could print the error: printed here.
      std::fprintf(stderr, "%s\n", e.what());
      session.abort_at_exit(exit_code_of(e));
    }
    throw;
  }
  distributor.finish(exit_code);
  if (!distributor.lost_ranks().empty()) session.abort_at_exit(exit_code);  // everything is stored
  return exit_code;
}

}  // namespace emrm::cluster::detail
