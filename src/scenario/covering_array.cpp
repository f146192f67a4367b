#include "emrm/scenario/covering_array.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace emrm::scenario {
namespace {

using Row = std::vector<int>;

// Portable, seedable randomness: std distributions differ between standard libraries, and the
// same seed must give the same array everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
  template <class T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(i)]);
  }

 private:
  std::uint64_t state_;
};

// Every t-subset of columns ("combo") owns a contiguous block of tuple indices, so coverage is one
// bitset over all t-tuples and a tuple's index is a few multiplications.
class TupleSpace {
 public:
  TupleSpace(const std::vector<int>& levels, int t)
      : t_(t), n_(static_cast<int>(levels.size())), levels_(levels) {
    const std::size_t n = levels.size();
    combo_of_.assign(t == 2 ? n * n : n * n * n, -1);
    auto add = [&](std::array<int, 3> cols) {
      std::size_t size = 1;
      for (int i = 0; i < t; ++i) size *= static_cast<std::size_t>(levels[static_cast<std::size_t>(cols[i])]);
      combo_of_[key(cols[0], cols[1], cols[2])] = static_cast<int>(combos_.size());
      combos_.push_back(cols);
      offset_.push_back(total_);
      total_ += size;
    };
    for (int a = 0; a < n_; ++a)
      for (int b = a + 1; b < n_; ++b) {
        if (t == 2) {
          add({a, b, 0});
        } else {
          for (int c = b + 1; c < n_; ++c) add({a, b, c});
        }
      }
  }

  [[nodiscard]] int t() const { return t_; }
  [[nodiscard]] int columns() const { return n_; }
  [[nodiscard]] int level(int col) const { return levels_[static_cast<std::size_t>(col)]; }
  [[nodiscard]] std::size_t total() const { return total_; }
  [[nodiscard]] std::size_t combo_count() const { return combos_.size(); }
  [[nodiscard]] const std::array<int, 3>& combo(std::size_t k) const { return combos_[k]; }
  [[nodiscard]] std::size_t combo_size(std::size_t k) const {
    return (k + 1 < combos_.size() ? offset_[k + 1] : total_) - offset_[k];
  }
  [[nodiscard]] std::size_t offset(std::size_t k) const { return offset_[k]; }
  // Combo owning tuple `i`.
  [[nodiscard]] std::size_t combo_of_tuple(std::size_t i) const {
    return static_cast<std::size_t>(std::upper_bound(offset_.begin(), offset_.end(), i) - offset_.begin()) -
           1;
  }

  // Combo of columns a < b (< c).
  [[nodiscard]] std::size_t combo_index(int a, int b, int c = 0) const {
    return static_cast<std::size_t>(combo_of_[key(a, b, c)]);
  }
  // Index of the tuple of combo k whose values are taken from `row`.
  [[nodiscard]] std::size_t index(std::size_t k, std::span<const int> row) const {
    const auto& c = combos_[k];
    std::size_t i = static_cast<std::size_t>(row[static_cast<std::size_t>(c[0])]);
    for (int j = 1; j < t_; ++j)
      i = i * static_cast<std::size_t>(level(c[static_cast<std::size_t>(j)])) +
          static_cast<std::size_t>(row[static_cast<std::size_t>(c[static_cast<std::size_t>(j)])]);
    return offset_[k] + i;
  }
  // Writes the values of tuple `i` of combo k into `row`.
  void decode(std::size_t k, std::size_t i, std::span<int> row) const {
    std::size_t local = i - offset_[k];
    const auto& c = combos_[k];
    for (int j = t_ - 1; j >= 0; --j) {
      const auto col = static_cast<std::size_t>(c[static_cast<std::size_t>(j)]);
      const auto l = static_cast<std::size_t>(levels_[col]);
      row[col] = static_cast<int>(local % l);
      local /= l;
    }
  }
  // Calls f(tuple index) for every t-tuple of a complete row.
  template <class F>
  void for_each_tuple(std::span<const int> row, F&& f) const {
    for (std::size_t k = 0; k < combos_.size(); ++k) f(index(k, row));
  }

 private:
  [[nodiscard]] std::size_t key(int a, int b, int c) const {
    const auto n = static_cast<std::size_t>(n_);
    const auto base = static_cast<std::size_t>(a) * n + static_cast<std::size_t>(b);
    return t_ == 2 ? base : base * n + static_cast<std::size_t>(c);
  }

