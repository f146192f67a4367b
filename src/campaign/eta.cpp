#include "emrm/campaign/eta.hpp"

#include <algorithm>
#include <numeric>

namespace emrm::campaign {

void EtaModel::record(int cost, double seconds) noexcept {
  const auto c = static_cast<std::size_t>(std::clamp(cost, 0, static_cast<int>(kClasses) - 1));
  ++done_[c];
  if (left_[c] > 0) --left_[c];
  busy_s_[c] += std::max(seconds, 0.0);
}

std::optional<double> EtaModel::remaining_seconds(double elapsed_s) const noexcept {
  const std::size_t done = std::accumulate(done_.begin(), done_.end(), std::size_t{0});
  const double busy = std::accumulate(busy_s_.begin(), busy_s_.end(), 0.0);
  if (done == 0 || !(busy > 0.0)) return std::nullopt;
  const double overall_mean = busy / static_cast<double>(done);
  double work_left = 0.0;  // worker seconds
  for (std::size_t c = 0; c < kClasses; ++c) {
    const double mean = done_[c] > 0 ? busy_s_[c] / static_cast<double>(done_[c]) : overall_mean;
    work_left += mean * static_cast<double>(left_[c]);
  }
  // Wall time per worker second so far: 1/threads when every worker is busy.
  return work_left * (std::max(elapsed_s, 0.0) / busy);
}

}  // namespace emrm::campaign
