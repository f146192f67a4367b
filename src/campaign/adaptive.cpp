#include "emrm/campaign/adaptive.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>

namespace emrm::campaign::adaptive {
namespace {

using sim::Region;

constexpr std::size_t kAxes = 5;
constexpr std::size_t kTtc = 1;
constexpr std::size_t kMu = 2;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxFrom = 16;

bool avoidable(Region r) noexcept { return r == Region::kG || r == Region::kY; }

// A line: the feasible cells that differ only in the monotone factor, in ascending order of it.
// Once settled (resolved by simulation or inferred from a box), its cells hold their regions.
struct Line {
  std::vector<std::uint32_t> cells;
  std::vector<std::uint32_t> position;  ///< of each cell along the monotone axis (sorted level)
  bool resolved = false;  ///< by its own simulations
  bool inferred = false;  ///< from the corners of a box
  bool full = false;      ///< every cell that the stop boundary does not settle simulated
  bool violated = false;  ///< simulations contradicted monotonicity
  std::uint32_t hint = kNone;  ///< a guess of the avoidance threshold's position (from a parent box)
  std::size_t t_g = 0;  ///< first index of the G run at the top
  std::size_t t_a = 0;  ///< first index of the avoidable run (G or Y) at the top

  [[nodiscard]] bool settled() const noexcept { return resolved || inferred; }
  /// Position of the avoidance threshold when the line has Y cells; kNone when avoidance starts with G.
  [[nodiscard]] std::uint32_t avoid_position() const noexcept { return t_a < t_g ? position[t_a] : kNone; }
};

// A box of lines: per line axis, a range of sorted positions [lo, hi].
struct Box {
  std::array<std::uint32_t, 4> lo{}, hi{};
  std::uint32_t hint = kNone;
};

// What a uniform box's corners say: the avoidance threshold's position and the O/R label at every
// position below it that some corner has.
struct Signature {
  std::uint32_t avoid_low = kNone, avoid_high = kNone;  ///< the corners' thresholds span [low, high]
  std::map<std::uint32_t, Region> labels;
};

// Corners whose avoidance thresholds differ by at most this many levels still agree: the lines
// between them search their own threshold within that bracket (a simulation or two each).
constexpr std::uint32_t kBracket = 2;

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
    result_.cells.resize(lattice.size());
    build_lines();
  }