  int t_;
  int n_;
  std::vector<int> levels_;
  std::vector<std::array<int, 3>> combos_;
  std::vector<std::size_t> offset_;
  std::vector<int> combo_of_;
  std::size_t total_ = 0;
};

class Bitset {
 public:
  explicit Bitset(std::size_t n) : words_((n + 63) / 64, 0) {}
  [[nodiscard]] bool test(std::size_t i) const { return (words_[i >> 6] >> (i & 63)) & 1U; }
  void set(std::size_t i) { words_[i >> 6] |= std::uint64_t{1} << (i & 63); }

 private:
  std::vector<std::uint64_t> words_;
};

bool complete_from(const std::vector<int>& levels, Row& row, std::size_t from, const RowViolates& violates) {
  if (violates && violates(row)) return false;
  while (from < row.size() && row[from] != kDontCare) ++from;
  if (from == row.size()) return true;
  for (int v = 0; v < levels[from]; ++v) {
    row[from] = v;
    if (complete_from(levels, row, from + 1, violates)) return true;
  }
  row[from] = kDontCare;
  return false;
}

// Which tuples no valid row contains. A witness row found for one tuple proves all its tuples
// feasible, so the (exponential) completion search runs for few tuples.
struct Feasibility {
  Bitset forbidden;
  std::size_t forbidden_count = 0;
};

Feasibility find_forbidden(const TupleSpace& space, const std::vector<int>& levels,
                           const RowViolates& violates) {
  Feasibility f{Bitset(space.total()), 0};
  if (!violates) return f;
  Bitset feasible(space.total());
  auto mark_feasible = [&](const Row& r) {
    space.for_each_tuple(r, [&](std::size_t i) { feasible.set(i); });
  };
  auto any = complete_row(levels, Row(levels.size(), kDontCare), violates);
  if (!any) throw std::domain_error("the constraints exclude every row");
  mark_feasible(*any);
  Row partial(levels.size(), kDontCare);
  for (std::size_t k = 0; k < space.combo_count(); ++k)
    for (std::size_t i = space.offset(k); i < space.offset(k) + space.combo_size(k); ++i) {
      if (feasible.test(i)) continue;
      std::fill(partial.begin(), partial.end(), kDontCare);
      space.decode(k, i, partial);
      std::optional<Row> witness;
      if (!violates(partial)) witness = complete_row(levels, partial, violates);
      if (witness) {
        mark_feasible(*witness);
      } else {
        f.forbidden.set(i);
        ++f.forbidden_count;
      }
    }
  return f;
}

// One greedy construction of a whole array.
class Builder {
 public:
  Builder(const TupleSpace& space, const Feasibility& feasibility, const RowViolates& violates,
          const CoveringArrayOptions& options, std::uint64_t seed)
      : space_(space),
        violates_(violates),
        options_(options),
        rng_(seed),
        covered_(feasibility.forbidden),
        uncovered_in_combo_(space.combo_count(), 0) {
    const int n = space.columns();
    value_base_.resize(static_cast<std::size_t>(n) + 1, 0);
    for (int c = 0; c < n; ++c)
      value_base_[static_cast<std::size_t>(c) + 1] =
          value_base_[static_cast<std::size_t>(c)] + space.level(c);
    value_uncovered_.assign(static_cast<std::size_t>(value_base_.back()) * static_cast<std::size_t>(n), 0);
    Row row(static_cast<std::size_t>(n), 0);
    for (std::size_t k = 0; k < space.combo_count(); ++k)
      for (std::size_t i = space.offset(k); i < space.offset(k) + space.combo_size(k); ++i) {
        if (covered_.test(i)) continue;
        ++uncovered_in_combo_[k];
        ++uncovered_;
        space.decode(k, i, row);
        count_value_pairs(k, row, +1);
      }
  }

  std::vector<Row> build() {
    for (const Row& seed : options_.seed_rows) commit(fill_seed(seed));
    const std::size_t seeds = rows_.size();
    while (uncovered_ > 0) {
      Row best;
      std::size_t best_gain = 0;
      for (int c = 0; c < options_.candidates_per_row; ++c) {
        std::size_t gain = 0;
        Row row = candidate(gain);
        if (gain > best_gain) {
          best_gain = gain;
          best = std::move(row);
        }
      }
      commit(best);
    }
    if (options_.remove_redundant_rows) remove_redundant(seeds);
    return std::move(rows_);
  }

