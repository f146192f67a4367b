// A line's O/R labels below its avoidance threshold, sampled along it and bisected where they change.

#include "adaptive_search.hpp"

namespace emrm::campaign::adaptive::detail {

// A corner of a label box: the O/R labels below the avoidance threshold sampled every `stride`
// cells, with every change bisected down to adjacent cells, the cells between equal samples
// taking their label.
void Search::sample_labels(std::size_t id) {
  Line& line = lines_[id];
  line.labels_sampled = line.labels_known = true;
  if (line.predicted_hi != 0) {  // a predicted threshold searched: the cell below it is sampled anyway
    line.t_a = threshold_from_above(line.predicted_lo, line.predicted_hi - 1, line.t_a, [&](std::size_t i) {
      return avoidable(simulate(line.cells[i], Purpose::kLabels));
    });
    line.predicted_hi = 0;
  }
  if (line.t_a > line.t_e) {
    std::vector<std::uint32_t> samples{line.cells[line.t_a - 1]};
    for (std::size_t i = line.t_a; i > line.t_e;) {
      i = i > line.t_e + options_.stride ? i - options_.stride : line.t_e;
      samples.push_back(line.cells[i]);
    }
    std::erase_if(samples, [&](std::uint32_t cell) { return !is_simulated(cell) && nothing_to_mitigate(cell); });
    simulate_all(samples, Purpose::kLabels);
    bisect_changes(line, line.t_e, line.t_a, Purpose::kLabels);
  }
  line.labels.assign(line.t_a, Region::kR);
  std::size_t below = line.t_e;
  for (std::size_t i = line.t_e; i < line.t_a; ++i) {
    if (label(line.cells[i])) below = i;
    line.labels[i] = label(line.cells[below]).value_or(Region::kR);
  }
}

// Whether an unavoidable cell is R by the oracle's rule (nothing to mitigate), asked once a cell.
bool Search::nothing_to_mitigate(std::uint32_t cell) {
  std::int8_t& known = nothing_to_mitigate_[cell];
  if (known < 0) known = oracle_.nothing_to_mitigate(cell) ? 1 : 0;
  return known == 1;
}

// An unavoidable cell's label when something gives it: its simulation, else the rule.
std::optional<Region> Search::label(std::uint32_t cell) {
  if (is_simulated(cell)) return result_.cells[cell].region;
  if (nothing_to_mitigate(cell)) return Region::kR;
  return std::nullopt;
}

// Between two cells of [begin, end) with different known labels (simulated, or R by the rule),
// simulations halve the gap until the two are neighbours; the midpoints of one pass are simulated
// together.
void Search::bisect_changes(const Line& line, std::size_t begin, std::size_t end, Purpose purpose) {
  std::vector<std::uint32_t> midpoints{0};
  while (!midpoints.empty()) {
    midpoints.clear();
    std::size_t previous = end;
    std::optional<Region> before;
    for (std::size_t i = begin; i < end; ++i) {
      const std::optional<Region> here = label(line.cells[i]);
      if (!here) continue;
      if (previous != end && i - previous > 1 && *here != *before)
        midpoints.push_back(line.cells[previous + (i - previous) / 2]);
      previous = i;
      before = here;
    }
    simulate_all(midpoints, purpose);
  }
}

}  // namespace emrm::campaign::adaptive::detail
