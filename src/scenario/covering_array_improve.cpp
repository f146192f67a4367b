#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "covering_array_internal.hpp"
#include "emrm/core/random.hpp"

namespace emrm::scenario::detail {
namespace {

// Post-optimisation: delete the row that covers the fewest tuples alone, then repair coverage by a
// tabu search whose moves make a row contain a random uncovered tuple; repeat until a repair fails
// and keep the last complete array. Per tuple the search keeps a cover count and the sum of its
// covering rows' indices (which names the row when the count is 1); per cell the number of tuples
// through it that only its row covers. A move then costs O(t + uncovered tuples) to score and
// O(t-subsets through the changed columns) to make.
class Improver {
 public:
  Improver(const TupleSpace& space, const Feasibility& feasibility, const RowViolates& violates,
           const CoveringArrayOptions& options, std::uint64_t seed)
      : space_(space),
        forbidden_(feasibility.forbidden),
        violates_(violates),
        options_(options),
        rng_(seed),
        t_(static_cast<std::size_t>(space.t())),
        k_(static_cast<std::size_t>(space.columns())),
        incidence_(k_) {
    for (std::size_t combo = 0; combo < space.combo_count(); ++combo) {
      // No array is shorter than the number of required tuples of one t-subset.
      std::size_t required = 0;
      for (std::size_t i = space.offset(combo); i < space.offset(combo) + space.combo_size(combo); ++i)
        required += feasibility.forbidden.test(i) ? 0 : 1;
      lower_bound_ = std::max(lower_bound_, required);
      required_ += required;
      const auto cols = columns_of(combo);
      // Mixed-radix place values of the subset's columns, the last one fastest (as TupleSpace::index).
      std::array<std::size_t, 3> place{};
      std::size_t p = 1;
      for (std::size_t j = t_; j-- > 0;) {
        place[j] = p;
        p *= static_cast<std::size_t>(space.level(static_cast<int>(cols[j])));
      }
      for (std::size_t j = 0; j < t_; ++j) {
        Incidence inc{space.offset(combo), {}, {}, place[j]};
        for (std::size_t o = 0, m = 0; o < t_; ++o) {
          if (o == j) continue;
          inc.other_col[m] = cols[o];
          inc.other_place[m++] = place[o];
        }
        if (t_ == 2) inc.other_col[1] = inc.other_col[0];  // with place 0 it adds nothing
        incidence_[cols[j]].push_back(inc);
      }
    }
    patience_ = std::llround(options.improvement_effort * static_cast<double>(required_));
  }

  // `rows` is a complete array whose first `seeds` rows are the seed rows.
  std::vector<Row> improve(std::vector<Row> rows, std::size_t seeds) {
    if (patience_ == 0 || rows.size() <= lower_bound_ || space_.total() >= kNone) return rows;
    load(rows, seeds);
    std::int64_t moves_left = options_.improvement_max_moves;
    while (rows_ > lower_bound_ && rows_ > seeds_ && moves_left > 0) {
      remove_row();
      if (!repair(moves_left)) break;
      rows = to_rows();
    }
    return rows;
  }

 private:
  // A t-subset seen from one of its columns: tuple index = offset + sum of value * place.
  struct Incidence {
    std::size_t offset;
    std::array<std::size_t, 2> other_col;
    std::array<std::size_t, 2> other_place;
    std::size_t self_place;
  };
  struct Missing {  // an uncovered required tuple
    std::size_t tuple;
    std::array<std::size_t, 3> cols;
    std::array<int, 3> values;
  };
  struct Move {  // row `row` takes values[j] in column cols[j], j < changes
    std::size_t row = 0;
    std::size_t changes = 0;
    std::array<std::size_t, 3> cols{};
    std::array<int, 3> values{};
    std::array<std::size_t, 3> target_index{};  // which column of the target tuple cols[j] is
  };
  struct Choice {  // the best moves seen so far in a step
    std::int64_t delta = std::numeric_limits<std::int64_t>::max();
    std::vector<Move> moves;
  };

  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // A cell changed by the previous move may not change again unless that beats the best count;
  // longer tenures searched less well on the reference models.
  static constexpr std::int64_t kTabuTenure = 1;

