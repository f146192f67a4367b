#include "emrm/campaign/adaptive.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

#include "emrm/sim/loss.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::campaign::adaptive {
namespace {

using sim::Region;

constexpr std::size_t kAxes = 5;
constexpr std::size_t kTtc = 1;
constexpr std::size_t kMu = 2;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxFrom = 16;

bool avoidable(Region r) noexcept { return r == Region::kG || r == Region::kY; }

// A guess of where a line's early run ends and where its G part ends (positions; kNone: no guess,
// or no early run on the lines it came from).
struct EarlyHint {
  std::uint32_t end = kNone, g_end = kNone;
  bool to_the_stop = false;  ///< every corner's early run reaches the stop's run (no cell between cannot avoid)
  /// Where the line's early run is predicted to end (a position; kNone: it is searched), when the
  /// corners' early runs all end below the stop's run within the bracket of one another.
  std::uint32_t predicted_end = kNone;
};

// A line: the feasible cells that differ only in the monotone factor, in ascending order of it.
// Two questions settle it, each answered by its own simulations or inferred from the lines at the
// corners of a box: where avoidance starts (the thresholds), and the O/R labels below that.
struct Line {
  std::vector<std::uint32_t> cells;
  std::vector<std::uint32_t> position;  ///< of each cell along the monotone axis (sorted level)
  bool thresholds_searched = false;  ///< by a search of its own (a corner of a threshold box)
  bool thresholds_known = false;     ///< searched, or found within a uniform box's bracket
  bool labels_sampled = false;       ///< O/R labels by samples of its own (a corner of a label box)
  bool labels_known = false;         ///< sampled, or inferred from a uniform box's corners
  bool full = false;      ///< every cell that the stop boundary does not settle simulated
  bool violated = false;  ///< simulations contradicted monotonicity
  bool early_searched = false;  ///< its early run by simulations of its own (else from its corners)
  bool early_predicted = false;  ///< its early run's end predicted from its corners (its G part searched)
  std::uint32_t hint = kNone;       ///< a guess of the avoidance threshold's position (from a parent box)
  std::uint32_t stop_hint = kNone;  ///< and of the stop boundary's
  EarlyHint early_hint;  ///< from a parent box
  // The line in runs, bottom to top: [0, t_eg) G and [t_eg, t_e) Y passing in front of a truck
  // still on its way (the early run; empty unless the oracle says arriving sooner can help),
  // [t_e, t_a) O or R, [t_a, t_g) Y, [t_g, size) G.
  std::size_t t_eg = 0;  ///< end of the early G run
  std::size_t t_e = 0;   ///< end of the early avoidable run
  std::size_t t_g = 0;  ///< first index of the G run at the top
  std::size_t t_a = 0;  ///< first index of the avoidable run (G or Y) at the top
  std::vector<Region> labels;  ///< O/R of the cells in [t_e, t_a) (by index; simulated or inferred)
  std::vector<std::size_t> changes;  ///< where its runs of labels start, when found within its corners' brackets
  std::vector<std::uint32_t> threshold_corners;  ///< the lines its bracket came from (when not searched)
  std::vector<std::uint32_t> label_corners;      ///< the lines its labels came from (when not sampled)
  /// Its avoidance threshold was predicted from its corners within [lo, hi) of their bracket, not
  /// searched (Options::brackets); hi == 0: searched, or found without a bracket.
  std::size_t predicted_lo = 0, predicted_hi = 0;