 private:
  // Uncovered tuples that (col, v) forms with the columns already assigned in `row`; with t = 2,
  // also the density of what it could still cover with the unassigned columns (DDA's tie-break).
  double score(Row& row, const std::vector<int>& assigned, int col, int v, std::size_t& gain) const {
    const auto c = static_cast<std::size_t>(col);
    row[c] = v;
    gain = 0;
    if (space_.t() == 2) {
      for (int a : assigned) {
        const auto k = a < col ? space_.combo_index(a, col) : space_.combo_index(col, a);
        if (!covered_.test(space_.index(k, row))) ++gain;
      }
    } else {
      for (std::size_t i = 0; i < assigned.size(); ++i)
        for (std::size_t j = i + 1; j < assigned.size(); ++j) {
          std::array<int, 3> cols{assigned[i], assigned[j], col};
          std::sort(cols.begin(), cols.end());
          if (!covered_.test(space_.index(space_.combo_index(cols[0], cols[1], cols[2]), row))) ++gain;
        }
    }
    row[c] = kDontCare;
    double density = 0.0;
    const auto vi = static_cast<std::size_t>(value_base_[c] + v) * static_cast<std::size_t>(space_.columns());
    for (int j = 0; j < space_.columns(); ++j)
      if (row[static_cast<std::size_t>(j)] == kDontCare && j != col)
        density += value_uncovered_[vi + static_cast<std::size_t>(j)] / static_cast<double>(space_.level(j));
    return static_cast<double>(gain) + kDensityWeight * density;
  }

  // Assigns `col` the best-scoring value that keeps the row completable; returns its gain.
  std::size_t assign_best(Row& row, std::vector<int>& assigned, int col) {
    const int levels = space_.level(col);
    std::vector<std::pair<double, int>> order;
    order.reserve(static_cast<std::size_t>(levels));
    std::vector<std::size_t> gains(static_cast<std::size_t>(levels));
    for (int v = 0; v < levels; ++v) {
      // A random fraction below the smallest score step breaks ties without changing the order.
      const double s = score(row, assigned, col, v, gains[static_cast<std::size_t>(v)]);
      order.emplace_back(s + 1e-6 * static_cast<double>(rng_.below(1000)), v);
    }
    std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    const auto c = static_cast<std::size_t>(col);
    for (const auto& [s, v] : order) {
      row[c] = v;
      if (!violates_ || complete_row(levels_of_space(), row, violates_)) {
        assigned.push_back(col);
        return gains[static_cast<std::size_t>(v)];
      }
    }
    // Unreachable: the row was completable before this column was assigned.
    row[c] = kDontCare;
    throw std::logic_error("covering array: no completable value");
  }

  std::vector<int> levels_of_space() const {
    std::vector<int> l(static_cast<std::size_t>(space_.columns()));
    for (int c = 0; c < space_.columns(); ++c) l[static_cast<std::size_t>(c)] = space_.level(c);
    return l;
  }

  Row candidate(std::size_t& gain) {
    // Start from an uncovered tuple of a combo with the most uncovered tuples (random among ties).
    std::size_t best_k = 0;
    std::size_t ties = 0;
    int most = 0;
    for (std::size_t k = 0; k < space_.combo_count(); ++k) {
      const int u = uncovered_in_combo_[k];
      if (u > most) {
        most = u;
        best_k = k;
        ties = 1;
      } else if (u == most && u > 0 && rng_.below(++ties) == 0) {
        best_k = k;
      }
    }
    std::size_t pick = 0;
    std::size_t seen = 0;
    for (std::size_t i = space_.offset(best_k); i < space_.offset(best_k) + space_.combo_size(best_k); ++i)
      if (!covered_.test(i) && rng_.below(++seen) == 0) pick = i;
    Row row(static_cast<std::size_t>(space_.columns()), kDontCare);
    space_.decode(best_k, pick, row);
    std::vector<int> assigned;
    std::vector<int> rest;
    const auto& cols = space_.combo(best_k);
    for (int c = 0; c < space_.columns(); ++c) {
      if (std::find(cols.begin(), cols.begin() + space_.t(), c) != cols.begin() + space_.t()) {
        assigned.push_back(c);
      } else {
        rest.push_back(c);
      }
    }
    rng_.shuffle(rest);
    gain = 1;
    for (int c : rest) gain += assign_best(row, assigned, c);
    return row;
  }

