// The cells of a sweep in the order they run, and the committer that stores their records
// (docs/campaign.md, "Progress and ETA"): a batch committed by whichever worker finds one waiting,
// the progress bar, the --progress-log and the remaining time from the cells' cost classes.

#include <fmt/format.h>
#include <oneapi/tbb/info.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "emrm/core/error.hpp"
#include "emrm/sim/stop_physics.hpp"
#include "sweep_parts.hpp"

namespace emrm::campaign::detail {

Committer::Committer(ResultStore& store, std::size_t total, bool progress, std::string unit, EtaModel eta,
                     std::FILE* log)
    : store_(store),
      total_(total),
      progress_(progress),
      unit_(std::move(unit)),
      start_(Clock::now()),
      eta_(eta),
      log_(log) {
  last_commit_ns_ = now_ns();
}

void Committer::add(CellRecord record, int cost, double seconds) {
  std::size_t waiting = 0;
  {
    std::lock_guard lock(pending_mutex_);
    pending_.push_back(std::move(record));
    waiting = pending_.size();
    eta_.record(cost, seconds);
  }
  ++simulated_;
  if (waiting < kBatchCells && now_ns() - last_commit_ns_.load() < kBatchNs) return;
  std::unique_lock lock(commit_mutex_, std::try_to_lock);
  if (lock) flush_locked();
}

void Committer::finish() {
  std::lock_guard lock(commit_mutex_);
  flush_locked();
  if (progress_ && drew_) std::fputs("\n", stderr);
  drew_ = false;  // called after every adaptive grid: one line break per bar
}

void Committer::flush_locked() {
  std::vector<CellRecord> batch;
  {
    std::lock_guard lock(pending_mutex_);
    batch.swap(pending_);
  }
  store_.insert(batch);
  last_commit_ns_ = now_ns();
  if (progress_) draw();
  if (log_ != nullptr) log_line();
}

std::optional<double> Committer::remaining_s() {
  if (!estimate_) return std::nullopt;
  const double seconds = static_cast<double>(now_ns()) * 1e-9;
  std::lock_guard lock(pending_mutex_);
  return eta_.remaining_seconds(seconds);
}

void Committer::log_line() {
  const auto left = remaining_s();
  std::fprintf(log_, "{\"done\": %zu, \"total\": %zu, \"elapsed_s\": %.3f, \"eta_s\": %s}\n", simulated_.load(), total_,
               static_cast<double>(now_ns()) * 1e-9, left ? fmt::format("{:.3f}", *left).c_str() : "null");
  std::fflush(log_);
}

void Committer::draw() {
  const std::size_t done = simulated_.load();
  const double seconds = static_cast<double>(now_ns()) * 1e-9;
  const double rate = seconds > 0.0 ? static_cast<double>(done) / seconds : 0.0;
  const double fraction = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string eta = "--:--";
  if (const auto left_s = remaining_s()) {
    const auto left = std::llround(*left_s);
    eta = fmt::format("{}:{:02d}", left / 60, left % 60);
  }
  std::fprintf(stderr, "\r[%s%s] %zu/%zu %s  %.1f %s/s  ETA %s ", std::string(filled, '#').c_str(),
               std::string(kWidth - filled, '.').c_str(), done, total_, unit_.c_str(), rate, unit_.c_str(),
               eta.c_str());
  std::fflush(stderr);
  drew_ = true;
}

std::unique_ptr<std::FILE, CloseFile> open_progress_log(const std::filesystem::path& log) {
  if (log.empty()) return nullptr;
  std::unique_ptr<std::FILE, CloseFile> file(std::fopen(log.string().c_str(), "w"));
  if (!file) throw UsageError(fmt::format("--progress-log: cannot write '{}'", log.string()));
  return file;
}

int local_threads(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

int expected_cost(const Campaign& campaign, const WorkItem& item) {
  const sim::CellInput& cell = campaign.grids[item.grid].cells[item.index];
  const sim::Scene scene(campaign.scene, cell);
  if (!scene.feasible()) return 0;
  if (!sim::stop_boundary_applies(campaign.scene)) return 2;  // no closed form: assume the dearer class
  return sim::stop_margin_m(scene.speed_kph(), scene.ttc_s(), scene.friction(), campaign.scene.actuation) < 0.0 ? 2 : 1;
}

std::array<std::size_t, EtaModel::kClasses> order_work(std::vector<WorkItem>& work) {
  std::mt19937_64 random(0x5eed5eedULL);
  std::shuffle(work.begin(), work.end(), random);
  std::stable_sort(work.begin(), work.end(), [](const WorkItem& a, const WorkItem& b) { return a.cost > b.cost; });
  std::array<std::size_t, EtaModel::kClasses> counts{}, taken{};
  for (const WorkItem& item : work) ++counts[static_cast<std::size_t>(item.cost)];
  for (WorkItem& item : work) {
    const auto c = static_cast<std::size_t>(item.cost);
    item.probe = taken[c]++ < std::max<std::size_t>(4, counts[c] / 20);  // 5 % of the class, at least 4
  }
  std::stable_partition(work.begin(), work.end(), [](const WorkItem& item) { return item.probe; });
  return counts;  // cells per class
}

}  // namespace emrm::campaign::detail
