// A line's thresholds: the stop boundary, the early run and the avoidance threshold, searched along it.

#include "adaptive_search.hpp"

namespace emrm::campaign::adaptive::detail {

// The first index of the top run of cells that physics says stop in time.
std::size_t Search::analytic_top(const Line& line) const {
  std::size_t hi = line.cells.size();
  while (hi > 0 && oracle_.stop(line.cells[hi - 1]) == StopCall::kStops) --hi;
  return hi;
}

// The stop boundary: the top run of cells physics says stop in time, extended downwards by
// simulation (galloping, then bisecting) over the cells it cannot settle, down to the highest
// cell below them that physics says cannot stop, and above the early run's first cell that
// cannot avoid (no G run of the stop reaches below either). Sets line.t_g.
void Search::stop_threshold(Line& line, Purpose purpose) {
  const auto g = [&](std::size_t i) {
    return oracle_.stop(line.cells[i]) == StopCall::kUnknown && simulate(line.cells[i], purpose) == Region::kG;
  };
  const std::size_t hi = analytic_top(line);
  std::size_t lo = hi;
  while (lo > 0 && oracle_.stop(line.cells[lo - 1]) == StopCall::kUnknown) --lo;
  if (line.t_e > 0) lo = std::max(lo, std::min(hi, line.t_e < hi ? line.t_e + 1 : line.t_eg + 1));
  const std::size_t guess = line.stop_hint == kNone ? hi : std::clamp(index_at(line, line.stop_hint), lo, hi);
  line.t_g = threshold(lo, hi, guess, g);
  if (line.t_e >= line.t_g) {  // no cell below the stop's run cannot avoid: the early run meets it
    line.t_e = line.t_g;
    line.t_eg = std::min(line.t_eg, line.t_g);
  }
}

// Whether the line may start with an early run: along TTC, where arriving sooner can help.
bool Search::may_pass_early(const Line& line) const {
  return monotone_ == lattice_.ttc_axis && !line.cells.empty() && oracle_.passes_early(line.cells.front());
}

// The early run (docs/adaptive.md): from the line's lowest cell, where the car passes in front of
// a truck still on its way, up to its first cell that cannot avoid, walking up from the bottom
// in steps of at most `stride` (not from the corners' ends: the cell below a guess that lands in
// the avoiding run above the gap avoids too), then bisecting; and the G run within it, which
// ends at the latest below the first cell that physics says cannot stop, from the corners' end
// (two simulations when right). Sets t_eg and t_e (both 0 without an early run).
void Search::early_run(Line& line, Purpose purpose, EarlyHint hint) {
  line.t_eg = line.t_e = 0;
  line.early_searched = true;
  if (!may_pass_early(line)) return;
  const std::size_t top = analytic_top(line);
  const auto region = [&](std::size_t i) { return simulate(line.cells[i], purpose); };
  const auto guess = [&](std::uint32_t position, std::size_t hi) {
    return position == kNone ? 0 : std::min(index_at(line, position), hi);
  };
  if (hint.predicted_end != kNone && predicted_early_run(line, hint, top, purpose)) return;
  // Between corners whose early runs all reach the stop's run, no gap is looked for: the line's
  // early run is taken to reach it too (its G part is still searched, and what it simulates is
  // checked against that).
  line.t_e = hint.to_the_stop ? top
                              : threshold_from_below(
                                    top, [&](std::size_t i) { return !avoidable(region(i)); }, options_.stride);
  std::size_t g_end = 0;
  while (g_end < line.t_e && oracle_.stop(line.cells[g_end]) != StopCall::kCannotStop) ++g_end;
  // Where the early run reaches the stop's run and no cell that cannot stop lies between, the
  // G test is not monotone up to g_end: early G, then Y, then the stop's G. A guess that lands in
  // the stop's G looks like the early run's, so the G part is walked up from the bottom instead
  // (steps of at most the stride, as the early run's end is).
  const bool unbounded = hint.to_the_stop && g_end == line.t_e;
  line.t_eg = threshold(
      0, g_end, unbounded ? 0 : guess(hint.g_end, g_end), [&](std::size_t i) { return region(i) != Region::kG; },
      options_.stride);
}

// Between corners whose early runs end alike below the stop's run: the G part searched exactly
// below the first cell that physics says cannot stop (G cannot reach past it, and the stop's G run
// lies above it), the end of the avoiding part predicted from the corners, unless the first cell
// above the G part already cannot avoid. False (nothing decided) when no cell below the top
// cannot stop: then G is searched after the walk, as on a corner.
bool Search::predicted_early_run(Line& line, const EarlyHint& hint, std::size_t top, Purpose purpose) {
  std::size_t cannot_stop = 0;
  while (cannot_stop < top && oracle_.stop(line.cells[cannot_stop]) != StopCall::kCannotStop) ++cannot_stop;
  if (cannot_stop >= top) return false;
  const auto region = [&](std::size_t i) { return simulate(line.cells[i], purpose); };
  const std::size_t guess = hint.g_end == kNone ? 0 : std::min(index_at(line, hint.g_end), cannot_stop);
  line.t_eg = threshold(0, cannot_stop, guess, [&](std::size_t i) { return region(i) != Region::kG; });
  if (line.t_eg < cannot_stop && !avoidable(region(line.t_eg))) {
    line.t_e = line.t_eg;
    return true;
  }
  line.t_e = std::clamp(index_at(line, hint.predicted_end), line.t_eg + (line.t_eg < cannot_stop ? 1 : 0), top);
  line.early_predicted = true;
  return true;
}

// A predicted early run's end moved where the line's own simulations put it: down to the first
// that cannot avoid, up past the last that avoids below the first that cannot. Cells that join
// the part below the avoidance threshold take the label of the simulated cell they join.
void Search::settle_early(Line& line) {
  if (!line.early_predicted) return;
  std::size_t t = line.t_e;
  for (std::size_t i = line.t_eg; i < line.t_e; ++i)
    if (is_simulated(line.cells[i]) && !avoidable(result_.cells[line.cells[i]].region)) {
      t = i;
      break;
    }
  if (t == line.t_e)
    for (std::size_t i = line.t_e; i < line.t_a && i < line.cells.size(); ++i) {
      if (!is_simulated(line.cells[i])) continue;
      if (!avoidable(result_.cells[line.cells[i]].region)) break;
      t = i + 1;
    }
  if (t == line.t_e) return;
  if (t < line.t_e && line.labels_known && line.labels.size() >= line.t_e)
    for (std::size_t i = t; i < line.t_e; ++i) line.labels[i] = result_.cells[line.cells[t]].region;
  line.t_e = std::min(t, line.t_a);
}

// An early run that met the stop's run may have walked over a gap narrower than the stride: the
// cell below the corners' avoidance threshold, when it cannot avoid, is in such a gap, and the
// early run ends below it. One simulation when there is no gap.
void Search::look_for_gap(Line& line, std::uint32_t avoid_hint, Purpose purpose) {
  if (line.t_e == 0 || line.t_e < line.t_g || avoid_hint == kNone) return;
  const std::size_t at = index_at(line, avoid_hint);
  const auto cannot = [&](std::size_t i) { return !avoidable(simulate(line.cells[i], purpose)); };
  if (at == 0 || at >= line.t_g || !cannot(at - 1)) return;
  line.t_e = threshold_from_below(at - 1, cannot, options_.stride);
  line.t_eg = std::min(line.t_eg, line.t_e);
}

// The avoidance threshold between the early run and the stop boundary, from the line's hint
// when it has one.
std::size_t Search::avoidance_threshold(const Line& line) {
  const std::size_t guess = line.hint == kNone ? line.t_g : std::clamp(index_at(line, line.hint), line.t_e, line.t_g);
  return threshold_from_above(line.t_e, line.t_g, guess, [&](std::size_t i) {
    return avoidable(simulate(line.cells[i], Purpose::kThresholdCorners));
  });
}

// A corner of a threshold box: its stop boundary and avoidance threshold by search.
void Search::search_thresholds(std::size_t id) {
  Line& line = lines_[id];
  line.thresholds_searched = line.thresholds_known = true;
  if (line.cells.empty()) return;
  early_run(line, Purpose::kThresholdCorners, line.early_hint);
  stop_threshold(line, Purpose::kThresholdCorners);
  look_for_gap(line, line.hint, Purpose::kThresholdCorners);
  line.t_a = avoidance_threshold(line);
}

// An avoidance threshold that the line's later simulations (its labels, a neighbour's search)
// contradict with no simulated cell between to break monotonicity, as a prediction or a bracket
// one level off does: searched again between the simulated cells that bound it (a few
// simulations instead of this line and its neighbours in full). Searched down from the lowest
// cell below it that avoids, above the highest simulated one below that does not; up from the
// highest cell above it that does not avoid, below the lowest simulated one above that avoids.
void Search::research_threshold(Line& line) {
  if (line.full || line.t_a <= line.t_e || line.t_a > line.t_g) return;
  const auto simulated_avoids = [&](std::size_t i) -> std::optional<bool> {
    if (!is_simulated(line.cells[i])) return std::nullopt;
    return avoidable(result_.cells[line.cells[i]].region);
  };
  const auto avoids = [&](std::size_t i) { return avoidable(simulate(line.cells[i], Purpose::kViolations)); };
  std::size_t lowest_avoiding = line.t_a, floor = line.t_a;
  for (std::size_t i = line.t_a; i-- > line.t_e;) {
    const auto a = simulated_avoids(i);
    if (!a) continue;
    if (!*a) {
      floor = i + 1;
      break;
    }
    lowest_avoiding = i;
  }
  std::size_t t = line.t_a;
  if (lowest_avoiding < line.t_a && floor <= lowest_avoiding) {
    t = threshold_from_above(floor, lowest_avoiding, lowest_avoiding, avoids);
  } else if (line.t_a < line.t_g) {
    std::size_t highest_failing = line.t_a, ceiling = line.t_g;
    bool found_failing = false;
    for (std::size_t i = line.t_a; i < line.t_g; ++i) {
      const auto a = simulated_avoids(i);
      if (!a) continue;
      if (*a) {
        ceiling = i;
        break;
      }
      highest_failing = i;
      found_failing = true;
    }
    if (!found_failing) return;
    t = threshold_from_above(highest_failing + 1, ceiling, highest_failing + 1, avoids);
  }
  if (t == line.t_a) return;
  if (line.labels_known && !line.labels.empty()) {
    Region fill = Region::kR;  // of the nearest simulated cell that cannot avoid below the new threshold
    for (std::size_t i = t; i-- > line.t_e;)
      if (simulated_avoids(i) == std::optional<bool>(false)) {
        fill = result_.cells[line.cells[i]].region;
        break;
      }
    line.labels.resize(std::max(t, line.t_e), fill);
  }
  line.t_a = t;
}

}  // namespace emrm::campaign::adaptive::detail
