// Boxes of lines refined: where their corners agree, what they predict for the lines between; else split.

#include <cmath>
#include <deque>

#include "adaptive_search.hpp"

namespace emrm::campaign::adaptive::detail {

namespace {

// A line's O/R labels as runs: their regions bottom to top, and the position where each run after
// the first starts.
struct Runs {
  std::vector<Region> regions;
  std::vector<std::uint32_t> starts;
};

Runs runs_of(const Line& line) {
  Runs r;
  for (std::size_t i = line.t_e; i < line.t_a; ++i) {
    if (!r.regions.empty() && r.regions.back() == line.labels[i]) continue;
    if (!r.regions.empty()) r.starts.push_back(line.position[i]);
    r.regions.push_back(line.labels[i]);
  }
  return r;
}

}  // namespace

// Whether two lines, settled by their own searches, answer `q` alike: both have a Y run or
// neither, with thresholds within the bracket; the same O/R label wherever both have one, or the
// same runs of labels changing within the bracket of each other.
bool Search::agree(std::size_t id_a, std::size_t id_b, Question q) const {
  const Line& a = lines_[id_a];
  const Line& b = lines_[id_b];
  if (q == Question::kThresholds) {
    const std::uint32_t pa = a.avoid_position(), pb = b.avoid_position();
    if ((pa == kNone) != (pb == kNone)) return false;
    return pa == kNone || (pa > pb ? pa - pb : pb - pa) <= options_.bracket;
  }
  std::size_t j = b.t_e;
  for (std::size_t i = a.t_e; i < a.t_a; ++i) {
    while (j < b.t_a && b.position[j] < a.position[i]) ++j;
    if (j < b.t_a && b.position[j] == a.position[i] && a.labels[i] != b.labels[j])
      return alike_runs({id_a, id_b}, Signature{}).has_value();
  }
  return true;
}

// The median end of the lines' early runs (a position), or kNone when none has one.
EarlyHint Search::median_early(const std::vector<std::size_t>& ids) const {
  const auto median = [&](auto&& position) {
    std::vector<std::uint32_t> ends;
    for (std::size_t id : ids)
      if (position(lines_[id]) != kNone) ends.push_back(position(lines_[id]));
    if (ends.empty()) return kNone;
    std::nth_element(ends.begin(), ends.begin() + static_cast<long>(ends.size() / 2), ends.end());
    return ends[ends.size() / 2];
  };
  return {median([](const Line& l) { return l.early_position(); }),
          median([](const Line& l) { return l.early_g_position(); })};
}

// The corners' common answer to `q`, or nothing when some two of them disagree.
std::optional<Signature> Search::signature(const Box& box, Question q) const {
  std::vector<std::size_t> corners;
  for_each_corner(box, [&](std::size_t id) { corners.push_back(id); });
  Signature s;
  s.box = box;
  if (q == Question::kThresholds) {
    s.early_hint = median_early(corners);
    s.early_hint.to_the_stop = std::all_of(corners.begin(), corners.end(), [&](std::size_t id) {
      const Line& line = lines_[id];
      return line.cells.empty() || (line.t_e > 0 && line.t_e >= line.t_g);
    });
    if (predict_brackets_ && options_.predict_early) {
      std::uint32_t low = kNone, high = 0;
      bool alike = true;
      for (std::size_t id : corners) {
        const Line& line = lines_[id];
        if (line.cells.empty()) continue;
        if (line.t_e == 0 || line.t_e >= line.t_g) alike = false;
        low = std::min(low, line.early_position());
        high = std::max(high, line.early_position());
      }
      if (alike && low != kNone && high - low <= spread_) s.early_predicted = true;
    }
  }
  bool with_y = false, without_y = false;
  for (std::size_t id : corners) {
    const Line& line = lines_[id];
    if (q == Question::kThresholds) {
      const std::uint32_t p = line.avoid_position();
      (p == kNone ? without_y : with_y) = true;
      if (p != kNone) {
        s.avoid_low = s.avoid_low == kNone ? p : std::min(s.avoid_low, p);
        s.avoid_high = std::max(s.avoid_high == kNone ? 0 : s.avoid_high, p);
      }
      continue;
    }
    for (std::size_t i = line.t_e; i < line.t_a; ++i) {
      const auto [it, inserted] = s.labels.emplace(line.position[i], line.labels[i]);
      if (!inserted && it->second != line.labels[i]) return alike_runs(corners, std::move(s));
    }
  }
  if (q == Question::kThresholds && with_y && without_y) {
    return std::nullopt;  // some corners avoid by Y first, others only where braking stops
  }
  if (q == Question::kThresholds && s.avoid_low != kNone && s.avoid_high - s.avoid_low > options_.bracket) {
    if (!predict_brackets_ || s.avoid_high - s.avoid_low > spread_) return std::nullopt;
  }
  return s;
}

// Corners whose labels differ at some level may still change alike: the same runs in the same
// order (corners without O/R cells aside), each change within the bracket of the others. The
// lines between then find each of their own changes within that bracket (none or one simulation
// each), as they do their avoidance thresholds.
std::optional<Signature> Search::alike_runs(const std::vector<std::size_t>& corners, Signature s) const {
  s.labels.clear();
  bool first = true;
  for (std::size_t id : corners) {
    const Line& line = lines_[id];
    if (line.t_a <= line.t_e) continue;
    const Runs r = runs_of(line);
    if (first) {
      s.runs = r.regions;
      for (std::uint32_t p : r.starts) s.changes.emplace_back(p, p);
      first = false;
      continue;
    }
    if (r.regions != s.runs) return std::nullopt;
    for (std::size_t j = 0; j < r.starts.size(); ++j) {
      s.changes[j].first = std::min(s.changes[j].first, r.starts[j]);
      s.changes[j].second = std::max(s.changes[j].second, r.starts[j]);
    }
  }
  if (first) return std::nullopt;
  for (std::size_t j = 0; j < s.changes.size(); ++j)
    if (s.changes[j].second - s.changes[j].first > options_.bracket ||
        (j > 0 && s.changes[j].first <= s.changes[j - 1].second))
      return std::nullopt;
  return s;
}

// A line between corners that change alike: each of its changes searched within their bracket.
void Search::bracket_labels(std::size_t id, const Signature& s) {
  Line& line = lines_[id];
  line.changes.clear();
  std::size_t from = line.t_e;
  for (std::size_t j = 0; j < s.changes.size(); ++j) {
    const std::size_t lo = std::clamp(index_at(line, s.changes[j].first), from, line.t_a);
    const std::size_t hi = std::clamp(index_at(line, s.changes[j].second), lo, line.t_a);
    if (four_factors_ && lo != hi) {
      from = predicted_change(line, id, s, j, lo, hi);
    } else {
      from = threshold(lo, hi, hi,
                       [&](std::size_t i) { return simulate(line.cells[i], Purpose::kLabelBrackets) != s.runs[j]; });
    }
    line.changes.push_back(from);
  }
}

// Where the corners' j-th change of labels predicts the line's, within [lo, hi]: interpolated
// from them, then moved where the line's own simulations say (above the last cell of the run
// before it, at the first of the run after it).
std::size_t Search::predicted_change(const Line& line, std::size_t id, const Signature& s, std::size_t j,
                                     std::size_t lo, std::size_t hi) const {
  const std::uint32_t at = interpolated(s.box, id, [&](const Line& corner) -> std::optional<std::uint32_t> {
    if (!corner.labels_sampled || corner.t_a <= corner.t_e) return std::nullopt;
    const Runs r = runs_of(corner);
    if (r.starts.size() != s.changes.size()) return std::nullopt;
    return r.starts[j];
  });
  std::size_t change = at == kNone ? hi : std::clamp(index_at(line, at), lo, hi);
  const auto label = [&](std::size_t i) { return result_.cells[line.cells[i]].region; };
  for (std::size_t i = lo; i < hi; ++i)
    if (is_simulated(line.cells[i]) && label(i) == s.runs[j]) change = std::max(change, i + 1);
  for (std::size_t i = change; i-- > lo;) {
    if (!is_simulated(line.cells[i])) continue;
    if (label(i) == s.runs[j]) break;
    if (label(i) == s.runs[j + 1]) change = i;
  }
  return change;
}

// A line between agreeing corners: its own early run (none, without a simulation, when no corner
// has one and brackets are predicted or physics says its lowest cell cannot stop) and stop
// boundary, and its avoidance threshold searched within the corners' bracket (no simulation when
// they agree exactly) or predicted.
void Search::bracket_thresholds(std::size_t id, const Signature& s) {
  Line& line = lines_[id];
  line.thresholds_known = true;
  if (line.cells.empty()) return;
  if (s.early_hint.end != kNone || (!predict_brackets_ && oracle_.stop(line.cells.front()) != StopCall::kCannotStop)) {
    EarlyHint hint = s.early_hint;
    if (hint.g_end != kNone) hint.g_end = predicted(s.box, id, &Line::early_g_end);
    if (s.early_predicted) hint.predicted_end = predicted(s.box, id, &Line::early_position);
    early_run(line, Purpose::kThresholdBrackets, hint);
  }
  line.stop_hint = predicted(s.box, id, &Line::stop_start);
  stop_threshold(line, Purpose::kThresholdBrackets);
  look_for_gap(line, s.avoid_low, Purpose::kThresholdBrackets);
  if (s.avoid_low == kNone) {
    line.t_a = line.t_g;
    return;
  }
  const auto index_of = [&](std::uint32_t position) {
    return std::clamp(index_at(line, position), line.t_e, line.t_g);
  };
  const std::size_t lo = index_of(s.avoid_low), hi = index_of(s.avoid_high);
  const std::uint32_t predicted_start = predicted(s.box, id, &Line::avoid_start);
  const std::size_t guess = predicted_start == kNone ? hi : std::clamp(index_at(line, predicted_start), lo, hi);
  if (predict_brackets_ && lo != hi) {
    line.t_a = guess;
    line.predicted_lo = lo;
    line.predicted_hi = hi + 1;
    settle_prediction(line);
    return;
  }
  line.t_a = lo == hi ? lo : threshold_from_above(lo, hi, guess, [&](std::size_t i) {
    return avoidable(simulate(line.cells[i], Purpose::kThresholdBrackets));
  });
}

// A predicted avoidance threshold moved where the line's own simulations within its bracket put
// it: above the highest that cannot avoid, else at the lowest that avoids below it. Cells that
// join the unavoidable part take the label of the simulated cell they join.
void Search::settle_prediction(Line& line) {
  if (line.predicted_hi == 0) return;
  std::size_t t = line.t_a;
  for (std::size_t i = line.predicted_lo; i < std::min(line.predicted_hi, line.t_g); ++i) {
    if (!is_simulated(line.cells[i])) continue;
    if (!avoidable(result_.cells[line.cells[i]].region)) t = std::max(t, i + 1);
  }
  for (std::size_t i = t; i-- > line.predicted_lo;) {
    if (!is_simulated(line.cells[i])) continue;
    if (!avoidable(result_.cells[line.cells[i]].region)) break;
    t = i;
  }
  if (t == line.t_a) return;
  if (line.labels_known && !line.labels.empty()) {
    const Region fill = t > line.t_a ? result_.cells[line.cells[t - 1]].region : Region::kR;
    line.labels.resize(std::max(t, line.t_e), fill);
  }
  line.t_a = t;
}

// The label the corners give the level nearest `position` (the lower on a tie).
std::optional<Region> Search::nearest_label(const Signature& s, std::uint32_t position) {
  if (s.labels.empty()) return std::nullopt;
  auto it = s.labels.lower_bound(position);
  if (it == s.labels.end() ||
      (it->first != position && it != s.labels.begin() && position - std::prev(it)->first <= it->first - position))
    it = std::prev(it);
  return it->second;
}

// A line between agreeing corners takes their labels; false when they give none, or when a cell
// the line simulated for its thresholds says otherwise.
bool Search::infer_labels(Line& line, const Signature& s) {
  std::vector<Region> labels(line.t_a, Region::kR);
  for (std::size_t i = line.t_e; i < line.t_a; ++i) {
    std::optional<Region> label;
    if (s.runs.empty())
      label = nearest_label(s, line.position[i]);
    else
      label = s.runs[static_cast<std::size_t>(std::upper_bound(line.changes.begin(), line.changes.end(), i) -
                                              line.changes.begin())];
    if (!label) return false;
    labels[i] = *label;
    if (is_simulated(line.cells[i]) && result_.cells[line.cells[i]].region != labels[i]) return false;
  }
  line.labels = std::move(labels);
  line.labels_known = true;
  line.label_corners.clear();
  for_each_corner(s.box, [&](std::size_t id) { line.label_corners.push_back(static_cast<std::uint32_t>(id)); });
  return true;
}

// Refines boxes of lines for one question: their corners answer it by their own simulations;
// boxes whose corners agree answer it for the lines between them, the others are split across
// the factors the corners disagree across.
void Search::refine(Question q) {
  std::vector<Box> pending = initial_boxes(initial_levels(q));
  // The lines between the agreeing corners of one round search their thresholds beside the next
  // round's corners: the two sets of lines are disjoint (the next corners lie in boxes that
  // disagreed), and nothing of the next round waits for them, so no worker idles between.
  std::deque<Signature> signatures_kept;
  std::vector<std::pair<std::size_t, const Signature*>> brackets;
  while (!pending.empty()) {
    ++result_.rounds;
    std::sort(pending.begin(), pending.end());
    pending.erase(std::unique(pending.begin(), pending.end(),
                              [](const Box& a, const Box& b) { return a.lo == b.lo && a.hi == b.hi; }),
                  pending.end());
    // 1. The corners, by their own search (and the previous round's brackets).
    std::vector<std::pair<std::size_t, const Signature*>> work;
    std::vector<char> queued(lines_.size(), 0);
    for (const Box& box : pending)
      for_each_corner(box, [&](std::size_t id) {
        Line& line = lines_[id];
        const bool done = q == Question::kThresholds ? line.thresholds_searched : line.labels_sampled;
        if (done || queued[id]) return;
        queued[id] = 1;
        if (q == Question::kThresholds) {
          if (box.parent) {
            line.hint = predicted(*box.parent, id, &Line::avoid_start);
            line.stop_hint = predicted(*box.parent, id, &Line::stop_start);
          }
          line.early_hint = box.early_hint;
        }
        work.emplace_back(id, nullptr);
      });
    work.insert(work.end(), brackets.begin(), brackets.end());
    brackets.clear();
    run(work, q);
    // 2. Which boxes agree; the lines inside a box that disagrees are left to its parts.
    std::vector<std::optional<Signature>> signatures(pending.size());
    std::vector<char> blocked(lines_.size(), 0);
    for (std::size_t b = 0; b < pending.size(); ++b) {
      signatures[b] = signature(pending[b], q);
      if (!signatures[b]) for_each_line(pending[b], [&](std::size_t id) { blocked[id] = 1; });
    }
    std::vector<std::vector<std::size_t>> owned(pending.size());
    std::vector<char> taken(lines_.size(), 0);
    for (std::size_t b = 0; b < pending.size(); ++b) {
      if (!signatures[b]) continue;
      for_each_line(pending[b], [&](std::size_t id) {
        if (known(lines_[id], q) || blocked[id] || taken[id]) return;
        taken[id] = 1;
        owned[b].push_back(id);
      });
    }
    // 3. Their lines answered from the corners: thresholds with the next round (they may
    // simulate), labels now and in order (they do not).
    std::vector<Box> next;
    if (q == Question::kThresholds) {
      for (std::size_t b = 0; b < pending.size(); ++b) {
        if (owned[b].empty()) continue;
        const Signature* kept = &signatures_kept.emplace_back(*signatures[b]);
        for (std::size_t id : owned[b]) {
          brackets.emplace_back(id, kept);
          lines_[id].thresholds_known = true;  // by the time anything reads it
          auto& sources = lines_[id].threshold_corners;
          for_each_corner(pending[b], [&](std::size_t c) { sources.push_back(static_cast<std::uint32_t>(c)); });
        }
      }
    } else {
      std::vector<std::pair<std::size_t, const Signature*>> changes;
      for (std::size_t b = 0; b < pending.size(); ++b)
        if (signatures[b] && !signatures[b]->runs.empty())
          for (std::size_t id : owned[b]) changes.emplace_back(id, &*signatures[b]);
      parallel(changes, [&](const std::pair<std::size_t, const Signature*>& w) { bracket_labels(w.first, *w.second); });
      for (std::size_t b = 0; b < pending.size(); ++b) {
        if (!signatures[b]) continue;
        bool ok = true;
        for (std::size_t id : owned[b]) ok = ok && infer_labels(lines_[id], *signatures[b]);
        if (ok) continue;
        for (std::size_t id : owned[b]) lines_[id].labels_known = false;
        signatures[b].reset();
      }
    }
    for (std::size_t b = 0; b < pending.size(); ++b)
      if (!signatures[b]) split(pending[b], q, next);
    pending.swap(next);
  }
  run(brackets, q);
}

// One stage's lines side by side: corners (no signature) search or sample their own, the
// others search their thresholds within their corners' bracket.
void Search::run(const std::vector<std::pair<std::size_t, const Signature*>>& work, Question q) {
  parallel(work, [&](const std::pair<std::size_t, const Signature*>& w) {
    if (w.second != nullptr)
      bracket_thresholds(w.first, *w.second);
    else if (q == Question::kThresholds)
      search_thresholds(w.first);
    else
      sample_labels(w.first);
  });
}

// What the searched corners of `box` predict for the line `id` within it: their `start` (a
// position along the line, as Line::avoid_start), interpolated multilinearly in the lines'
// positions. The thresholds move smoothly with speed, friction and passage, so where a box's
// corners are too far apart to bracket the lines between, a new corner's search starts where
// they point (two simulations when it is right) rather than at their median. kNone when no
// corner has cells.
std::uint32_t Search::predicted(const Range& box, std::size_t id, std::uint32_t (Line::*start)() const) const {
  return interpolated(box, id, [&](const Line& corner) -> std::optional<std::uint32_t> {
    if (corner.cells.empty() || !corner.thresholds_searched) return std::nullopt;
    return (corner.*start)();
  });
}

// A position the corners of `box` give (nothing from a corner that has none), interpolated
// multilinearly at the line `id`'s place in the box; kNone when no corner gives one.
template <typename Value>
std::uint32_t Search::interpolated(const Range& box, std::size_t id, Value&& value) const {
  const auto p = line_position(id);
  double sum = 0.0, weight = 0.0;
  for_each_corner(box, [&](std::size_t c) {
    const std::optional<std::uint32_t> v = value(lines_[c]);
    if (!v) return;
    const auto q = line_position(c);
    double w = 1.0;
    for (std::size_t a = 0; a < 4; ++a) {
      if (box.hi[a] == box.lo[a]) continue;
      const double f = static_cast<double>(p[a] - box.lo[a]) / static_cast<double>(box.hi[a] - box.lo[a]);
      w *= q[a] == box.hi[a] ? f : 1.0 - f;
    }
    sum += w * *v;
    weight += w;
  });
  return weight > 0.0 ? static_cast<std::uint32_t>(std::lround(sum / weight)) : kNone;
}

// Splits a box whose corners disagree across the factors they disagree across: in two halves
// when there are lines between the corners, into its two faces when there are none. Factors
// along which every pair of corners agrees stay whole, so a boundary across one factor does not
// refine the others. Corners that disagree only diagonally split every factor.
void Search::split(const Box& box, Question q, std::vector<Box>& out) const {
  std::array<bool, 4> across{};
  bool any = false;
  for (std::size_t a = 0; a < 4; ++a) {
    if (box.hi[a] == box.lo[a]) continue;
    for_each_corner(box, [&](std::size_t id) {
      auto p = line_position(id);
      if (across[a] || p[a] != box.lo[a]) return;
      p[a] = box.hi[a];
      across[a] = !agree(id, line_id(p), q);
    });
    any = any || across[a];
  }
  if (q == Question::kThresholds && four_factors_) {
    // From four factors on, only across the factor along which the corners' thresholds differ
    // most: split across every factor at once, a box of k factors gets up to 3^k - 2^k new corner
    // lines (65 for k = 4), most of them along factors the next split would not have needed.
    std::array<std::uint32_t, 4> worst{};
    for (std::size_t a = 0; a < 4; ++a) {
      if (!across[a]) continue;
      for_each_corner(box, [&](std::size_t id) {
        auto p = line_position(id);
        if (p[a] != box.lo[a]) return;
        p[a] = box.hi[a];
        const Line& x = lines_[id];
        const Line& y = lines_[line_id(p)];
        if (x.cells.empty() != y.cells.empty()) {
          worst[a] = kNone;  // feasible on one side only: the widest disagreement
          return;
        }
        if (x.cells.empty()) return;
        const std::uint32_t u = x.avoid_start(), v = y.avoid_start();
        worst[a] = std::max(worst[a], u > v ? u - v : v - u);
      });
    }
    std::size_t best = 4;  // the first of the widest among the factors they disagree across
    for (std::size_t a = 0; a < 4; ++a)
      if (across[a] && (best == 4 || worst[a] > worst[best])) best = a;
    for (std::size_t a = 0; a < 4; ++a) across[a] = across[a] && a == best;
  }
  std::array<std::vector<std::pair<std::uint32_t, std::uint32_t>>, 4> parts;
  bool divides = false;
  for (std::size_t a = 0; a < 4; ++a) {
    const std::uint32_t lo = box.lo[a], hi = box.hi[a];
    if (hi == lo || (any && !across[a])) {
      parts[a] = {{lo, hi}};
    } else if (hi - lo >= 2) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      parts[a] = {{lo, mid}, {mid, hi}};
      divides = true;
    } else {
      parts[a] = {{lo, lo}, {hi, hi}};
      divides = true;
    }
  }
  if (!divides) return;
  std::vector<std::size_t> corners;
  for_each_corner(box, [&](std::size_t id) { corners.push_back(id); });
  const EarlyHint early_hint = median_early(corners);
  for (const auto& h0 : parts[0])
    for (const auto& h1 : parts[1])
      for (const auto& h2 : parts[2])
        for (const auto& h3 : parts[3])
          out.push_back(Box{{{h0.first, h1.first, h2.first, h3.first}, {h0.second, h1.second, h2.second, h3.second}},
                            Range(box),
                            early_hint});
}

}  // namespace emrm::campaign::adaptive::detail