  /// Position of the avoidance threshold when the line has Y cells; kNone when avoidance starts with G.
  [[nodiscard]] std::uint32_t avoid_position() const noexcept { return t_a < t_g ? position[t_a] : kNone; }
  /// Position of the first cell of the avoiding run at the top (of the G run when there is no Y).
  [[nodiscard]] std::uint32_t avoid_start() const noexcept { return position_of(t_a); }
  /// Position of the first cell above the early run's G part (the line's first without one).
  [[nodiscard]] std::uint32_t early_g_end() const noexcept { return position_of(t_eg); }
  /// Position of the first cell of the G run at the top.
  [[nodiscard]] std::uint32_t stop_start() const noexcept { return position_of(t_g); }
  /// Position of the first cell above the early run; kNone without an early run.
  [[nodiscard]] std::uint32_t early_position() const noexcept { return t_e == 0 ? kNone : position_of(t_e); }
  /// Position of the first cell above the early run's G part; kNone without one.
  [[nodiscard]] std::uint32_t early_g_position() const noexcept { return t_eg == 0 ? kNone : position_of(t_eg); }
  [[nodiscard]] std::uint32_t position_of(std::size_t i) const noexcept {
    return i < position.size() ? position[i] : position.back() + 1;
  }
};

// Lines by their place: per line axis, a range of sorted positions [lo, hi].
struct Range {
  std::array<std::uint32_t, 4> lo{}, hi{};
};

// A box of lines; and the range it was split from, whose corners predict the thresholds of its new
// corners (none for the first lattice's).
struct Box : Range {
  std::optional<Range> parent;
  EarlyHint early_hint;
  bool operator<(const Box& o) const noexcept { return std::tie(lo, hi) < std::tie(o.lo, o.hi); }
};

// What agreeing corners say of the lines between them.
struct Signature {
  Range box;  ///< where the corners are
  std::uint32_t avoid_low = kNone, avoid_high = kNone;  ///< the corners' thresholds span [low, high]
  EarlyHint early_hint;  ///< the median ends of the corners' early runs
  bool early_predicted = false;  ///< the corners' early runs end alike below the stop's run
  std::map<std::uint32_t, Region> labels;                ///< O/R by level, below the thresholds
  // Or, when the corners' labels differ at some level: the runs of labels they all have, bottom to
  // top, and the span of the positions where each run after the first starts.
  std::vector<Region> runs;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> changes;
};

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

// The two refinements: of the avoidance thresholds, then of the O/R labels below them.
enum class Question { kThresholds, kLabels };

class Search {
 public:
  Search(const Lattice& lattice, Oracle& oracle, const Options& options)
      : lattice_(lattice), oracle_(oracle), options_(options) {
    for (std::size_t k = 0; k < kAxes; ++k) {
      auto& order = order_[k];
      order.resize(lattice.levels[k].size());
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return lattice.levels[k][a] < lattice.levels[k][b]; });
    }
    monotone_ = lattice.levels[kTtc].size() > 1 ? kTtc : (lattice.levels[kMu].size() > 1 ? kMu : kTtc);
    for (std::size_t k = 0; k < kAxes; ++k)
      if (k != monotone_) line_axes_.push_back(k);
    const auto varying = std::count_if(line_axes_.begin(), line_axes_.end(),
                                       [&](std::size_t k) { return lattice.levels[k].size() > 1; });
    predict_brackets_ =
        options.brackets == Brackets::kPredict || (options.brackets == Brackets::kAuto && varying >= 2);
    four_factors_ = predict_brackets_ && varying >= 3;
    spread_ = predict_brackets_ ? std::max(options.bracket, options.spread) : options.bracket;
    result_.cells.resize(lattice.size());
    nothing_to_mitigate_.assign(lattice.size(), -1);
    build_lines();
  }

  Result run() {
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

 private:
  // --- geometry ---------------------------------------------------------------------------

  [[nodiscard]] std::uint32_t extent(std::size_t a) const noexcept {
    return static_cast<std::uint32_t>(lattice_.levels[line_axes_[a]].size());
  }

  [[nodiscard]] std::size_t line_id(const std::array<std::uint32_t, 4>& p) const noexcept {
    std::size_t id = 0;
    for (std::size_t a = 0; a < 4; ++a) id = id * extent(a) + p[a];
    return id;
  }

  void build_lines() {
    std::size_t count = 1;
    for (std::size_t a = 0; a < 4; ++a) count *= extent(a);
    lines_.resize(count);
    result_.lines = count;
    std::array<std::uint32_t, 4> p{};
    for (std::size_t id = 0; id < count; ++id) {
      Line& line = lines_[id];
      std::array<std::size_t, kAxes> level{};
      for (std::size_t a = 0; a < 4; ++a) level[line_axes_[a]] = order_[line_axes_[a]][p[a]];
      for (std::uint32_t j = 0; j < lattice_.levels[monotone_].size(); ++j) {
        level[monotone_] = order_[monotone_][j];
        const std::size_t cell = lattice_.index(level);
        if (!oracle_.feasible(cell)) continue;
        line.cells.push_back(static_cast<std::uint32_t>(cell));
        line.position.push_back(j);
        ++result_.feasible;
      }
      for (std::size_t a = 4; a-- > 0;) {  // next position, the last line axis fastest
        if (++p[a] < extent(a)) break;
        p[a] = 0;
      }
    }
  }

  [[nodiscard]] std::array<std::uint32_t, 4> line_position(std::size_t id) const noexcept {
    std::array<std::uint32_t, 4> p{};
    for (std::size_t a = 4; a-- > 0;) {
      p[a] = static_cast<std::uint32_t>(id % extent(a));
      id /= extent(a);
    }
    return p;
  }

  // Lines searched per factor before refining, unless the options say: for thresholds 4 when the
  // lines vary in one factor, 3 when in more (the first lattice's share of the lines stays small);
  // for labels 2, the domain's corners, since a label boundary is refined across the factor it
  // crosses only.
  [[nodiscard]] std::size_t initial_levels(Question q) const noexcept {
    if (options_.initial_levels > 0) return options_.initial_levels;
    if (q == Question::kLabels) return 2;
    std::size_t varying = 0;
    for (std::size_t a = 0; a < 4; ++a) varying += extent(a) > 1;
    return varying <= 1 ? 4 : 3;
  }

  // Each factor sampled at about `initial_levels` positions, always its first and last.
  std::vector<Box> initial_boxes(std::size_t levels) const {
    std::array<std::vector<std::uint32_t>, 4> samples;
    for (std::size_t a = 0; a < 4; ++a) {
      const std::uint32_t n = extent(a);
      const std::uint32_t stride =
          n <= 1 ? 1 : std::max<std::uint32_t>(1, static_cast<std::uint32_t>((n - 1 + levels - 2) / (levels - 1)));
      for (std::uint32_t p = 0; p + 1 < n; p += stride) samples[a].push_back(p);
      samples[a].push_back(n - 1);
    }
    std::vector<Box> boxes;
    std::array<std::size_t, 4> k{};
    const auto intervals = [&](std::size_t a) { return std::max<std::size_t>(1, samples[a].size() - 1); };
    while (true) {
      Box box;
      for (std::size_t a = 0; a < 4; ++a) {
        box.lo[a] = samples[a][k[a]];
        box.hi[a] = samples[a].size() > 1 ? samples[a][k[a] + 1] : samples[a][0];
      }
      boxes.push_back(box);
      std::size_t a = 4;
      while (a-- > 0) {
        if (++k[a] < intervals(a)) break;
        k[a] = 0;
      }
      if (a == static_cast<std::size_t>(-1)) break;
    }
    return boxes;
  }

  template <typename Visit>
  void for_each_corner(const Range& box, Visit&& visit) const {
    std::array<std::uint32_t, 4> p{};
    for (unsigned mask = 0; mask < 16; ++mask) {
      bool duplicate = false;
      for (std::size_t a = 0; a < 4; ++a) {
        const bool high = (mask >> a) & 1U;
        if (high && box.lo[a] == box.hi[a]) duplicate = true;
        p[a] = high ? box.hi[a] : box.lo[a];
      }
      if (!duplicate) visit(line_id(p));
    }
  }

  template <typename Visit>
  void for_each_line(const Range& box, Visit&& visit) const {
    std::array<std::uint32_t, 4> p = box.lo;
    while (true) {
      visit(line_id(p));
      std::size_t a = 4;
      while (a-- > 0) {
        if (++p[a] <= box.hi[a]) break;
        p[a] = box.lo[a];
      }
      if (a == static_cast<std::size_t>(-1)) return;
    }
  }

  // --- one line -----------------------------------------------------------------------------

  Region simulate(std::uint32_t cell, Purpose purpose) {
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

  [[nodiscard]] bool is_simulated(std::uint32_t cell) const noexcept {
    return result_.cells[cell].method == Method::kSimulated;
  }

  // The first index of the top run of cells that physics says stop in time.
  [[nodiscard]] std::size_t analytic_top(const Line& line) const {
    std::size_t hi = line.cells.size();
    while (hi > 0 && oracle_.stop(line.cells[hi - 1]) == StopCall::kStops) --hi;
    return hi;
  }

  // The index of the first cell at or above a position (the line's size when none is).
  [[nodiscard]] static std::size_t index_at(const Line& line, std::uint32_t position) {
    return static_cast<std::size_t>(std::lower_bound(line.position.begin(), line.position.end(), position) -
                                    line.position.begin());
  }

  // The stop boundary: the top run of cells physics says stop in time, extended downwards by
  // simulation (galloping, then bisecting) over the cells it cannot settle, down to the highest
  // cell below them that physics says cannot stop, and above the early run's first cell that
  // cannot avoid (no G run of the stop reaches below either). Sets line.t_g.
  void stop_threshold(Line& line, Purpose purpose) {
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
  [[nodiscard]] bool may_pass_early(const Line& line) const {
    return monotone_ == kTtc && !line.cells.empty() && oracle_.passes_early(line.cells.front());
  }

  // The early run (docs/adaptive.md): from the line's lowest cell, where the car passes in front of
  // a truck still on its way, up to its first cell that cannot avoid, walking up from the bottom
  // in steps of at most `stride` (not from the corners' ends: the cell below a guess that lands in
  // the avoiding run above the gap avoids too), then bisecting; and the G run within it, which
  // ends at the latest below the first cell that physics says cannot stop, from the corners' end
  // (two simulations when right). Sets t_eg and t_e (both 0 without an early run).
  void early_run(Line& line, Purpose purpose, EarlyHint hint) {
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
    line.t_e = hint.to_the_stop ? top : threshold_from_below(top, [&](std::size_t i) { return !avoidable(region(i)); }, options_.stride);
    std::size_t g_end = 0;
    while (g_end < line.t_e && oracle_.stop(line.cells[g_end]) != StopCall::kCannotStop) ++g_end;
    // Where the early run reaches the stop's run and no cell that cannot stop lies between, the
    // G test is not monotone up to g_end: early G, then Y, then the stop's G. A guess that lands in
    // the stop's G looks like the early run's, so the G part is walked up from the bottom instead
    // (steps of at most the stride, as the early run's end is).
    const bool unbounded = hint.to_the_stop && g_end == line.t_e;
    line.t_eg = threshold(0, g_end, unbounded ? 0 : guess(hint.g_end, g_end),
                          [&](std::size_t i) { return region(i) != Region::kG; }, options_.stride);
  }

  // Between corners whose early runs end alike below the stop's run: the G part searched exactly
  // below the first cell that physics says cannot stop (G cannot reach past it, and the stop's G run
  // lies above it), the end of the avoiding part predicted from the corners, unless the first cell
  // above the G part already cannot avoid. False (nothing decided) when no cell below the top
  // cannot stop: then G is searched after the walk, as on a corner.
  bool predicted_early_run(Line& line, const EarlyHint& hint, std::size_t top, Purpose purpose) {
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
  void settle_early(Line& line) {
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
  void look_for_gap(Line& line, std::uint32_t avoid_hint, Purpose purpose) {
    if (line.t_e == 0 || line.t_e < line.t_g || avoid_hint == kNone) return;
    const std::size_t at = index_at(line, avoid_hint);
    const auto cannot = [&](std::size_t i) { return !avoidable(simulate(line.cells[i], purpose)); };
    if (at == 0 || at >= line.t_g || !cannot(at - 1)) return;
    line.t_e = threshold_from_below(at - 1, cannot, options_.stride);
    line.t_eg = std::min(line.t_eg, line.t_e);
  }

  // Down from hi in steps that double from first_step to the first false test (test monotone:
  // false then true): [lo, hi] narrowed to just above that cell and the last true one.
  template <typename Test>
  static void gallop_down_from(std::size_t& lo, std::size_t& hi, Test&& test, std::size_t first_step) {
    for (std::size_t step = first_step; hi > lo; step *= 2) {
      const std::size_t i = hi - lo > step ? hi - step : lo;
      if (!test(i)) {
        lo = i + 1;
        return;
      }
      hi = i;
    }
  }

  // Up from lo in steps that double from first_step (up to max_step) to the first true test (test
  // monotone: false then true): lo just above the last false test, hi at the first true one.
  template <typename Test>
  static void gallop_up_from(std::size_t& lo, std::size_t& hi, Test&& test, std::size_t first_step,
                             std::size_t max_step = std::numeric_limits<std::size_t>::max()) {
    for (std::size_t step = first_step; lo < hi; step = std::min(2 * step, max_step)) {
      const std::size_t i = std::min(lo + step - 1, hi - 1);
      if (test(i)) {
        hi = i;
        return;
      }
      lo = i + 1;
    }
  }

  // The smallest b in [lo, hi] with test(i) true for every i in [b, hi), by bisection (test
  // monotone: false then true).
  template <typename Test>
  static std::size_t bisect(std::size_t lo, std::size_t hi, Test&& test) {
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (test(mid))
        hi = mid;
      else
        lo = mid + 1;
    }
    return hi;
  }

  // The smallest b in [lo, hi] with test(i) true for every i in [b, hi) (test monotone: false then
  // true), from a guess: galloping away from the guess, then bisecting. Two tests when the guess is
  // right, about 2·log2(distance) when it is not. Upwards the steps grow to max_step at most, so
  // that from the bottom of a line (an early run's end) a run of trues as long as max_step between
  // falses is not stepped over.
  template <typename Test>
  static std::size_t threshold(std::size_t lo, std::size_t hi, std::size_t guess, Test&& test,
                               std::size_t max_step = std::numeric_limits<std::size_t>::max()) {
    const auto gallop_down = [&] { gallop_down_from(lo, hi, test, 1); };
    if (guess >= hi) {
      gallop_down();
    } else if (test(guess)) {
      hi = guess;
      gallop_down();
    } else {
      lo = guess + 1;
      gallop_up_from(lo, hi, test, 1, max_step);
    }
    return bisect(lo, hi, test);
  }

  // threshold() from the bottom of a line for a test whose false answers are cheap and true ones
  // dear (the early run's end: a cell that avoids against one that cannot): up in steps that grow
  // to max_step, then, from the last false, up a cell at a time to the first true. At most one dear
  // test besides the answer's (bisecting the last step could make two).
  template <typename Test>
  static std::size_t threshold_from_below(std::size_t hi, Test&& test, std::size_t max_step) {
    std::size_t lo = 0;
    gallop_up_from(lo, hi, test, 1, max_step);
    while (lo < hi && !test(lo)) ++lo;
    return lo;
  }

  // threshold() for a test whose true answers are cheap and false ones dear: a cell that avoids
  // (a planner that found a way, about 0.3 s) against one that no strategy avoids and no
  // certificate proves so (the strengthened search, 1 to 2 s). The same answer where the test is
  // monotone, found from above: from a true guess it walks down a cell at a time to the first
  // false, the one dear test a threshold needs; from a false one it first jumps up (2, 4, 8 cells)
  // to a true one. Past kWalk cells down without a false it gallops down (2, 4, 8 cells) to a
  // false and walks down again from the last true, bisecting only a gap wider than 2·kWalk.
  template <typename Test>
  static std::size_t threshold_from_above(std::size_t lo, std::size_t hi, std::size_t guess, Test&& test) {
    constexpr std::size_t kWalk = 6;
    if (guess < hi) {
      if (test(guess)) {
        hi = guess;
      } else {
        lo = guess + 1;
        gallop_up_from(lo, hi, test, 2);
      }
    }
    const auto walk_down = [&] {  // true: the threshold is found (hi)
      for (std::size_t walked = 0; walked < kWalk && hi > lo; ++walked) {
        if (!test(hi - 1)) return true;
        --hi;
      }
      return hi == lo;
    };
    if (walk_down()) return hi;
    gallop_down_from(lo, hi, test, 2);
    if (hi - lo <= 2 * kWalk) {
      while (hi > lo && test(hi - 1)) --hi;
      return hi;
    }
    return bisect(lo, hi, test);
  }

  // The avoidance threshold between the early run and the stop boundary, from the line's hint
  // when it has one.
  std::size_t avoidance_threshold(const Line& line) {
    const std::size_t guess = line.hint == kNone ? line.t_g : std::clamp(index_at(line, line.hint), line.t_e, line.t_g);
    return threshold_from_above(line.t_e, line.t_g, guess, [&](std::size_t i) {
      return avoidable(simulate(line.cells[i], Purpose::kThresholdCorners));
    });
  }

  // Every simulated cell against the thresholds; the first contradiction, if any.
  std::optional<Violation> check(const Line& line) const {
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      const std::uint32_t cell = line.cells[i];
      const bool stops = oracle_.stop(cell) == StopCall::kStops;
      if (!is_simulated(cell) && !stops) continue;
      const Region r = stops && !is_simulated(cell) ? Region::kG : result_.cells[cell].region;
      const bool g = i < line.t_eg || i >= line.t_g;
      const bool a = i < line.t_e || i >= line.t_a;
      if (r == Region::kG && !g) return Violation{cell, line.cells[std::min(line.t_g, line.cells.size() - 1)], "stop"};
      if (r != Region::kG && g) return Violation{line.cells[i < line.t_eg ? 0 : line.t_g], cell, "stop"};
      if (avoidable(r) && !a) return Violation{cell, line.cells[line.t_a > 0 ? line.t_a - 1 : 0], "avoidance"};
      if (!avoidable(r) && a) return Violation{line.cells[i < line.t_e ? 0 : line.t_a], cell, "avoidance"};
    }
    return std::nullopt;
  }
  // A corner of a threshold box: its stop boundary and avoidance threshold by search.
  void search_thresholds(std::size_t id) {
    Line& line = lines_[id];
    line.thresholds_searched = line.thresholds_known = true;
    if (line.cells.empty()) return;
    early_run(line, Purpose::kThresholdCorners, line.early_hint);
    stop_threshold(line, Purpose::kThresholdCorners);
    look_for_gap(line, line.hint, Purpose::kThresholdCorners);
    line.t_a = avoidance_threshold(line);
  }

  // A corner of a label box: the O/R labels below the avoidance threshold sampled every `stride`
  // cells, with every change bisected down to adjacent cells, the cells between equal samples
  // taking their label.
  void sample_labels(std::size_t id) {
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
  bool nothing_to_mitigate(std::uint32_t cell) {
    std::int8_t& known = nothing_to_mitigate_[cell];
    if (known < 0) known = oracle_.nothing_to_mitigate(cell) ? 1 : 0;
    return known == 1;
  }

  // An unavoidable cell's label when something gives it: its simulation, else the rule.
  std::optional<Region> label(std::uint32_t cell) {
    if (is_simulated(cell)) return result_.cells[cell].region;
    if (nothing_to_mitigate(cell)) return Region::kR;
    return std::nullopt;
  }

  // Between two cells of [begin, end) with different known labels (simulated, or R by the rule),
  // simulations halve the gap until the two are neighbours; the midpoints of one pass are simulated
  // together.
  void bisect_changes(const Line& line, std::size_t begin, std::size_t end, Purpose purpose) {
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

  // Cells whose simulations do not depend on one another, side by side (each once).
  void simulate_all(std::vector<std::uint32_t> cells, Purpose purpose) {
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    parallel(cells, [&](std::uint32_t cell) { simulate(cell, purpose); });
  }

  // After a contradiction: every cell the analytic stop run does not settle is simulated, and the
  // thresholds and labels are read off the simulations.
  void resolve_fully(std::size_t id) {
    Line& line = lines_[id];
    line.full = true;
    line.thresholds_searched = line.thresholds_known = line.labels_sampled = line.labels_known = true;
    const std::size_t top = analytic_top(line);
    simulate_all({line.cells.begin(), line.cells.begin() + static_cast<long>(top)}, Purpose::kViolations);
    const auto region = [&](std::size_t i) { return result_.cells[line.cells[i]].region; };
    line.t_g = top;
    while (line.t_g > 0 && region(line.t_g - 1) == Region::kG) --line.t_g;
    line.early_searched = true;
    line.t_e = line.t_eg = 0;
    if (may_pass_early(line)) {
      while (line.t_e < line.t_g && avoidable(region(line.t_e))) ++line.t_e;
      while (line.t_eg < line.t_e && region(line.t_eg) == Region::kG) ++line.t_eg;
    }
    line.t_a = line.t_g;
    while (line.t_a > line.t_e && avoidable(region(line.t_a - 1))) --line.t_a;
    if (line.t_e > 0 && line.t_a == line.t_e) line.t_e = line.t_a = line.t_g;  // no cell below the stop's run cannot avoid
    line.labels.assign(line.t_a, Region::kR);
    for (std::size_t i = line.t_e; i < line.t_a; ++i) line.labels[i] = region(i);
  }

  // An avoidance threshold that the line's later simulations (its labels, a neighbour's search)
  // contradict with no simulated cell between to break monotonicity, as a prediction or a bracket
  // one level off does: searched again between the simulated cells that bound it (a few
  // simulations instead of this line and its neighbours in full). Searched down from the lowest
  // cell below it that avoids, above the highest simulated one below that does not; up from the
  // highest cell above it that does not avoid, below the lowest simulated one above that avoids.
  void research_threshold(Line& line) {
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

  // Simulations against the thresholds and labels of every line; a line that breaks monotonicity
  // is simulated in full with its neighbours (theirs too, if they break it), until none does.
  void resolve_violations() {
    std::vector<char> queued(lines_.size(), 0);
    std::vector<std::size_t> todo;
    const auto scan = [&](const std::vector<std::size_t>& ids) {
      std::vector<std::size_t> next;
      for (std::size_t id : ids) {
        Line& line = lines_[id];
        if (line.violated) continue;
        const auto v = check(line);
        if (!v) continue;
        line.violated = true;
        result_.violations.push_back(*v);
        const auto p = line_position(id);
        if (!queued[id]) next.push_back(id), queued[id] = 1;
        for (std::size_t a = 0; a < 4; ++a)
          for (int d : {-1, 1}) {
            auto q = p;
            if ((d < 0 && q[a] == 0) || (d > 0 && q[a] + 1 >= extent(a))) continue;
            q[a] = static_cast<std::uint32_t>(static_cast<int>(q[a]) + d);
            const std::size_t n = line_id(q);
            if (!queued[n]) next.push_back(n), queued[n] = 1;
          }
      }
      return next;
    };
    std::vector<std::size_t> all(lines_.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    todo = scan(all);
    while (!todo.empty()) {
      std::sort(todo.begin(), todo.end());
      parallel(todo, [&](std::size_t id) { resolve_fully(id); });
      todo = scan(todo);
    }
  }

  // --- boxes --------------------------------------------------------------------------------

  [[nodiscard]] bool known(const Line& line, Question q) const noexcept {
    return q == Question::kThresholds ? line.thresholds_known : line.labels_known;
  }

  // Whether two lines, settled by their own searches, answer `q` alike: both have a Y run or
  // neither, with thresholds within the bracket; the same O/R label wherever both have one, or the
  // same runs of labels changing within the bracket of each other.
  bool agree(std::size_t id_a, std::size_t id_b, Question q) const {
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
  [[nodiscard]] EarlyHint median_early(const std::vector<std::size_t>& ids) const {
    const auto median = [&](auto&& position) {
      std::vector<std::uint32_t> ends;
      for (std::size_t id : ids)
        if (position(lines_[id]) != kNone) ends.push_back(position(lines_[id]));
      if (ends.empty()) return kNone;
      std::nth_element(ends.begin(), ends.begin() + static_cast<long>(ends.size() / 2), ends.end());
      return ends[ends.size() / 2];
    };
    return {median([](const Line& l) { return l.early_position(); }), median([](const Line& l) { return l.early_g_position(); })};
  }

  // The corners' common answer to `q`, or nothing when some two of them disagree.
  std::optional<Signature> signature(const Box& box, Question q) const {
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
  std::optional<Signature> alike_runs(const std::vector<std::size_t>& corners, Signature s) const {
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
  void bracket_labels(std::size_t id, const Signature& s) {
    Line& line = lines_[id];
    line.changes.clear();
    std::size_t from = line.t_e;
    for (std::size_t j = 0; j < s.changes.size(); ++j) {
      const std::size_t lo = std::clamp(index_at(line, s.changes[j].first), from, line.t_a);
      const std::size_t hi = std::clamp(index_at(line, s.changes[j].second), lo, line.t_a);
      if (four_factors_ && lo != hi) {
        from = predicted_change(line, id, s, j, lo, hi);
      } else {
        from = threshold(lo, hi, hi, [&](std::size_t i) {
          return simulate(line.cells[i], Purpose::kLabelBrackets) != s.runs[j];
        });
      }
      line.changes.push_back(from);
    }
  }

  // Where the corners' j-th change of labels predicts the line's, within [lo, hi]: interpolated
  // from them, then moved where the line's own simulations say (above the last cell of the run
  // before it, at the first of the run after it).
  std::size_t predicted_change(const Line& line, std::size_t id, const Signature& s, std::size_t j, std::size_t lo,
                               std::size_t hi) const {
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
  void bracket_thresholds(std::size_t id, const Signature& s) {
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
    const auto index_of = [&](std::uint32_t position) { return std::clamp(index_at(line, position), line.t_e, line.t_g); };
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
  void settle_prediction(Line& line) {
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
  static std::optional<Region> nearest_label(const Signature& s, std::uint32_t position) {
    if (s.labels.empty()) return std::nullopt;
    auto it = s.labels.lower_bound(position);
    if (it == s.labels.end() || (it->first != position && it != s.labels.begin() &&
                                 position - std::prev(it)->first <= it->first - position))
      it = std::prev(it);
    return it->second;
  }

  // A line between agreeing corners takes their labels; false when they give none, or when a cell
  // the line simulated for its thresholds says otherwise.
  bool infer_labels(Line& line, const Signature& s) {
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
  void refine(Question q) {
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
  void run(const std::vector<std::pair<std::size_t, const Signature*>>& work, Question q) {
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
  [[nodiscard]] std::uint32_t predicted(const Range& box, std::size_t id,
                                        std::uint32_t (Line::*start)() const) const {
    return interpolated(box, id, [&](const Line& corner) -> std::optional<std::uint32_t> {
      if (corner.cells.empty() || !corner.thresholds_searched) return std::nullopt;
      return (corner.*start)();
    });
  }

  // A position the corners of `box` give (nothing from a corner that has none), interpolated
  // multilinearly at the line `id`'s place in the box; kNone when no corner gives one.
  template <typename Value>
  [[nodiscard]] std::uint32_t interpolated(const Range& box, std::size_t id, Value&& value) const {
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
  void split(const Box& box, Question q, std::vector<Box>& out) const {
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
                              Range(box), early_hint});
  }

  // --- the map ---------------------------------------------------------------------------------

  // Gives every cell of a line its region and method: G above the stop boundary (by physics), Y
  // from the avoidance threshold, the labels below it; `from` names the simulated cells behind
  // each inferred cell (in the line, or at the same level on the corners it was inferred from).
  void fill(std::size_t id) {
    Line& line = lines_[id];
    std::vector<std::size_t> simulated;
    for (std::size_t i = 0; i < line.cells.size(); ++i)
      if (is_simulated(line.cells[i])) simulated.push_back(i);
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      Cell& c = result_.cells[line.cells[i]];
      if (c.method == Method::kSimulated) continue;
      c.from.clear();
      if (i >= line.t_g) {
        c.region = Region::kG;
        c.method = Method::kStop;
        continue;
      }
      // Its run [begin, end), and whether the line's own simulations settled it.
      std::size_t begin = line.t_e, end = line.t_a;
      bool from_line = line.labels_sampled;
      const bool y = i >= line.t_a;
      if (i < line.t_e) {
        const bool g = i < line.t_eg;
        c.region = g ? Region::kG : Region::kY;
        begin = g ? 0 : line.t_eg;
        end = g ? line.t_eg : line.t_e;
        from_line = g || !line.early_predicted;  // an early run's G part is always the line's own
      } else if (y) {
        c.region = Region::kY;
        begin = line.t_a;
        end = line.t_g;
        from_line = line.thresholds_searched;
      } else {
        c.region = nothing_to_mitigate(line.cells[i]) ? Region::kR : line.labels[i];
      }
      c.method = from_line ? Method::kLine : Method::kBox;
      // The line's simulated cells nearest below and above it within [lo, hi).
      const auto bounding = [&](std::size_t lo, std::size_t hi) {
        const auto above = std::upper_bound(simulated.begin(), simulated.end(), i);
        if (above != simulated.begin() && *std::prev(above) >= lo) c.from.push_back(line.cells[*std::prev(above)]);
        if (above != simulated.end() && *above < hi) c.from.push_back(line.cells[*above]);
      };
      if (from_line) bounding(begin, end);  // the simulated cells around it in its run
      if (c.from.empty())
        corner_sources(line, y || i < line.t_e ? line.threshold_corners : line.label_corners, i, c.from);
      if (c.from.empty()) bounding(0, line.cells.size());  // R by the rule where nothing was sampled
      if (c.from.empty()) corner_sources(line, line.threshold_corners, i, c.from);
    }
  }

  // The simulated cells at the level of cell i (or the nearest) on the lines its labels came from,
  // or on the lines beside it when it has none.
  void corner_sources(const Line& line, const std::vector<std::uint32_t>& corners, std::size_t i,
                      std::vector<std::uint32_t>& from) const {
    for (std::uint32_t corner : corners) {
      const Line& other = lines_[corner];
      if (other.cells.empty()) continue;
      auto at = static_cast<std::size_t>(std::lower_bound(other.position.begin(), other.position.end(),
                                                          line.position[i]) - other.position.begin());
      if (at == other.cells.size() ||
          (at > 0 && line.position[i] - other.position[at - 1] < other.position[at] - line.position[i]))
        --at;
      const std::uint32_t cell = other.cells[at];
      if (is_simulated(cell)) {
        from.push_back(cell);
        continue;
      }
      // The corner's own nearest simulations at that level's run.
      for (std::size_t k = at; k-- > 0;)
        if (is_simulated(other.cells[k])) {
          from.push_back(other.cells[k]);
          break;
        }
      for (std::size_t k = at + 1; k < other.cells.size(); ++k)
        if (is_simulated(other.cells[k])) {
          from.push_back(other.cells[k]);
          break;
        }
    }
    std::sort(from.begin(), from.end());
    from.erase(std::unique(from.begin(), from.end()), from.end());
    if (from.size() > kMaxFrom) from.resize(kMaxFrom);
  }

  // --- verification and totals ------------------------------------------------------------------

  // A random sample of the cells inferred from other simulations (not the analytic stop cells, which
  // are exact by construction), simulated: the observed disagreement rate and its Wilson interval.
  void verify() {
    std::vector<std::uint32_t> population;
    for (std::size_t c = 0; c < result_.cells.size(); ++c)
      if (result_.cells[c].method == Method::kLine || result_.cells[c].method == Method::kBox)
        population.push_back(static_cast<std::uint32_t>(c));
    result_.verify_population = population.size();
    const std::size_t automatic = std::clamp<std::size_t>(result_.feasible / 200, 20, 500);
    const std::size_t k = std::min(options_.verify_sample.value_or(automatic), population.size());
    std::mt19937_64 random(options_.seed);
    for (std::size_t i = 0; i < k; ++i) {  // a partial Fisher-Yates shuffle: the same sample everywhere
      const std::size_t j = i + static_cast<std::size_t>(random() % (population.size() - i));
      std::swap(population[i], population[j]);
    }
    population.resize(k);
    std::sort(population.begin(), population.end());
    std::vector<Region> inferred(k);
    for (std::size_t i = 0; i < k; ++i) inferred[i] = result_.cells[population[i]].region;
    simulate_all(population, Purpose::kVerification);
    for (std::size_t i = 0; i < k; ++i)
      if (result_.cells[population[i]].region != inferred[i]) result_.verify_disagreements.push_back(population[i]);
    result_.verify_sampled = k;
    result_.disagreement = scenario::wilson_interval(static_cast<double>(result_.verify_disagreements.size()),
                                                     static_cast<double>(k), options_.confidence);
  }

  void finish() {
    result_.simulated = simulated_.load();
    for (std::size_t p = 0; p < kPurposes; ++p) result_.simulated_for[p] = simulated_for_[p].load();
    for (const Line& line : lines_) {
      result_.lines_resolved += line.thresholds_searched || line.labels_sampled ? 1 : 0;
      result_.lines_inferred += line.thresholds_searched || line.labels_sampled ? 0 : 1;
      result_.lines_fully_resolved += line.full ? 1 : 0;
    }
  }

  template <typename Id, typename Work>
  void parallel(const std::vector<Id>& ids, Work&& work) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, ids.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i < range.end(); ++i) work(ids[i]);
        },
        tbb::simple_partitioner());
  }

  const Lattice& lattice_;
  Oracle& oracle_;
  Options options_;
  bool predict_brackets_ = false;  ///< Options::brackets, auto resolved
  std::uint32_t spread_ = 1;       ///< Options::spread, auto resolved
  /// From four factors on (with predicted brackets): label changes predicted within their bracket,
  /// and boxes split across one factor at a time.
  bool four_factors_ = false;
  std::array<std::vector<std::size_t>, kAxes> order_;  ///< per factor: sorted position → level index
  std::size_t monotone_ = kTtc;
  std::vector<std::size_t> line_axes_;
  std::vector<Line> lines_;
  std::vector<std::int8_t> nothing_to_mitigate_;  ///< per cell: -1 not asked yet, else the oracle's answer
  Result result_;
  std::atomic<std::size_t> simulated_{0};
  std::array<std::atomic<std::size_t>, kPurposes> simulated_for_{};
};

}  // namespace

std::size_t Lattice::size() const noexcept {
  std::size_t n = 1;
  for (const auto& l : levels) n *= l.size();
  return n;
}

std::size_t Lattice::index(const std::array<std::size_t, 5>& level) const noexcept {
  std::size_t i = 0;
  for (std::size_t k = 0; k < 5; ++k) i = i * levels[k].size() + level[k];
  return i;
}

std::string_view method_name(Method m) noexcept {
  switch (m) {
    case Method::kNone: return "";
    case Method::kSimulated: return "simulated";
    default: return "inferred";
  }
}

std::string_view purpose_name(Purpose p) noexcept {
  switch (p) {
    case Purpose::kThresholdCorners: return "threshold_corners";
    case Purpose::kThresholdBrackets: return "threshold_brackets";
    case Purpose::kLabels: return "labels";
    case Purpose::kLabelBrackets: return "label_brackets";
    case Purpose::kViolations: return "violations";
    case Purpose::kVerification: return "verification";
  }
  return "";
}

std::optional<Brackets> brackets_named(std::string_view name) noexcept {
  if (name == "auto") return Brackets::kAuto;
  if (name == "search") return Brackets::kSearch;
  if (name == "predict") return Brackets::kPredict;
  return std::nullopt;
}

std::string_view basis_name(Method m) noexcept {
  switch (m) {
    case Method::kNone: return "";
    case Method::kSimulated: return "simulated";
    case Method::kStop: return "stop";
    case Method::kLine: return "line";
    case Method::kBox: return "box";
  }
  return "";
}

sim::Region region_named(std::string_view name) noexcept {
  for (const Region r : {Region::kG, Region::kY, Region::kO, Region::kR})
    if (sim::region_name(r) == name) return r;
  return Region::kInfeasible;
}

Result search(const Lattice& lattice, Oracle& oracle, const Options& options) {
  for (const auto& l : lattice.levels)
    if (l.empty()) throw std::invalid_argument("adaptive search: a factor has no level");
  if (options.initial_levels == 1) throw std::invalid_argument("adaptive search: initial_levels must be 0 (automatic) or at least 2");
  if (options.stride < 1) throw std::invalid_argument("adaptive search: stride must be at least 1");
  if (options.spread < 1) throw std::invalid_argument("adaptive search: spread must be at least 1");
  return Search(lattice, oracle, options).run();
}

}  // namespace emrm::campaign::adaptive