  void load(const std::vector<Row>& rows, std::size_t seeds) {
    seeds_ = seeds;
    rows_ = rows.size();
    stride_ = rows.size();
    cells_.clear();
    for (const Row& r : rows) cells_.insert(cells_.end(), r.begin(), r.end());
    by_column_.resize(k_ * stride_);
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t c = 0; c < k_; ++c) by_column_[c * stride_ + r] = cell(r, c);
    matches_.assign(stride_, 0);
    count_.assign(space_.total(), 0);
    owner_sum_.assign(space_.total(), 0);
    position_.assign(space_.total(), kNone);
    unique_.assign(cells_.size(), 0);
    missing_.clear();
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t combo = 0; combo < space_.combo_count(); ++combo) {
        const std::size_t i = space_.index(combo, row(r));
        ++count_[i];
        owner_sum_[i] += static_cast<std::uint32_t>(r);
      }
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t combo = 0; combo < space_.combo_count(); ++combo)
        if (count_[space_.index(combo, row(r))] == 1) add_unique(r, columns_of(combo), +1);
  }

  [[nodiscard]] std::vector<Row> to_rows() const {
    std::vector<Row> out(rows_);
    for (std::size_t r = 0; r < rows_; ++r)
      out[r].assign(cells_.begin() + static_cast<std::ptrdiff_t>(r * k_),
                    cells_.begin() + static_cast<std::ptrdiff_t>((r + 1) * k_));
    return out;
  }

  [[nodiscard]] std::array<std::size_t, 3> columns_of(std::size_t combo) const {
    const auto& c = space_.combo(combo);
    return {static_cast<std::size_t>(c[0]), static_cast<std::size_t>(c[1]), static_cast<std::size_t>(c[2])};
  }
  [[nodiscard]] std::span<int> row(std::size_t r) { return {cells_.data() + r * k_, k_}; }
  [[nodiscard]] int& cell(std::size_t r, std::size_t c) { return cells_[r * k_ + c]; }
  [[nodiscard]] bool forced(std::size_t r, std::size_t c) const {
    return r < seeds_ && options_.seed_rows[r][c] != kDontCare;
  }

  void add_unique(std::size_t r, const std::array<std::size_t, 3>& cols, int delta) {
    for (std::size_t j = 0; j < t_; ++j) {
      auto& u = unique_[r * k_ + cols[j]];
      u = delta > 0 ? u + 1 : u - 1;
    }
  }

  void add_missing(std::size_t tuple) {
    const std::size_t combo = space_.combo_of_tuple(tuple);
    Missing m{tuple, columns_of(combo), {}};
    std::size_t local = tuple - space_.offset(combo);
    for (std::size_t j = t_; j-- > 0;) {
      const auto levels = static_cast<std::size_t>(space_.level(static_cast<int>(m.cols[j])));
      m.values[j] = static_cast<int>(local % levels);
      local /= levels;
    }
    position_[tuple] = static_cast<std::uint32_t>(missing_.size());
    missing_.push_back(m);
  }
  void remove_missing(std::size_t tuple) {
    const std::uint32_t at = position_[tuple];
    missing_[at] = missing_.back();
    position_[missing_[at].tuple] = at;
    missing_.pop_back();
    position_[tuple] = kNone;
  }

  // Row r stops or starts containing `tuple` of the t-subset on `cols`. (Valid rows never contain
  // forbidden tuples; the checks only keep them out of missing_ whatever a constraint answers.)
  void lose(std::size_t tuple, const std::array<std::size_t, 3>& cols, std::size_t r) {
    owner_sum_[tuple] -= static_cast<std::uint32_t>(r);
    if (--count_[tuple] == 0) {
      add_unique(r, cols, -1);
      if (!forbidden_.test(tuple)) add_missing(tuple);
    } else if (count_[tuple] == 1) {
      add_unique(owner_sum_[tuple], cols, +1);
    }
  }
  void gain(std::size_t tuple, const std::array<std::size_t, 3>& cols, std::size_t r) {
    if (count_[tuple] == 0) {
      if (position_[tuple] != kNone) remove_missing(tuple);
      add_unique(r, cols, +1);
    } else if (count_[tuple] == 1) {
      add_unique(owner_sum_[tuple], cols, -1);
    }
    ++count_[tuple];
    owner_sum_[tuple] += static_cast<std::uint32_t>(r);
  }

  void set_cell(std::size_t r, std::size_t c, int v) {
    const std::span<int> values = row(r);
    const auto old_value = static_cast<std::size_t>(values[c]);
    const auto new_value = static_cast<std::size_t>(v);
    for (const Incidence& inc : incidence_[c]) {
      const std::size_t base = inc.offset + static_cast<std::size_t>(values[inc.other_col[0]]) * inc.other_place[0] +
                               static_cast<std::size_t>(values[inc.other_col[1]]) * inc.other_place[1];
      const std::array<std::size_t, 3> cols{c, inc.other_col[0], inc.other_col[1]};
      lose(base + old_value * inc.self_place, cols, r);
      gain(base + new_value * inc.self_place, cols, r);
    }
    values[c] = v;
    by_column_[c * stride_ + r] = v;
    changed_at_[r * k_ + c] = iteration_;
  }

  // Drops the non-seed row covering the fewest tuples alone; the last row takes its place.
  void remove_row() {
    std::size_t victim = seeds_;
    std::size_t fewest = std::numeric_limits<std::size_t>::max();
    std::size_t ties = 0;
    for (std::size_t r = seeds_; r < rows_; ++r) {
      std::size_t alone = 0;  // t times the tuples only r covers
      for (std::size_t c = 0; c < k_; ++c) alone += unique_[r * k_ + c];
      if (alone < fewest) {
        fewest = alone;
        victim = r;
        ties = 1;
      } else if (alone == fewest && core::index_below(rng_, ++ties) == 0) {
        victim = r;
      }
    }
    for (std::size_t combo = 0; combo < space_.combo_count(); ++combo)
      lose(space_.index(combo, row(victim)), columns_of(combo), victim);
    const std::size_t last = rows_ - 1;
    if (victim != last) {
      for (std::size_t c = 0; c < k_; ++c) {
        cell(victim, c) = cell(last, c);
        unique_[victim * k_ + c] = unique_[last * k_ + c];
        by_column_[c * stride_ + victim] = cell(last, c);
      }
      for (std::size_t combo = 0; combo < space_.combo_count(); ++combo)
        owner_sum_[space_.index(combo, row(victim))] += static_cast<std::uint32_t>(victim - last);
    }
    --rows_;
    cells_.resize(rows_ * k_);
    unique_.resize(rows_ * k_);
  }

  // Tabu search until every required tuple is covered; false once the patience or budget is spent.
  bool repair(std::int64_t& moves_left) {
    changed_at_.assign(cells_.size(), std::numeric_limits<std::int64_t>::min() / 2);
    std::size_t best = missing_.size();
    std::int64_t since_best = 0;
    while (!missing_.empty()) {
      if (moves_left <= 0 || since_best >= patience_) return false;
      --moves_left;
      ++iteration_;
      step(best);
      if (missing_.size() < best) {
        best = missing_.size();
        since_best = 0;
      } else {
        ++since_best;
      }
    }
    return true;
  }

  // One move toward a random uncovered tuple. Rows one cell away from it are tried first; rows
  // that need more changes only when none of those keeps the count of uncovered tuples. A move
  // leaving the fewest tuples uncovered is made (ties at random), except that a move changing a
  // cell the previous move changed must beat this repair's best count (tabu). If every move is
  // tabu, forced or breaks a constraint, nothing changes.
  void step(std::size_t best) {
    const Missing target = missing_[core::index_below(rng_, missing_.size())];
    std::fill_n(matches_.begin(), rows_, std::uint8_t{0});
    for (std::size_t j = 0; j < t_; ++j) {
      const int* column = by_column_.data() + target.cols[j] * stride_;
      const int value = target.values[j];
      for (std::size_t r = 0; r < rows_; ++r)
        matches_[r] = static_cast<std::uint8_t>(matches_[r] + (column[r] == value ? 1 : 0));
    }
    // A move can only newly cover uncovered tuples through the columns it changes.
    for (std::size_t j = 0; j < t_; ++j) {
      through_[j].clear();
      for (const Missing& m : missing_)
        if (std::find(m.cols.begin(), m.cols.begin() + static_cast<std::ptrdiff_t>(t_), target.cols[j]) !=
            m.cols.begin() + static_cast<std::ptrdiff_t>(t_))
          through_[j].push_back(m);
    }
    collect(target, best, false);
    if (violates_) {
      // Constraints can be slow to evaluate: try the best moves in random order and validate the
      // whole neighbourhood only when none of them is valid.
      while (!choice_.moves.empty()) {
        const std::size_t i = core::index_below(rng_, choice_.moves.size());
        if (valid_after(choice_.moves[i])) return make(choice_.moves[i]);
        choice_.moves[i] = choice_.moves.back();
        choice_.moves.pop_back();
      }
      collect(target, best, true);
    }
    if (!choice_.moves.empty()) make(choice_.moves[core::index_below(rng_, choice_.moves.size())]);
  }

  void make(const Move& move) {
    for (std::size_t j = 0; j < move.changes; ++j) set_cell(move.row, move.cols[j], move.values[j]);
  }

  // Gathers in choice_ the best moves for `target`, with valid rows only if `check_validity`.
  void collect(const Missing& target, std::size_t best, bool check_validity) {
    choice_.delta = std::numeric_limits<std::int64_t>::max();
    choice_.moves.clear();
    consider(target, best, true, check_validity);
    if (choice_.moves.empty() || choice_.delta > 0) consider(target, best, false, check_validity);
  }

  // Scores the moves of rows one cell away from `target` (or of the other rows) into choice_.
  void consider(const Missing& target, std::size_t best, bool one_away, bool check_validity) {
    const auto uncovered = static_cast<std::int64_t>(missing_.size());
    for (std::size_t r = 0; r < rows_; ++r) {
      if ((static_cast<std::size_t>(matches_[r]) + 1 == t_) != one_away) continue;
      Move move;
      move.row = r;
      bool blocked = false;
      bool tabu = false;
      for (std::size_t j = 0; j < t_; ++j) {
        const std::size_t c = target.cols[j];
        if (cell(r, c) == target.values[j]) continue;
        blocked = blocked || forced(r, c);
        tabu = tabu || iteration_ - changed_at_[r * k_ + c] <= kTabuTenure;
        move.cols[move.changes] = c;
        move.target_index[move.changes] = j;
        move.values[move.changes++] = target.values[j];
      }
      if (blocked) continue;
      const auto delta = score(move, choice_.delta);
      if (!delta || *delta > choice_.delta) continue;
      if (tabu && uncovered + *delta >= static_cast<std::int64_t>(best)) continue;
      if (check_validity && !valid_after(move)) continue;
      if (*delta < choice_.delta) {
        choice_.delta = *delta;
        choice_.moves.clear();
      }
      choice_.moves.push_back(move);
    }
  }

  // Change in the number of uncovered tuples if `move` were made: the tuples through a changed
  // column that only this row covers are lost, the uncovered tuples the new row contains are
  // gained. Nothing when the change is sure to be worse than `bound`.
  std::optional<std::int64_t> score(const Move& move, std::int64_t bound) {
    const std::size_t r = move.row;
    std::int64_t lost_at_least = 0;
    std::int64_t lost_sum = 0;
    for (std::size_t j = 0; j < move.changes; ++j) {
      const auto u = static_cast<std::int64_t>(unique_[r * k_ + move.cols[j]]);
      lost_at_least = std::max(lost_at_least, u);
      lost_sum += u;
    }
    std::size_t gainable = 0;
    for (std::size_t j = 0; j < move.changes; ++j) gainable += through_[move.target_index[j]].size();
    if (lost_at_least - static_cast<std::int64_t>(gainable) > bound) return std::nullopt;
    std::array<int, 3> old_values{};
    for (std::size_t j = 0; j < move.changes; ++j) old_values[j] = std::exchange(cell(r, move.cols[j]), move.values[j]);
    const std::int64_t gained = uncovered_in_row(move);
    for (std::size_t j = 0; j < move.changes; ++j) cell(r, move.cols[j]) = old_values[j];
    if (lost_at_least - gained > bound) return std::nullopt;
    // lost_sum counted a tuple once per changed column through it; each must count once.
    std::int64_t overcount = 0;
    for (std::size_t a = 0; a < move.changes; ++a)
      for (std::size_t b = a + 1; b < move.changes; ++b) {
        const std::size_t ca = std::min(move.cols[a], move.cols[b]);
        const std::size_t cb = std::max(move.cols[a], move.cols[b]);
        if (t_ == 2) {
          overcount += only_row_covers(r, {ca, cb, 0}) ? 1 : 0;
          continue;
        }
        for (std::size_t x = 0; x < k_; ++x) {
          if (x == ca || x == cb) continue;
          std::array<std::size_t, 3> cols{ca, cb, x};
          std::sort(cols.begin(), cols.end());
          overcount += only_row_covers(r, cols) ? 1 : 0;
        }
      }
    if (move.changes == 3) {  // met from each of its three pairs above, but needs only two
      std::array<std::size_t, 3> cols = move.cols;
      std::sort(cols.begin(), cols.end());
      overcount -= only_row_covers(r, cols) ? 1 : 0;
    }
    return lost_sum - overcount - gained;
  }

  // Uncovered tuples that row `move.row`, already holding the move's values, contains: by looking
  // through the uncovered tuples through the changed columns or through the t-subsets through
  // them, whichever is fewer.
  [[nodiscard]] std::int64_t uncovered_in_row(const Move& move) {
    const std::size_t r = move.row;
    std::int64_t n = 0;
    std::size_t listed = 0;
    for (std::size_t a = 0; a < move.changes; ++a) listed += through_[move.target_index[a]].size();
    if (listed * t_ <= move.changes * incidence_[move.cols[0]].size()) {
      for (std::size_t a = 0; a < move.changes; ++a)
        for (const Missing& m : through_[move.target_index[a]]) {
          bool contained = true;
          for (std::size_t j = 0; j < t_ && contained; ++j) {
            // Counted already from an earlier changed column through it?
            for (std::size_t b = 0; b < a && contained; ++b) contained = m.cols[j] != move.cols[b];
            contained = contained && cell(r, m.cols[j]) == m.values[j];
          }
          n += contained ? 1 : 0;
        }
      return n;
    }
    const std::span<int> values = row(r);
    for (std::size_t a = 0; a < move.changes; ++a)
      for (const Incidence& inc : incidence_[move.cols[a]]) {
        bool seen = false;  // the subset also passes through an earlier changed column
        for (std::size_t b = 0; b < a; ++b)
          seen = seen || inc.other_col[0] == move.cols[b] || inc.other_col[1] == move.cols[b];
        if (seen) continue;
        const std::size_t i = inc.offset + static_cast<std::size_t>(values[inc.other_col[0]]) * inc.other_place[0] +
                              static_cast<std::size_t>(values[inc.other_col[1]]) * inc.other_place[1] +
                              static_cast<std::size_t>(values[move.cols[a]]) * inc.self_place;
        n += position_[i] != kNone ? 1 : 0;
      }
    return n;
  }

  // Whether row r alone contains its tuple of the t-subset on the sorted columns `cols`.
  [[nodiscard]] bool only_row_covers(std::size_t r, const std::array<std::size_t, 3>& cols) {
    const std::size_t combo =
        space_.combo_index(static_cast<int>(cols[0]), static_cast<int>(cols[1]), static_cast<int>(cols[2]));
    return count_[space_.index(combo, row(r))] == 1;
  }

  [[nodiscard]] bool valid_after(const Move& move) {
    if (!violates_) return true;
    std::array<int, 3> old_values{};
    for (std::size_t j = 0; j < move.changes; ++j)
      old_values[j] = std::exchange(cell(move.row, move.cols[j]), move.values[j]);
    const bool ok = !violates_(row(move.row));
    for (std::size_t j = 0; j < move.changes; ++j) cell(move.row, move.cols[j]) = old_values[j];
    return ok;
  }

  const TupleSpace& space_;
  const Bitset& forbidden_;  // tuples no valid row contains
  const RowViolates& violates_;
  const CoveringArrayOptions& options_;
  core::SplitMix64 rng_;
  std::size_t t_;
  std::size_t k_;
  std::vector<std::vector<Incidence>> incidence_;  // per column, the t-subsets through it
  std::size_t lower_bound_ = 0;
  std::size_t required_ = 0;   // required tuples
  std::int64_t patience_ = 0;  // moves without a new best before a repair gives up
  std::size_t seeds_ = 0;
  std::size_t rows_ = 0;
  std::size_t stride_ = 0;                // rows the column-major copy has room for
  std::vector<int> cells_;                // row-major, rows_ x k_
  std::vector<int> by_column_;            // column-major copy, for scanning a column
  std::vector<std::uint8_t> matches_;     // per row, cells equal to the current target tuple
  std::vector<std::uint32_t> count_;      // per tuple, rows containing it
  std::vector<std::uint32_t> owner_sum_;  // per tuple, sum of those rows' indices (mod 2^32)
  std::vector<std::uint32_t> position_;   // per tuple, its index in missing_, or kNone
  std::vector<std::uint32_t> unique_;     // per cell, tuples through it that only its row covers
  std::vector<Missing> missing_;          // uncovered required tuples, in no particular order
  std::vector<std::int64_t> changed_at_;  // per cell, the move that last changed it
  std::int64_t iteration_ = 0;
  Choice choice_;
  std::array<std::vector<Missing>, 3> through_;  // per column of the target, uncovered tuples through it
};

}  // namespace

std::vector<Row> remove_rows(const TupleSpace& space, const Feasibility& feasibility, const RowViolates& violates,
                             const CoveringArrayOptions& options, std::uint64_t seed, std::vector<Row> rows,
                             std::size_t seeds) {
  Improver improver(space, feasibility, violates, options, seed);
  return improver.improve(std::move(rows), seeds);
}

}  // namespace emrm::scenario::detail
