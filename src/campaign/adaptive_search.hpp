#pragma once

// The adaptive boundary search's internals (docs/adaptive.md): the lines of the lattice, boxes of
// lines, what agreeing corners say of the lines between them, and the class Search that settles
// them. Internal to src/campaign. Search's member functions are defined by concept: adaptive.cpp
// (the run and its simulations), adaptive_lines.cpp (the lattice's geometry),
// adaptive_thresholds.cpp (a line's thresholds), adaptive_labels.cpp (a line's O/R labels),
// adaptive_boxes.cpp (boxes refined, what their corners predict) and adaptive_fill.cpp (monotonicity,
// the map and its grounds, the verification sample).

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "emrm/campaign/adaptive.hpp"

namespace emrm::campaign::adaptive::detail {

using sim::Region;

inline constexpr std::size_t kAxes = Lattice::kMaxAxes;  ///< a lattice of fewer is padded with single levels
inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

inline bool avoidable(Region r) noexcept { return r == Region::kG || r == Region::kY; }

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
  bool thresholds_searched = false;     ///< by a search of its own (a corner of a threshold box)
  bool thresholds_known = false;        ///< searched, or found within a uniform box's bracket
  bool labels_sampled = false;          ///< O/R labels by samples of its own (a corner of a label box)
  bool labels_known = false;            ///< sampled, or inferred from a uniform box's corners
  bool full = false;                    ///< every cell that the stop boundary does not settle simulated
  bool violated = false;                ///< simulations contradicted monotonicity
  bool early_searched = false;          ///< its early run by simulations of its own (else from its corners)
  bool early_predicted = false;         ///< its early run's end predicted from its corners (its G part searched)
  std::uint32_t hint = kNone;           ///< a guess of the avoidance threshold's position (from a parent box)
  std::uint32_t stop_hint = kNone;      ///< and of the stop boundary's
  EarlyHint early_hint;                 ///< from a parent box
  // The line in runs, bottom to top: [0, t_eg) G and [t_eg, t_e) Y passing in front of a truck
  // still on its way (the early run; empty unless the oracle says arriving sooner can help),
  // [t_e, t_a) O or R, [t_a, t_g) Y, [t_g, size) G.
  std::size_t t_eg = 0;              ///< end of the early G run
  std::size_t t_e = 0;               ///< end of the early avoidable run
  std::size_t t_g = 0;               ///< first index of the G run at the top
  std::size_t t_a = 0;               ///< first index of the avoidable run (G or Y) at the top
  std::vector<Region> labels;        ///< O/R of the cells in [t_e, t_a) (by index; simulated or inferred)
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
  Range box;                                            ///< where the corners are
  std::uint32_t avoid_low = kNone, avoid_high = kNone;  ///< the corners' thresholds span [low, high]
  EarlyHint early_hint;                                 ///< the median ends of the corners' early runs
  bool early_predicted = false;                         ///< the corners' early runs end alike below the stop's run
  std::map<std::uint32_t, Region> labels;               ///< O/R by level, below the thresholds
  // Or, when the corners' labels differ at some level: the runs of labels they all have, bottom to
  // top, and the span of the positions where each run after the first starts.
  std::vector<Region> runs;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> changes;
};

// The two refinements: of the avoidance thresholds, then of the O/R labels below them.
enum class Question { kThresholds, kLabels };

class Search {
 public:
  Search(const Lattice& lattice, Oracle& oracle, const Options& options);
  Result run();

 private:
  // --- geometry (adaptive_lines.cpp) -------------------------------------------------------------

  [[nodiscard]] std::uint32_t extent(std::size_t a) const noexcept {
    return static_cast<std::uint32_t>(lattice_.levels[line_axes_[a]].size());
  }

  [[nodiscard]] std::size_t line_id(const std::array<std::uint32_t, 4>& p) const noexcept {
    std::size_t id = 0;
    for (std::size_t a = 0; a < 4; ++a) id = id * extent(a) + p[a];
    return id;
  }

  void build_lines();
  [[nodiscard]] std::array<std::uint32_t, 4> line_position(std::size_t id) const noexcept;
  [[nodiscard]] std::size_t initial_levels(Question q) const noexcept;
  std::vector<Box> initial_boxes(std::size_t levels) const;

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