  Row fill_seed(const Row& seed) {
    Row row = seed;
    if (violates_ && !complete_row(levels_of_space(), row, violates_))
      throw std::domain_error("a seed row cannot be completed without breaking a constraint");
    std::vector<int> assigned;
    for (int c = 0; c < space_.columns(); ++c)
      if (row[static_cast<std::size_t>(c)] != kDontCare) assigned.push_back(c);
    for (int c = 0; c < space_.columns(); ++c)
      if (row[static_cast<std::size_t>(c)] == kDontCare) assign_best(row, assigned, c);
    return row;
  }

  void count_value_pairs(std::size_t k, const Row& row, int delta) {
    const auto& cols = space_.combo(k);
    const auto n = static_cast<std::size_t>(space_.columns());
    for (int i = 0; i < space_.t(); ++i)
      for (int j = 0; j < space_.t(); ++j) {
        if (i == j) continue;
        const auto ci = static_cast<std::size_t>(cols[static_cast<std::size_t>(i)]);
        const auto cj = static_cast<std::size_t>(cols[static_cast<std::size_t>(j)]);
        value_uncovered_[static_cast<std::size_t>(value_base_[ci] + row[ci]) * n + cj] += delta;
      }
  }

  void commit(const Row& row) {
    for (std::size_t k = 0; k < space_.combo_count(); ++k) {
      const std::size_t i = space_.index(k, row);
      if (covered_.test(i)) continue;
      covered_.set(i);
      --uncovered_in_combo_[k];
      --uncovered_;
      count_value_pairs(k, row, -1);
    }
    rows_.push_back(row);
  }

  // Greedy leaves early rows whose tuples later rows happen to repeat; drop them, last first.
  void remove_redundant(std::size_t seeds) {
    std::vector<std::uint32_t> count(space_.total(), 0);
    for (const Row& r : rows_) space_.for_each_tuple(r, [&](std::size_t i) { ++count[i]; });
    for (std::size_t r = rows_.size(); r-- > seeds;) {
      bool redundant = true;
      space_.for_each_tuple(rows_[r], [&](std::size_t i) { redundant = redundant && count[i] >= 2; });
      if (!redundant) continue;
      space_.for_each_tuple(rows_[r], [&](std::size_t i) { --count[i]; });
      rows_.erase(rows_.begin() + static_cast<std::ptrdiff_t>(r));
    }
  }

  static constexpr double kDensityWeight = 0.1;

  const TupleSpace& space_;
  const RowViolates& violates_;
  const CoveringArrayOptions& options_;
  Rng rng_;
  Bitset covered_;  // covered, or forbidden (never required)
  std::vector<int> uncovered_in_combo_;
  std::size_t uncovered_ = 0;
  std::vector<int> value_base_;
  // Uncovered tuples containing value (c, v) and any value of column j, at [(base[c]+v)*n + j].
  std::vector<int> value_uncovered_;
  std::vector<Row> rows_;
};

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
      const std::size_t base = inc.offset +
                               static_cast<std::size_t>(values[inc.other_col[0]]) * inc.other_place[0] +
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
      } else if (alone == fewest && rng_.below(++ties) == 0) {
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
    const Missing target = missing_[rng_.below(missing_.size())];
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
        const std::size_t i = rng_.below(choice_.moves.size());
        if (valid_after(choice_.moves[i])) return make(choice_.moves[i]);
        choice_.moves[i] = choice_.moves.back();
        choice_.moves.pop_back();
      }
      collect(target, best, true);
    }
    if (!choice_.moves.empty()) make(choice_.moves[rng_.below(choice_.moves.size())]);
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
    for (std::size_t j = 0; j < move.changes; ++j)
      old_values[j] = std::exchange(cell(r, move.cols[j]), move.values[j]);
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
        const std::size_t i = inc.offset +
                              static_cast<std::size_t>(values[inc.other_col[0]]) * inc.other_place[0] +
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
  Rng rng_;
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

void validate(const std::vector<int>& levels, const CoveringArrayOptions& options) {
  if (options.strength != 2 && options.strength != 3)
    throw std::invalid_argument("strength must be 2 or 3, got " + std::to_string(options.strength));
  if (static_cast<std::size_t>(options.strength) > levels.size())
    throw std::invalid_argument("strength " + std::to_string(options.strength) +
                                " needs at least that many factors, got " + std::to_string(levels.size()));
  for (int l : levels)
    if (l < 1) throw std::invalid_argument("every factor needs at least one level");
  if (options.candidates_per_row < 1 || options.restarts < 1)
    throw std::invalid_argument("candidates_per_row and restarts must be positive");
  if (!(options.improvement_effort >= 0.0 && options.improvement_effort <= 1e6) ||
      options.improvement_max_moves < 0)
    throw std::invalid_argument("improvement_effort must be in [0, 1e6] and improvement_max_moves >= 0");
  for (const Row& r : options.seed_rows) {
    if (r.size() != levels.size()) throw std::invalid_argument("a seed row has the wrong number of entries");
    for (std::size_t c = 0; c < r.size(); ++c)
      if (r[c] != kDontCare && (r[c] < 0 || r[c] >= levels[c]))
        throw std::invalid_argument("a seed row has an out-of-range entry");
  }
}

}  // namespace

