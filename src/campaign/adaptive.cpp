// The adaptive search's entry points (search(), the names, Lattice) and the run of a Search.
#include "emrm/campaign/adaptive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "adaptive_search.hpp"
#include "emrm/sim/loss.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::campaign::adaptive {
namespace detail {

Search::Search(const Lattice& lattice, Oracle& oracle, const Options& options)
    : lattice_(lattice), oracle_(oracle), options_(options) {
  for (std::size_t k = 0; k < kAxes; ++k) {
    auto& order = order_[k];
    order.resize(lattice.levels[k].size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return lattice.levels[k][a] < lattice.levels[k][b]; });
  }
  const std::size_t ttc = lattice.ttc_axis, mu = lattice.friction_axis;
  monotone_ = lattice.levels[ttc].size() > 1 ? ttc : (lattice.levels[mu].size() > 1 ? mu : ttc);
  for (std::size_t k = 0; k < kAxes; ++k)
    if (k != monotone_) line_axes_.push_back(k);
  const auto varying =
      std::count_if(line_axes_.begin(), line_axes_.end(), [&](std::size_t k) { return lattice.levels[k].size() > 1; });
  predict_brackets_ = options.brackets == Brackets::kPredict || (options.brackets == Brackets::kAuto && varying >= 2);
  four_factors_ = predict_brackets_ && varying >= 3;
  spread_ = predict_brackets_ ? std::max(options.bracket, options.spread) : options.bracket;
  result_.cells.resize(lattice.size());
  nothing_to_mitigate_.assign(lattice.size(), -1);
  build_lines();
}

Result Search::run() {
  refine(Question::kThresholds);
  refine(Question::kLabels);
  for (Line& line : lines_) {
    settle_prediction(line);
    settle_early(line);
  }
  std::vector<std::size_t> every(lines_.size());
  std::iota(every.begin(), every.end(), std::size_t{0});
  parallel(every, [&](std::size_t id) { research_threshold(lines_[id]); });
  resolve_violations();
  std::vector<std::size_t> all(lines_.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  parallel(all, [&](std::size_t id) { fill(id); });  // each line writes its own cells
  verify();
  finish();
  return std::move(result_);
}

Region Search::simulate(std::uint32_t cell, Purpose purpose) {
  Cell& c = result_.cells[cell];
  if (c.method != Method::kSimulated) {
    c.region = oracle_.simulate(cell);
    c.method = Method::kSimulated;
    c.purpose = static_cast<std::uint8_t>(purpose);
    c.from.clear();
    ++simulated_;
    ++simulated_for_[static_cast<std::size_t>(purpose)];
  }
  return c.region;
}

// Cells whose simulations do not depend on one another, side by side (each once).
void Search::simulate_all(std::vector<std::uint32_t> cells, Purpose purpose) {
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  parallel(cells, [&](std::uint32_t cell) { simulate(cell, purpose); });
}

}  // namespace detail

using sim::Region;

std::size_t Lattice::size() const noexcept {
  std::size_t n = 1;
  for (const auto& l : levels) n *= l.size();
  return n;
}

std::size_t Lattice::index(const std::array<std::size_t, kMaxAxes>& level) const noexcept {
  std::size_t i = 0;
  for (std::size_t k = 0; k < levels.size(); ++k) i = i * levels[k].size() + level[k];
  return i;
}

std::string_view method_name(Method m) noexcept {
  switch (m) {
    case Method::kNone:
      return "";
    case Method::kSimulated:
      return "simulated";
    default:
      return "inferred";
  }
}

std::string_view purpose_name(Purpose p) noexcept {
  switch (p) {
    case Purpose::kThresholdCorners:
      return "threshold_corners";
    case Purpose::kThresholdBrackets:
      return "threshold_brackets";
    case Purpose::kLabels:
      return "labels";
    case Purpose::kLabelBrackets:
      return "label_brackets";
    case Purpose::kViolations:
      return "violations";
    case Purpose::kVerification:
      return "verification";
  }
  return "";
}

std::string_view brackets_name(Brackets brackets) noexcept {
  return kBracketsNames[static_cast<std::size_t>(brackets)];
}

std::optional<Brackets> brackets_named(std::string_view name) noexcept {
  for (std::size_t i = 0; i < kBracketsNames.size(); ++i)
    if (kBracketsNames[i] == name) return static_cast<Brackets>(i);
  return std::nullopt;
}

std::string_view basis_name(Method m) noexcept {
  switch (m) {
    case Method::kNone:
      return "";
    case Method::kSimulated:
      return "simulated";
    case Method::kStop:
      return "stop";
    case Method::kLine:
      return "line";
    case Method::kBox:
      return "box";
  }
  return "";
}

void check(const Options& options) {
  if (options.initial_levels == 1)
    throw std::invalid_argument("adaptive search: initial_levels must be 0 (automatic) or at least 2");
  if (options.stride < 1) throw std::invalid_argument("adaptive search: stride must be at least 1");
  if (options.spread < 1) throw std::invalid_argument("adaptive search: spread must be at least 1");
}

Result search(const Lattice& lattice, Oracle& oracle, const Options& options) {
  for (const auto& l : lattice.levels)
    if (l.empty()) throw std::invalid_argument("adaptive search: a factor has no level");
  if (lattice.levels.size() > Lattice::kMaxAxes)
    throw std::invalid_argument(
        fmt::format("adaptive search: {} factors, at most {} supported", lattice.levels.size(), Lattice::kMaxAxes));
  if (lattice.ttc_axis >= lattice.levels.size() || lattice.friction_axis >= lattice.levels.size())
    throw std::invalid_argument("adaptive search: the TTC or friction axis is not a factor of the lattice");
  check(options);
  // The search works on kMaxAxes factors: the missing ones take a single level, which changes no
  // cell's index.
  Lattice padded = lattice;
  padded.levels.resize(Lattice::kMaxAxes, std::vector<double>{0.0});
  return detail::Search(padded, oracle, options).run();
}

}  // namespace emrm::campaign::adaptive
