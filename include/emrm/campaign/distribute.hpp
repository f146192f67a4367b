#pragma once

// Handing a sweep's cells to other processes (docs/cluster.md). sweep() keeps everything that makes
// a campaign a campaign — the store, resume, the order of work, the batches, the interrupt, the
// exports — and a Distributor given in SweepOptions only moves cells out and records back.

#include <cstddef>
#include <cstdint>
#include <optional>

#include "emrm/campaign/campaign.hpp"
#include "emrm/campaign/records.hpp"

namespace emrm::campaign {

/// A cell a sweep still has to simulate: its grid's position in the campaign, its index there and
/// its expected cost class (0 infeasible, 1 feasible, 2 braking cannot stop in time).
struct CellTask {
  std::uint32_t grid = 0;
  std::uint32_t index = 0;
  int cost = 0;
};

/// Simulates one cell as every sweep does, with the cell's own seed: the record is the same on any
/// process and thread. Pure; thread-safe.
[[nodiscard]] CellRecord simulate_task(const Campaign& campaign, const CellTask& task);

/// The cells of a running sweep, dearest first, shared by its own threads and a Distributor.
/// Thread-safe.
class TaskQueue {
 public:
  virtual ~TaskQueue() = default;
  /// The next cell to simulate; none once all are taken or after an interrupt.
  virtual std::optional<CellTask> next() = 0;
  /// Cells not taken yet.
  [[nodiscard]] virtual std::size_t remaining() const = 0;
  /// A cell simulated elsewhere and the seconds it took there: committed in the sweep's next batch.
  /// Throws emrm::Error when the store cannot be written.
  virtual void deliver(CellRecord record, int cost, double seconds) = 0;
  /// Whether cells may still come after next() found none: an adaptive search asks for each cell
  /// as it goes, so a Distributor keeps waiting for cells until the search ends.
  [[nodiscard]] virtual bool open() const { return false; }
};

/// Runs on the thread that called sweep(), beside the sweep's own threads: takes cells of
/// `campaign` from the queue for other processes and delivers their records; returns when the
/// queue is closed and every cell it took is delivered, or after an interrupt. Called once per
/// run of cells: a sweep's cells, then each adaptive grid's.
class Distributor {
 public:
  virtual ~Distributor() = default;
  virtual void distribute(const Campaign& campaign, TaskQueue& queue) = 0;
  /// Threads simulating on the other processes: an adaptive search keeps as many more of its
  /// simulations in flight.
  [[nodiscard]] virtual int threads() const noexcept { return 0; }
};

}  // namespace emrm::campaign
