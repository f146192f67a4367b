#pragma once

// The remaining time of a sweep from a cost model (docs/campaign.md, "Progress and ETA"): cells
// fall into cost classes known before they run (campaign/sweep_progress.cpp: infeasible, feasible, braking
// alone cannot stop), each class's mean time per cell is learnt from the cells done, and the sum
// over the cells left is scaled by the parallelism observed so far. A rate over all cells done
// would be wrong whenever the mix of classes changes along the run (the dearest run first).

#include <array>
#include <cstddef>
#include <optional>

namespace emrm::campaign {

class EtaModel {
 public:
  static constexpr std::size_t kClasses = 3;

  /// `counts[c]`: cells of class c to run.
  explicit EtaModel(const std::array<std::size_t, kClasses>& counts) : left_(counts) {}

  /// One cell of class `cost` took `seconds` of one worker's time.
  void record(int cost, double seconds) noexcept;

  /// Seconds left, given the wall-clock seconds since the start; nullopt before any cell is done.
  /// A class with no cell done yet costs the mean over the classes that have some.
  [[nodiscard]] std::optional<double> remaining_seconds(double elapsed_s) const noexcept;

 private:
  std::array<std::size_t, kClasses> left_{};
  std::array<std::size_t, kClasses> done_{};
  std::array<double, kClasses> busy_s_{};  ///< worker time spent per class
};

}  // namespace emrm::campaign