std::optional<std::vector<int>> complete_row(const std::vector<int>& levels, std::vector<int> partial,
                                             const RowViolates& violates) {
  if (!complete_from(levels, partial, 0, violates)) return std::nullopt;
  return partial;
}

CoveringArray generate_covering_array(const std::vector<int>& levels, const CoveringArrayOptions& options,
                                      const RowViolates& violates) {
  validate(levels, options);
  const TupleSpace space(levels, options.strength);
  const Feasibility feasibility = find_forbidden(space, levels, violates);
  CoveringArray best;
  best.levels = levels;
  best.strength = options.strength;
  best.required_tuples = space.total() - feasibility.forbidden_count;
  best.forbidden_tuples = feasibility.forbidden_count;
  for (int attempt = 0; attempt < options.restarts; ++attempt) {
    Builder builder(space, feasibility, violates, options,
                    options.seed * 0x100000001B3ULL + static_cast<std::uint64_t>(attempt));
    auto rows = builder.build();
    if (attempt == 0 || rows.size() < best.rows.size()) best.rows = std::move(rows);
  }
  if (options.improvement_effort > 0.0 && options.improvement_max_moves > 0) {  // remove rows
    Improver improver(space, feasibility, violates, options, options.seed * 0x100000001B3ULL + 0x5EED);
    best.rows = improver.improve(std::move(best.rows), options.seed_rows.size());
  }
  return best;
}

ArrayCheck check_covering_array(const std::vector<int>& levels, int strength,
                                const std::vector<std::vector<int>>& rows, const RowViolates& violates) {
  ArrayCheck report;
  const std::size_t n = levels.size();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    bool bad = rows[r].size() != n;
    for (std::size_t c = 0; !bad && c < n; ++c) bad = rows[r][c] < 0 || rows[r][c] >= levels[c];
    if (!bad && violates) bad = violates(rows[r]);
    if (bad) {
      ++report.invalid_rows;
      if (report.first_problem.empty()) report.first_problem = "row " + std::to_string(r + 1) + " is invalid";
    }
  }
  if (report.invalid_rows > 0) return report;
  // Enumerate each set of t columns, then each value tuple of it; brute force on purpose.
  std::vector<std::size_t> cols(static_cast<std::size_t>(strength));
  auto visit = [&](auto&& self, std::size_t depth, std::size_t from) -> void {
    if (depth == cols.size()) {
      std::size_t size = 1;
      for (auto c : cols) size *= static_cast<std::size_t>(levels[c]);
      std::vector<char> seen(size, 0);
      for (const auto& row : rows) {
        std::size_t i = 0;
        for (auto c : cols) i = i * static_cast<std::size_t>(levels[c]) + static_cast<std::size_t>(row[c]);
        seen[i] = 1;
      }
      for (std::size_t i = 0; i < size; ++i) {
        std::vector<int> partial(n, kDontCare);
        std::size_t rest = i;
        for (std::size_t j = cols.size(); j-- > 0;) {
          partial[cols[j]] = static_cast<int>(rest % static_cast<std::size_t>(levels[cols[j]]));
          rest /= static_cast<std::size_t>(levels[cols[j]]);
        }
        if (!seen[i] && violates && !complete_row(levels, partial, violates)) continue;  // forbidden
        ++report.required_tuples;
        if (seen[i]) {
          ++report.covered_tuples;
        } else if (report.first_problem.empty()) {
          std::string what;
          for (auto c : cols) what += " p" + std::to_string(c + 1) + "=" + std::to_string(partial[c]);
          report.first_problem = "tuple not covered:" + what;
        }
      }
      return;
    }
    for (std::size_t c = from; c < n; ++c) {
      cols[depth] = c;
      self(self, depth + 1, c + 1);
    }
  };
  if (static_cast<std::size_t>(strength) <= n && strength >= 1) visit(visit, 0, 0);
  return report;
}

}  // namespace emrm::scenario