  // --- one line: its simulations (adaptive.cpp) --------------------------------------------------

  Region simulate(std::uint32_t cell, Purpose purpose);
  void simulate_all(std::vector<std::uint32_t> cells, Purpose purpose);

  [[nodiscard]] bool is_simulated(std::uint32_t cell) const noexcept {
    return result_.cells[cell].method == Method::kSimulated;
  }

  // --- one line: its thresholds (adaptive_thresholds.cpp) ----------------------------------------

  [[nodiscard]] std::size_t analytic_top(const Line& line) const;
  void stop_threshold(Line& line, Purpose purpose);
  [[nodiscard]] bool may_pass_early(const Line& line) const;
  void early_run(Line& line, Purpose purpose, EarlyHint hint);
  bool predicted_early_run(Line& line, const EarlyHint& hint, std::size_t top, Purpose purpose);
  void settle_early(Line& line);
  void look_for_gap(Line& line, std::uint32_t avoid_hint, Purpose purpose);
  std::size_t avoidance_threshold(const Line& line);
  void search_thresholds(std::size_t id);
  void research_threshold(Line& line);

  // The index of the first cell at or above a position (the line's size when none is).
  [[nodiscard]] static std::size_t index_at(const Line& line, std::uint32_t position) {
    return static_cast<std::size_t>(std::lower_bound(line.position.begin(), line.position.end(), position) -
                                    line.position.begin());
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

  // --- one line: its O/R labels (adaptive_labels.cpp) --------------------------------------------

  void sample_labels(std::size_t id);
  bool nothing_to_mitigate(std::uint32_t cell);
  std::optional<Region> label(std::uint32_t cell);
  void bisect_changes(const Line& line, std::size_t begin, std::size_t end, Purpose purpose);

  // --- boxes (adaptive_boxes.cpp) ----------------------------------------------------------------

  [[nodiscard]] bool known(const Line& line, Question q) const noexcept {
    return q == Question::kThresholds ? line.thresholds_known : line.labels_known;
  }

  bool agree(std::size_t id_a, std::size_t id_b, Question q) const;
  [[nodiscard]] EarlyHint median_early(const std::vector<std::size_t>& ids) const;
  std::optional<Signature> signature(const Box& box, Question q) const;
  std::optional<Signature> alike_runs(const std::vector<std::size_t>& corners, Signature s) const;
  void bracket_labels(std::size_t id, const Signature& s);
  std::size_t predicted_change(const Line& line, std::size_t id, const Signature& s, std::size_t j, std::size_t lo,
                               std::size_t hi) const;
  void bracket_thresholds(std::size_t id, const Signature& s);
  void settle_prediction(Line& line);
  static std::optional<Region> nearest_label(const Signature& s, std::uint32_t position);
  bool infer_labels(Line& line, const Signature& s);
  void refine(Question q);
  void run(const std::vector<std::pair<std::size_t, const Signature*>>& work, Question q);
  [[nodiscard]] std::uint32_t predicted(const Range& box, std::size_t id, std::uint32_t (Line::*start)() const) const;
  template <typename Value>
  [[nodiscard]] std::uint32_t interpolated(const Range& box, std::size_t id, Value&& value) const;
  void split(const Box& box, Question q, std::vector<Box>& out) const;

  // --- the map, its grounds, the verification and totals (adaptive_fill.cpp) ---------------------

  std::optional<Violation> check(const Line& line) const;
  void resolve_fully(std::size_t id);
  void resolve_violations();
  void fill(std::size_t id);
  void corner_sources(const Line& line, const std::vector<std::uint32_t>& corners, std::size_t i,
                      std::vector<std::uint32_t>& from) const;
  void verify();
  void finish();

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
  std::size_t monotone_ = 0;
  std::vector<std::size_t> line_axes_;
  std::vector<Line> lines_;
  std::vector<std::int8_t> nothing_to_mitigate_;  ///< per cell: -1 not asked yet, else the oracle's answer
  Result result_;
  std::atomic<std::size_t> simulated_{0};
  std::array<std::atomic<std::size_t>, kPurposes> simulated_for_{};
};

}  // namespace emrm::campaign::adaptive::detail
