// The MPI side of cluster/mpi_sweep.hpp (built only with EMRM_WITH_MPI; without_mpi.cpp otherwise).
//
// Messages (all MessagePack, nlohmann::json's binary form, which keeps every double and integer
// exactly, infinities included):
//   hello   worker → 0   {hash, threads} or {error}: what the worker loaded
//   go      0 → worker   true: sweep; false: rank 0 refuses the job and reports why
//   results worker → 0   [more, cells, simulation seconds, [[cost, seconds, record], ...]]: the
//                        records of its last chunk (none in the first), and whether it takes more
//   chunk   0 → worker   [[grid, index, cost], ...]: cells to simulate; empty: stop
// A worker always waits for rank 0's answer to its results, so no message is left unmatched when
// the ranks finalize.

#include <mpi.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <thread>
#include <vector>

#include "emrm/campaign/distribute.hpp"
#include "emrm/cluster/mpi_sweep.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/interrupt.hpp"

namespace emrm::cluster {
namespace {

using Clock = std::chrono::steady_clock;
using Json = nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

constexpr int kTagHello = 1;
constexpr int kTagGo = 2;
constexpr int kTagResults = 3;
constexpr int kTagChunk = 4;

// A chunk holds about this many seconds of simulation per thread of the rank it goes to: long
// enough that the coordinator's work per chunk (about 0.1 ms a message) is noise, short enough
// that the last chunks end close together.
constexpr double kChunkSecondsPerThread = 0.25;
// A cell of a class not seen yet is assumed this dear, so the first chunks are small.
constexpr double kUnknownCellSeconds = 0.05;
constexpr std::size_t kMaxChunkCells = 4096;
// After an interrupt rank 0 waits this long for the chunks in flight. A rank that died (mpirun
// then ends the job) never answers; what it had is simulated again by the rerun.
constexpr auto kInterruptGrace = std::chrono::seconds(5);

// ---- records on the wire: every field of CellRecord and OutcomeRecord, in declaration order ----

Json to_wire(const campaign::OutcomeRecord& o) {
  return Json::array({o.strategy, o.avoided, o.contact, o.road_departure, o.impact_speed_kph, o.delta_v_kph,
                      o.p_mais3, o.p_fatal, o.loss_level, o.delta_loss, o.min_ttc_s, o.planner_nodes,
                      o.planner_rollouts, o.fsm_trace, o.loss_evaluation_trace, o.chosen_strategy, o.adopted_from,
                      o.evidence, o.maneuver, o.path, o.goal_tree, o.failsafe_tree});
}

Json to_wire(const campaign::CellRecord& r) {
  Json outcomes = Json::array();
  for (const auto& o : r.outcomes) outcomes.push_back(to_wire(o));
  return Json::array({r.grid, r.index, r.speed_kph, r.ttc_s, r.mu, r.passage_m, r.truck_speed_kph, r.seed,
                      r.feasible, r.region, r.unmitigated_impact_speed_kph, r.unmitigated_delta_v_kph,
                      r.unmitigated_p_mais3, r.unmitigated_p_fatal, r.unmitigated_loss_level, r.evidence,
                      r.mitigation_evidence, r.strengthened, r.certificate, r.p_mais3_reduction,
                      r.p_fatal_reduction, std::move(outcomes), r.method, r.inferred_from});
}

campaign::OutcomeRecord outcome_from_wire(const Json& j) {
  campaign::OutcomeRecord o;
  std::size_t f = 0;
  j.at(f++).get_to(o.strategy);
  j.at(f++).get_to(o.avoided);
  j.at(f++).get_to(o.contact);
  j.at(f++).get_to(o.road_departure);
  j.at(f++).get_to(o.impact_speed_kph);
  j.at(f++).get_to(o.delta_v_kph);
  j.at(f++).get_to(o.p_mais3);
  j.at(f++).get_to(o.p_fatal);
  j.at(f++).get_to(o.loss_level);
  j.at(f++).get_to(o.delta_loss);
  j.at(f++).get_to(o.min_ttc_s);
  j.at(f++).get_to(o.planner_nodes);
  j.at(f++).get_to(o.planner_rollouts);
  j.at(f++).get_to(o.fsm_trace);
  j.at(f++).get_to(o.loss_evaluation_trace);
  j.at(f++).get_to(o.chosen_strategy);
  j.at(f++).get_to(o.adopted_from);
  j.at(f++).get_to(o.evidence);
  j.at(f++).get_to(o.maneuver);
  j.at(f++).get_to(o.path);
  j.at(f++).get_to(o.goal_tree);
  j.at(f++).get_to(o.failsafe_tree);
  return o;
}

campaign::CellRecord cell_from_wire(const Json& j) {
  campaign::CellRecord r;
  std::size_t f = 0;
  j.at(f++).get_to(r.grid);
  j.at(f++).get_to(r.index);
  j.at(f++).get_to(r.speed_kph);
  j.at(f++).get_to(r.ttc_s);
  j.at(f++).get_to(r.mu);
  j.at(f++).get_to(r.passage_m);
  j.at(f++).get_to(r.truck_speed_kph);
  j.at(f++).get_to(r.seed);
  j.at(f++).get_to(r.feasible);
  j.at(f++).get_to(r.region);
  j.at(f++).get_to(r.unmitigated_impact_speed_kph);
  j.at(f++).get_to(r.unmitigated_delta_v_kph);
  j.at(f++).get_to(r.unmitigated_p_mais3);
  j.at(f++).get_to(r.unmitigated_p_fatal);
  j.at(f++).get_to(r.unmitigated_loss_level);
  j.at(f++).get_to(r.evidence);
  j.at(f++).get_to(r.mitigation_evidence);
  j.at(f++).get_to(r.strengthened);
  j.at(f++).get_to(r.certificate);
  j.at(f++).get_to(r.p_mais3_reduction);
  j.at(f++).get_to(r.p_fatal_reduction);
  for (const Json& o : j.at(f++)) r.outcomes.push_back(outcome_from_wire(o));
  j.at(f++).get_to(r.method);
  j.at(f++).get_to(r.inferred_from);
  return r;
}

// ---- point-to-point messages ----

void send(const Json& message, int to, int tag) {
  const Bytes bytes = Json::to_msgpack(message);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

Json receive(const MPI_Status& probed) {
  int size = 0;
  MPI_Get_count(&probed, MPI_BYTE, &size);
  Bytes bytes(static_cast<std::size_t>(size));
  MPI_Recv(bytes.data(), size, MPI_BYTE, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return Json::from_msgpack(bytes);
}

// Open MPI's blocking calls poll the network without pause; a rank waiting so would take a core
// from the threads simulating beside it. So waits probe and sleep, from 50 µs up to 1 ms.
class Backoff {
 public:
  void reset() noexcept { pause_ = kShortest; }
  void wait() {
    std::this_thread::sleep_for(pause_);
    pause_ = std::min(pause_ * 2, kLongest);
  }

 private:
  static constexpr std::chrono::microseconds kShortest{50};
  static constexpr std::chrono::microseconds kLongest{1000};
  std::chrono::microseconds pause_ = kShortest;
};

Json wait_for(int source, int tag) {
  Backoff backoff;
  for (;;) {
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &arrived, &status);
    if (arrived != 0) return receive(status);
    backoff.wait();
  }
}

int thread_count(int requested) { return requested > 0 ? requested : tbb::info::default_concurrency(); }

// ---- rank 0 ----

// Hands cells out to the other ranks on demand, sized by what cells of each cost class took so
// far, and delivers their records to the sweep's committer.
class MpiDistributor final : public campaign::Distributor {
 public:
  MpiDistributor(int ranks, std::vector<int> threads)
      : threads_(std::move(threads)), stats_(static_cast<std::size_t>(ranks)), active_(ranks - 1) {
    for (int r = 1; r < ranks; ++r) stats_[static_cast<std::size_t>(r)].threads = threads_[static_cast<std::size_t>(r)];
  }

  void distribute(campaign::TaskQueue& queue) override { serve_until_stopped(queue, kInterruptGrace); }

  /// Stops the ranks still waiting when the sweep failed before or while it distributed: each is
  /// answered with no cells, whatever it sends is dropped.
  void release() noexcept {
    class NoCells final : public campaign::TaskQueue {
     public:
      std::optional<campaign::CellTask> next() override { return std::nullopt; }
      [[nodiscard]] std::size_t remaining() const override { return 0; }
      void deliver(campaign::CellRecord, int, double) override {}
    } none;
    try {
      serve_until_stopped(none, std::chrono::seconds(0));
    } catch (...) {  // the error being reported matters more than this one
    }
  }

  [[nodiscard]] std::vector<RankStats>& stats() noexcept { return stats_; }
  [[nodiscard]] std::size_t chunks() const noexcept { return chunks_; }
  [[nodiscard]] std::size_t cells_sent() const noexcept { return cells_sent_; }
  [[nodiscard]] double coordination_seconds() const noexcept {
    return std::chrono::duration<double>(coordination_).count();
  }

 private:
  // Answers results with chunks until every rank is stopped; after an interrupt (or with a zero
  // `grace`, at once) gives up `grace` after the last message came.
  void serve_until_stopped(campaign::TaskQueue& queue, Clock::duration grace) {
    std::optional<Clock::time_point> quiet_since;
    Backoff backoff;
    while (active_ > 0) {
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, kTagResults, MPI_COMM_WORLD, &arrived, &status);
      if (arrived == 0) {
        if (core::interrupt_signal() != 0 || grace == Clock::duration::zero()) {
          if (!quiet_since) quiet_since = Clock::now();
          if (Clock::now() - *quiet_since > std::max<Clock::duration>(grace, std::chrono::seconds(2))) return;
        }
        backoff.wait();
        continue;
      }
      backoff.reset();
      quiet_since.reset();
      const auto start = Clock::now();
      const Json message = receive(status);
      const int rank = status.MPI_SOURCE;
      RankStats& stats = stats_[static_cast<std::size_t>(rank)];
      stats.cells = message.at(1).get<std::size_t>();
      stats.simulation_seconds = message.at(2).get<double>();
      for (const Json& cell : message.at(3)) {
        const int cost = cell.at(0).get<int>();
        const double seconds = cell.at(1).get<double>();
        learn(cost, seconds);
        queue.deliver(cell_from_wire(cell.at(2)), cost, seconds);
      }
      Json chunk = Json::array();
      if (message.at(0).get<bool>()) chunk = next_chunk(queue, rank);
      send(chunk, rank, kTagChunk);
      if (chunk.empty()) --active_;
      coordination_ += Clock::now() - start;
    }
  }

  void learn(int cost, double seconds) {
    const auto c = static_cast<std::size_t>(std::clamp(cost, 0, 2));
    class_seconds_[c] += seconds;
    ++class_cells_[c];
  }

  [[nodiscard]] double expected_seconds(int cost) const {
    const auto c = static_cast<std::size_t>(std::clamp(cost, 0, 2));
    return class_cells_[c] > 0 ? class_seconds_[c] / static_cast<double>(class_cells_[c]) : kUnknownCellSeconds;
  }

  // About kChunkSecondsPerThread of work per thread of the rank; near the end, no more than a
  // share of what is left, so that the ranks finish together (guided self-scheduling).
  Json next_chunk(campaign::TaskQueue& queue, int rank) {
    const double budget = kChunkSecondsPerThread * threads_[static_cast<std::size_t>(rank)];
    const std::size_t share = std::max<std::size_t>(1, queue.remaining() / (2 * stats_.size()));
    const std::size_t limit = std::min(share, kMaxChunkCells);
    Json chunk = Json::array();
    double expected = 0.0;
    while (chunk.size() < limit && expected < budget) {
      const auto task = queue.next();
      if (!task) break;
      chunk.push_back(Json::array({task->grid, task->index, task->cost}));
      expected += expected_seconds(task->cost);
    }
    if (!chunk.empty()) ++chunks_;
    cells_sent_ += chunk.size();
    return chunk;
  }

  std::vector<int> threads_;
  std::vector<RankStats> stats_;
  int active_ = 0;  ///< ranks not told to stop yet
  std::array<double, 3> class_seconds_{};
  std::array<std::size_t, 3> class_cells_{};
  std::size_t chunks_ = 0;
  std::size_t cells_sent_ = 0;
  Clock::duration coordination_{};
};

// ---- the other ranks ----

// Simulates the chunks rank 0 sends with this rank's threads until it sends none.
void serve(const campaign::Campaign& campaign, int threads) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::size_t cells = 0;
  double busy_seconds = 0.0;
  Json done = Json::array();
  for (;;) {
    const bool more = core::interrupt_signal() == 0;
    send(Json::array({more, cells, busy_seconds, std::move(done)}), 0, kTagResults);
    const Json chunk = wait_for(0, kTagChunk);
    if (chunk.empty()) return;
    std::vector<campaign::CellTask> tasks;
    for (const Json& cell : chunk)
      tasks.push_back({cell.at(0).get<std::uint32_t>(), cell.at(1).get<std::uint32_t>(), cell.at(2).get<int>()});
    std::vector<Json> results(tasks.size());
    std::atomic<std::int64_t> busy_ns{0};
    tbb::parallel_for(std::size_t{0}, tasks.size(), [&](std::size_t i) {
      if (core::interrupt_signal() != 0) return;  // the cells not started are simulated by the rerun
      const auto start = Clock::now();
      campaign::CellRecord record = campaign::simulate_task(campaign, tasks[i]);
      const auto spent = Clock::now() - start;
      busy_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(spent).count();
      results[i] = Json::array({tasks[i].cost, std::chrono::duration<double>(spent).count(), to_wire(record)});
    });
    done = Json::array();
    for (Json& result : results)
      if (!result.is_null()) {
        done.push_back(std::move(result));
        ++cells;
      }
    busy_seconds += static_cast<double>(busy_ns.load()) * 1e-9;
  }
}

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

MpiSession::~MpiSession() { MPI_Finalize(); }

std::optional<ClusterSummary> sweep(const MpiSession& session, const std::function<campaign::Campaign()>& load,
                                    const campaign::SweepOptions& options, bool& refused) {
  refused = false;
  const int threads = thread_count(options.threads);
  // Every rank loads the campaign; rank 0 hears from every other rank before any cell runs, so a
  // bad campaign is reported once (by rank 0) and a rank that sees other files stops the job.
  std::optional<campaign::Campaign> campaign;
  std::exception_ptr failed;
  std::string failure;
  try {
    campaign = load();
    if (campaign::sweeps_adaptively(*campaign, options))
      throw UsageError("--mpi: the adaptive search is not yet distributed over MPI ranks; run it without --mpi on "
                       "one machine (every core: --threads 0)");
  } catch (const std::exception& e) {
    failed = std::current_exception();
    failure = e.what();
  }

  if (session.rank() != 0) {
    send(failed ? Json{{"error", failure}} : Json{{"hash", campaign::config_hash(*campaign)}, {"threads", threads}}, 0,
         kTagHello);
    if (!wait_for(0, kTagGo).get<bool>()) {
      refused = true;
      return std::nullopt;
    }
    serve(*campaign, options.threads);
    return std::nullopt;
  }

  std::vector<int> rank_threads(static_cast<std::size_t>(session.size()), threads);
  std::string mismatch;
  for (int r = 1; r < session.size(); ++r) {
    MPI_Status status;
    MPI_Probe(r, kTagHello, MPI_COMM_WORLD, &status);
    const Json hello = receive(status);
    if (hello.contains("error")) {
      if (mismatch.empty())
        mismatch = fmt::format("--mpi: rank {} could not load the campaign: {}", r, hello["error"].get<std::string>());
    } else if (!failed && hello["hash"].get<std::string>() != campaign::config_hash(*campaign)) {
      if (mismatch.empty())
        mismatch = fmt::format("--mpi: rank {} loaded another configuration (config hash {}, rank 0's is {}); every "
                               "rank must read the same campaign, scene and profile",
                               r, hello["hash"].get<std::string>(), campaign::config_hash(*campaign));
    } else {
      rank_threads[static_cast<std::size_t>(r)] = hello["threads"].get<int>();
    }
  }
  const bool go = !failed && mismatch.empty();
  for (int r = 1; r < session.size(); ++r) send(Json(go), r, kTagGo);
  if (failed) std::rethrow_exception(failed);
  if (!mismatch.empty()) throw UsageError(mismatch);

  MpiDistributor distributor(session.size(), rank_threads);
  campaign::SweepOptions rank0_options = options;
  if (session.size() > 1) rank0_options.distributor = &distributor;
  ClusterSummary summary;
  try {
    summary.sweep = campaign::sweep(*campaign, rank0_options);
  } catch (...) {  // another configuration in the store, an interrupt, a disk full: let the ranks go
    distributor.release();
    throw;
  }
  summary.ranks = std::move(distributor.stats());
  summary.ranks[0].threads = threads;
  summary.ranks[0].simulation_seconds = summary.sweep.simulation_seconds;
  std::size_t remote = 0;
  for (std::size_t r = 1; r < summary.ranks.size(); ++r) remote += summary.ranks[r].cells;
  summary.ranks[0].cells = summary.sweep.cells_simulated - remote;
  summary.chunks = distributor.chunks();
  summary.cells_sent = distributor.cells_sent();
  summary.coordination_seconds = distributor.coordination_seconds();
  return summary;
}

}  // namespace emrm::cluster