  Result run() {
    std::vector<Box> pending = initial_boxes();
    while (!pending.empty() || !full_queue_.empty()) {
      ++result_.rounds;
      resolve_corners(pending);
      pending = settle_boxes(pending);
    }
    for (std::size_t id = 0; id < lines_.size(); ++id)
      if (!lines_[id].settled()) resolve(id);  // cannot happen; a line left out is resolved, not guessed
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
    scheduled_.assign(count, 0);
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

  // Each factor sampled at about `initial_levels` positions, always its first and last.
  std::vector<Box> initial_boxes() const {
    std::array<std::vector<std::uint32_t>, 4> samples;
    for (std::size_t a = 0; a < 4; ++a) {
      const std::uint32_t n = extent(a);
      const std::uint32_t stride =
          n <= 1 ? 1 : std::max<std::uint32_t>(1, static_cast<std::uint32_t>((n - 1 + options_.initial_levels - 2) /
                                                                               (options_.initial_levels - 1)));
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
  void for_each_corner(const Box& box, Visit&& visit) const {
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
  void for_each_line(const Box& box, Visit&& visit) const {
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

  [[nodiscard]] static bool is_corner(const Box& box, const std::array<std::uint32_t, 4>& p) noexcept {
    for (std::size_t a = 0; a < 4; ++a)
      if (p[a] != box.lo[a] && p[a] != box.hi[a]) return false;
    return true;
  }

  // --- one line -----------------------------------------------------------------------------

  Region simulate(std::uint32_t cell) {
    Cell& c = result_.cells[cell];
    if (c.method != Method::kSimulated) {
      c.region = oracle_.simulate(cell);
      c.method = Method::kSimulated;
      c.from.clear();
      ++simulated_;
    }
    return c.region;
  }

  [[nodiscard]] bool is_simulated(std::uint32_t cell) const noexcept {
    return result_.cells[cell].method == Method::kSimulated;
  }

  // The stop boundary: the top run of cells physics says stop in time, extended downwards by
  // simulation (galloping, then bisecting) over the cells it cannot settle. Sets line.t_g.
  void stop_threshold(Line& line) {
    const auto g = [&](std::size_t i) {
      switch (oracle_.stop(line.cells[i])) {
        case StopCall::kStops: return true;
        case StopCall::kCannotStop: return false;
        case StopCall::kUnknown: break;
      }
      return simulate(line.cells[i]) == Region::kG;
    };
    std::size_t hi = line.cells.size();
    while (hi > 0 && oracle_.stop(line.cells[hi - 1]) == StopCall::kStops) --hi;
    line.t_g = threshold(0, hi, hi, g);
  }

  // The smallest b in [lo, hi] with test(i) true for every i in [b, hi) (test monotone: false then
  // true), from a guess: galloping away from the guess, then bisecting. Two tests when the guess is
  // right, about 2·log2(distance) when it is not.
  template <typename Test>
  static std::size_t threshold(std::size_t lo, std::size_t hi, std::size_t guess, Test&& test) {
    const auto gallop_down = [&] {
      for (std::size_t step = 1; hi > lo; step *= 2) {
        const std::size_t i = hi - lo > step ? hi - step : lo;
        if (!test(i)) {
          lo = i + 1;
          return;
        }
        hi = i;
      }
    };
    if (guess >= hi) {
      gallop_down();
    } else if (test(guess)) {
      hi = guess;
      gallop_down();
    } else {
      lo = guess + 1;
      for (std::size_t step = 1; hi > lo; step *= 2) {
        const std::size_t i = std::min(lo + step - 1, hi - 1);
        if (test(i)) {
          hi = i;
          break;
        }
        lo = i + 1;
      }
    }
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (test(mid))
        hi = mid;
      else
        lo = mid + 1;
    }
    return hi;
  }

  // The avoidance threshold below the stop boundary, from the line's hint when it has one.
  std::size_t avoidance_threshold(const Line& line) {
    std::size_t guess = line.t_g;
    if (line.hint != kNone)
      guess = static_cast<std::size_t>(std::lower_bound(line.position.begin(), line.position.begin() + static_cast<long>(line.t_g),
                                                        line.hint) - line.position.begin());
    return threshold(0, line.t_g, guess,
                     [&](std::size_t i) { return avoidable(simulate(line.cells[i])); });
  }

  // Every simulated cell against the thresholds; the first contradiction, if any.
  std::optional<Violation> check(const Line& line) const {
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      const std::uint32_t cell = line.cells[i];
      const bool stops = oracle_.stop(cell) == StopCall::kStops;
      if (!is_simulated(cell) && !stops) continue;
      const Region r = stops && !is_simulated(cell) ? Region::kG : result_.cells[cell].region;
      if (i < line.t_g && r == Region::kG)
        return Violation{cell, line.cells[std::min(line.t_g, line.cells.size() - 1)], "stop"};
      if (i >= line.t_g && r != Region::kG) return Violation{line.cells[line.t_g], cell, "stop"};
      if (i < line.t_a && avoidable(r)) return Violation{cell, line.cells[line.t_a > 0 ? line.t_a - 1 : 0], "avoidance"};
      if (i >= line.t_a && !avoidable(r)) return Violation{line.cells[line.t_a], cell, "avoidance"};
    }
    return std::nullopt;
  }
  // Resolves a line by simulation: the stop boundary, the avoidance threshold, then the O/R labels
  // below it sampled every `stride` cells with every change bisected down to adjacent cells.
  void resolve(std::size_t id) {
    Line& line = lines_[id];
    line.resolved = true;
    line.inferred = false;
    if (line.cells.empty()) return;
    stop_threshold(line);
    line.t_a = avoidance_threshold(line);
    if (line.t_a > 0) {
      std::vector<std::size_t> samples;
      for (std::size_t i = line.t_a; i > 0;) {
        i = i > options_.stride ? i - options_.stride : 0;
        samples.push_back(i);
      }
      for (std::size_t i : samples) simulate(line.cells[i]);
      simulate(line.cells[line.t_a - 1]);
      bisect_changes(line, 0, line.t_a);
    }
    if (const auto v = check(line)) return resolve_fully(id, v);
    fill(line);
  }

  // Between two simulated cells of [begin, end) with different labels, simulations halve the gap
  // until the two are neighbours.
  void bisect_changes(const Line& line, std::size_t begin, std::size_t end) {
    bool changed = true;
    while (changed) {
      changed = false;
      std::size_t previous = end;
      for (std::size_t i = begin; i < end; ++i) {
        if (!is_simulated(line.cells[i])) continue;
        if (previous != end && i - previous > 1 &&
            result_.cells[line.cells[i]].region != result_.cells[line.cells[previous]].region) {
          simulate(line.cells[previous + (i - previous) / 2]);
          changed = true;
        }
        previous = i;
      }
    }
  }

  // Gives every unsimulated cell of a resolved line its region: G above the stop boundary, Y up
  // to it from the avoidance threshold, below it the label shared by the simulated cells around it.
  void fill(const Line& line) {
    std::size_t below = kNone;  // last simulated index seen
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      const std::uint32_t cell = line.cells[i];
      if (is_simulated(cell)) {
        below = i;
        continue;
      }
      Cell& c = result_.cells[cell];
      c.from.clear();
      if (i >= line.t_g) {
        c.region = Region::kG;
        c.method = Method::kStop;
        continue;
      }
      c.method = Method::kLine;
      std::size_t above = i + 1;
      while (above < line.cells.size() && !is_simulated(line.cells[above])) ++above;
      if (below != kNone) c.from.push_back(line.cells[below]);
      if (above < line.cells.size() && (i >= line.t_a ? above < line.t_g : above < line.t_a))
        c.from.push_back(line.cells[above]);
      c.region = i >= line.t_a ? Region::kY : result_.cells[line.cells[below]].region;
    }
  }

  // After a contradiction: every cell the analytic stop run does not settle is simulated.
  void resolve_fully(std::size_t id, std::optional<Violation> violation) {
    Line& line = lines_[id];
    line.resolved = true;
    line.inferred = false;
    line.full = true;
    if (violation) {
      line.violated = true;
      std::lock_guard lock(violations_mutex_);
      found_[id] = *violation;
    }
    std::size_t top = line.cells.size();
    while (top > 0 && oracle_.stop(line.cells[top - 1]) == StopCall::kStops) --top;
    for (std::size_t i = 0; i < top; ++i) simulate(line.cells[i]);
    line.t_g = top;
    while (line.t_g > 0 && result_.cells[line.cells[line.t_g - 1]].region == Region::kG) --line.t_g;
    line.t_a = line.t_g;
    while (line.t_a > 0 && avoidable(result_.cells[line.cells[line.t_a - 1]].region)) --line.t_a;
    fill(line);
  }

  // --- boxes --------------------------------------------------------------------------------

  void resolve_corners(const std::vector<Box>& boxes) {
    std::vector<std::size_t> todo;
    std::vector<char> queued(lines_.size(), 0);
    for (const Box& box : boxes)
      for_each_corner(box, [&](std::size_t id) {
        if (lines_[id].resolved || queued[id]) return;
        queued[id] = 1;
        lines_[id].hint = box.hint;
        todo.push_back(id);
      });
    std::vector<std::size_t> full;
    full.swap(full_queue_);
    parallel(todo, [&](std::size_t id) { resolve(id); });
    parallel(full, [&](std::size_t id) { resolve_fully(id, std::nullopt); });
    // Around a contradiction, the neighbouring lines are resolved in full too (next round).
    std::map<std::size_t, Violation> found;
    found.swap(found_);
    for (const auto& [id, violation] : found) {
      result_.violations.push_back(violation);
      const auto p = line_position(id);
      for (std::size_t a = 0; a < 4; ++a)
        for (int d : {-1, 1}) {
          auto q = p;
          if ((d < 0 && q[a] == 0) || (d > 0 && q[a] + 1 >= extent(a))) continue;
          q[a] = static_cast<std::uint32_t>(static_cast<int>(q[a]) + d);
          const std::size_t neighbour = line_id(q);
          if (!lines_[neighbour].full && !scheduled_[neighbour]) {
            scheduled_[neighbour] = 1;
            full_queue_.push_back(neighbour);
          }
        }
    }
  }

  // Whether two settled lines tell the same story: both Y runs or neither, thresholds within the
  // bracket, the same O/R label wherever both have one.
  bool agree(const Line& a, const Line& b) const {
    if (a.violated || b.violated || !a.resolved || !b.resolved) return false;
    const std::uint32_t pa = a.avoid_position(), pb = b.avoid_position();
    if ((pa == kNone) != (pb == kNone)) return false;
    if (pa != kNone && (pa > pb ? pa - pb : pb - pa) > kBracket) return false;
    std::size_t j = 0;
    for (std::size_t i = 0; i < a.t_a; ++i) {
      while (j < b.t_a && b.position[j] < a.position[i]) ++j;
      if (j < b.t_a && b.position[j] == a.position[i] &&
          result_.cells[a.cells[i]].region != result_.cells[b.cells[j]].region)
        return false;
    }
    return true;
  }

  // The corners' common answer, or nothing when some two of them disagree.
  std::optional<Signature> signature(const Box& box) const {
    std::vector<std::size_t> corners;
    for_each_corner(box, [&](std::size_t id) { corners.push_back(id); });
    Signature s;
    for (std::size_t id : corners) {
      const Line& line = lines_[id];
      if (!line.resolved || line.violated) return std::nullopt;
      const std::uint32_t p = line.avoid_position();
      if (id == corners.front()) s.avoid_low = s.avoid_high = p;
      if ((p == kNone) != (s.avoid_low == kNone)) return std::nullopt;
      if (p != kNone) {
        s.avoid_low = std::min(s.avoid_low, p);
        s.avoid_high = std::max(s.avoid_high, p);
      }
      for (std::size_t i = 0; i < line.t_a; ++i) {
        const Region r = result_.cells[line.cells[i]].region;
        const auto [it, inserted] = s.labels.emplace(line.position[i], r);
        if (!inserted && it->second != r) return std::nullopt;
      }
    }
    if (s.avoid_low != kNone && s.avoid_high - s.avoid_low > kBracket) return std::nullopt;
    return s;
  }

  // An inferred line's avoidance threshold: the corners' when they agree exactly, else searched by
  // simulation within their bracket (the line's own stop boundary caps it). Sets line.t_a.
  void bracket_threshold(Line& line, const Signature& s) {
    const auto index_of = [&](std::uint32_t position) {
      return std::min<std::size_t>(line.t_g, static_cast<std::size_t>(std::lower_bound(line.position.begin(),
                                                                                     line.position.end(), position) -
                                                                    line.position.begin()));
    };
    if (s.avoid_low == kNone) {
      line.t_a = line.t_g;
      return;
    }
    const std::size_t lo = index_of(s.avoid_low), hi = index_of(s.avoid_high);
    line.t_a = lo == hi ? lo : threshold(lo, hi, hi, [&](std::size_t i) { return avoidable(simulate(line.cells[i])); });
  }

  // A line's regions as a uniform box's corners imply them, in `out` (one per cell); false when
  // they imply none (unavoidable cells the corners say nothing about) or a simulated cell of the
  // line contradicts them.
  bool infer(const Line& line, const Signature& s, std::vector<Region>& out) const {
    out.assign(line.cells.size(), Region::kG);
    const std::size_t t_a = line.t_a;
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      if (i >= line.t_g) continue;
      if (i >= t_a) {
        out[i] = Region::kY;
        continue;
      }
      if (s.labels.empty()) return false;
      auto it = s.labels.lower_bound(line.position[i]);  // the nearest position a corner labels
      if (it == s.labels.end() || (it->first != line.position[i] && it != s.labels.begin() &&
                                   line.position[i] - std::prev(it)->first <= it->first - line.position[i]))
        it = std::prev(it);
      out[i] = it->second;
    }
    for (std::size_t i = 0; i < line.cells.size(); ++i)
      if (is_simulated(line.cells[i]) && result_.cells[line.cells[i]].region != out[i]) return false;
    return true;
  }

  void commit(std::size_t id, const Box& box, const std::vector<Region>& regions) {
    Line& line = lines_[id];
    line.inferred = true;
    line.t_g = line.cells.size();
    while (line.t_g > 0 && regions[line.t_g - 1] == Region::kG) --line.t_g;
    line.t_a = line.t_g;
    while (line.t_a > 0 && regions[line.t_a - 1] == Region::kY) --line.t_a;
    for (std::size_t i = 0; i < line.cells.size(); ++i) {
      Cell& c = result_.cells[line.cells[i]];
      if (c.method == Method::kSimulated) continue;
      c.region = regions[i];
      c.from.clear();
      if (i >= line.t_g) {
        c.method = Method::kStop;
        continue;
      }
      c.method = Method::kBox;
      for_each_corner(box, [&](std::size_t corner) {  // the corner's cell at this level, or the nearest
        const Line& other = lines_[corner];
        if (other.cells.empty()) return;
        auto at = static_cast<std::size_t>(std::lower_bound(other.position.begin(), other.position.end(),
                                                            line.position[i]) - other.position.begin());
        if (at == other.cells.size() ||
            (at > 0 && line.position[i] - other.position[at - 1] < other.position[at] - line.position[i]))
          --at;
        const Cell& source = result_.cells[other.cells[at]];
        if (source.method == Method::kSimulated)
          c.from.push_back(other.cells[at]);
        else
          c.from.insert(c.from.end(), source.from.begin(), source.from.end());
      });
      std::sort(c.from.begin(), c.from.end());
      c.from.erase(std::unique(c.from.begin(), c.from.end()), c.from.end());
      if (c.from.size() > kMaxFrom) c.from.resize(kMaxFrom);
    }
  }

  // Boxes whose corners agree give their other lines the corners' answer (after simulating the
  // cells of those lines that the stop boundary leaves unsure, which must agree too); the others
  // are split in two along every factor that has lines between its corners.
  std::vector<Box> settle_boxes(const std::vector<Box>& boxes) {
    std::vector<std::optional<Signature>> signatures(boxes.size());
    for (std::size_t b = 0; b < boxes.size(); ++b) signatures[b] = signature(boxes[b]);
    // A line inside a box that will split is left to that box's children.
    std::vector<char> blocked(lines_.size(), 0);
    for (std::size_t b = 0; b < boxes.size(); ++b)
      if (!signatures[b]) for_each_line(boxes[b], [&](std::size_t id) { blocked[id] = 1; });
    std::vector<std::vector<std::size_t>> owned(boxes.size());
    std::vector<std::size_t> candidates;
    std::vector<char> taken(lines_.size(), 0);
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      if (!signatures[b]) continue;
      for_each_line(boxes[b], [&](std::size_t id) {
        if (lines_[id].settled() || blocked[id] || taken[id] || scheduled_[id]) return;
        taken[id] = 1;
        owned[b].push_back(id);
        candidates.push_back(id);
      });
    }
    // Every candidate's own stop boundary, and its avoidance threshold within the corners' bracket,
    // in parallel.
    std::vector<const Signature*> signature_of(lines_.size(), nullptr);
    for (std::size_t b = 0; b < boxes.size(); ++b)
      for (std::size_t id : owned[b]) signature_of[id] = &*signatures[b];
    parallel(candidates, [&](std::size_t id) {
      stop_threshold(lines_[id]);
      bracket_threshold(lines_[id], *signature_of[id]);
    });
    std::vector<Box> next;
    std::vector<Region> regions;
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      bool uniform = signatures[b].has_value();
      std::vector<std::vector<Region>> implied(owned[b].size());
      for (std::size_t k = 0; k < owned[b].size() && uniform; ++k)
        uniform = infer(lines_[owned[b][k]], *signatures[b], implied[k]);
      if (uniform) {
        for (std::size_t k = 0; k < owned[b].size(); ++k) commit(owned[b][k], boxes[b], implied[k]);
        continue;
      }
      split(boxes[b], next);
    }
    return next;
  }

  // Splits a box whose corners disagree across the factors they disagree across: in two halves
  // when there are lines between the corners, into its two faces when there are none. Factors
  // along which every pair of corners agrees stay whole, so a boundary across one factor does not
  // refine the others. Corners that disagree only diagonally split every factor.
  void split(const Box& box, std::vector<Box>& out) const {
    std::array<bool, 4> across{};
    bool any = false;
    for (std::size_t a = 0; a < 4; ++a) {
      if (box.hi[a] == box.lo[a]) continue;
      for_each_corner(box, [&](std::size_t id) {
        auto p = line_position(id);
        if (across[a] || p[a] != box.lo[a]) return;
        p[a] = box.hi[a];
        across[a] = !agree(lines_[id], lines_[line_id(p)]);
      });
      any = any || across[a];
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
    // The children's new lines start their search where the corners' thresholds are.
    std::vector<std::uint32_t> thresholds;
    for_each_corner(box, [&](std::size_t id) {
      if (lines_[id].avoid_position() != kNone) thresholds.push_back(lines_[id].avoid_position());
    });
    std::uint32_t hint = kNone;
    if (!thresholds.empty()) {
      std::nth_element(thresholds.begin(), thresholds.begin() + static_cast<long>(thresholds.size() / 2),
                       thresholds.end());
      hint = thresholds[thresholds.size() / 2];
    }
    for (const auto& h0 : parts[0])
      for (const auto& h1 : parts[1])
        for (const auto& h2 : parts[2])
          for (const auto& h3 : parts[3])
            out.push_back(Box{{h0.first, h1.first, h2.first, h3.first}, {h0.second, h1.second, h2.second, h3.second}, hint});
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
    const std::size_t k = std::min(options_.verify_sample, population.size());
    std::mt19937_64 random(options_.seed);
    for (std::size_t i = 0; i < k; ++i) {  // a partial Fisher-Yates shuffle: the same sample everywhere
      const std::size_t j = i + static_cast<std::size_t>(random() % (population.size() - i));
      std::swap(population[i], population[j]);
    }
    population.resize(k);
    std::sort(population.begin(), population.end());
    std::vector<Region> inferred(k);
    for (std::size_t i = 0; i < k; ++i) inferred[i] = result_.cells[population[i]].region;
    parallel(population, [&](std::uint32_t cell) { simulate(cell); });
    for (std::size_t i = 0; i < k; ++i)
      if (result_.cells[population[i]].region != inferred[i]) result_.verify_disagreements.push_back(population[i]);
    result_.verify_sampled = k;
    result_.disagreement = scenario::wilson_interval(static_cast<double>(result_.verify_disagreements.size()),
                                                     static_cast<double>(k), options_.confidence);
  }

  void finish() {
    result_.simulated = simulated_.load();
    for (const Line& line : lines_) {
      result_.lines_resolved += line.resolved ? 1 : 0;
      result_.lines_inferred += line.inferred ? 1 : 0;
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
  std::array<std::vector<std::size_t>, kAxes> order_;  ///< per factor: sorted position → level index
  std::size_t monotone_ = kTtc;
  std::vector<std::size_t> line_axes_;
  std::vector<Line> lines_;
  Result result_;
  std::atomic<std::size_t> simulated_{0};
  std::mutex violations_mutex_;
  std::map<std::size_t, Violation> found_;  ///< by line, so the order does not depend on threads
  std::vector<std::size_t> full_queue_;
  std::vector<char> scheduled_;  ///< per line: queued for full resolution
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

StopCall stop_call(const sim::SceneConfig& scene, const sim::CellInput& cell) {
  constexpr double kMargin_m = 0.1;  // the simulated stop matches the analytic one within 0.03 m (docs/adaptive.md)
  const double v = cell.speed_kph / 3.6;
  const double margin = v * cell.ttc_s - scene.actuation.stopping_distance_m(v, cell.mu, true);
  if (margin > kMargin_m) return StopCall::kStops;
  if (!(margin < -kMargin_m)) return StopCall::kUnknown;
  // The truck must overlap the car's straight path across the lane from the start (its front,
  // moving down the road, below the car's left side) to the end (its rear, at rest, above the car's
  // right side); a truck that keeps going clears the lane in the end.
  const sim::Scene s(scene, cell);
  const double top = scene.road.ego_lane_center_m + scene.ego.width_m / 2.0;
  const double bottom = scene.road.ego_lane_center_m - scene.ego.width_m / 2.0;
  if (scene.truck.decel_mps2 <= 0.0 && cell.truck_speed_kph > 0.0) return StopCall::kUnknown;
  const double rest_s = scene.truck.decel_mps2 > 0.0 ? cell.truck_speed_kph / 3.6 / scene.truck.decel_mps2 : 0.0;
  const double rear_at_rest = s.truck_front_y_at(rest_s) + scene.truck.length_m;
  constexpr double kOverlap_m = 0.01;  // of the truck and the car's path, for certain
  return s.truck_front_y_at(0.0) < top - kOverlap_m && rear_at_rest > bottom + kOverlap_m ? StopCall::kCannotStop
                                                                                          : StopCall::kUnknown;
}

Result search(const Lattice& lattice, Oracle& oracle, const Options& options) {
  for (const auto& l : lattice.levels)
    if (l.empty()) throw std::invalid_argument("adaptive search: a factor has no level");
  if (options.initial_levels < 2) throw std::invalid_argument("adaptive search: initial_levels must be at least 2");
  if (options.stride < 1) throw std::invalid_argument("adaptive search: stride must be at least 1");
  return Search(lattice, oracle, options).run();
}

}  // namespace emrm::campaign::adaptive
