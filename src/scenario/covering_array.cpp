#include "emrm/scenario/covering_array.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#ifdef CA_DEBUG
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <string>
#endif

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
    return static_cast<std::size_t>(std::upper_bound(offset_.begin(), offset_.end(), i) - offset_.begin()) - 1;
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

// Post-optimisation after Nurmela's tabu search for covering arrays: delete the row whose removal
// uncovers the fewest tuples, then repair coverage by single-cell changes that each cover a random
// uncovered tuple; repeat until a repair fails and keep the last complete array. Per-tuple cover
// counts make a change cost one look-up per t-subset containing its column.
class Improver {
 public:
  Improver(const TupleSpace& space, const Feasibility& feasibility, const RowViolates& violates,
           const CoveringArrayOptions& options, std::uint64_t seed)
      : space_(space),
        violates_(violates),
        options_(options),
        rng_(seed),
        incidence_(static_cast<std::size_t>(space.columns())) {
    // A row can never have fewer rows than the largest t-subset has required tuples.
    for (std::size_t k = 0; k < space.combo_count(); ++k) {
      std::size_t required = 0;
      for (std::size_t i = space.offset(k); i < space.offset(k) + space.combo_size(k); ++i)
        required += feasibility.forbidden.test(i) ? 0 : 1;
      lower_bound_ = std::max(lower_bound_, required);
      const auto& cols = space.combo(k);
      const auto t = static_cast<std::size_t>(space.t());
      // Mixed-radix place values of the combo's columns, last column fastest.
      std::array<std::size_t, 3> place{};
      std::size_t p = 1;
      for (std::size_t j = t; j-- > 0;) {
        place[j] = p;
        p *= static_cast<std::size_t>(space.level(cols[j]));
      }
      for (std::size_t j = 0; j < t; ++j) {
        Incidence inc{space.offset(k), {}, {}, place[j]};
        for (std::size_t o = 0, m = 0; o < t; ++o) {
          if (o == j) continue;
          inc.other_col[m] = static_cast<std::size_t>(cols[o]);
          inc.other_place[m++] = place[o];
        }
        if (t == 2) inc.other_col[1] = inc.other_col[0];  // place 0: contributes nothing
        incidence_[static_cast<std::size_t>(cols[j])].push_back(inc);
      }
    }
  }

  // `rows` must be a complete covering array whose first `seeds` rows are the seed rows.
  std::vector<Row> improve(std::vector<Row> rows, std::size_t seeds) {
    rows_ = std::move(rows);
    seeds_ = seeds;
    count_.assign(space_.total(), 0);
    position_.assign(space_.total(), kNotListed);
    since_.assign(space_.total(), 0);
    uncovered_.clear();
    for (const Row& r : rows_) space_.for_each_tuple(r, [&](std::size_t i) { ++count_[i]; });
    std::vector<Row> best = rows_;
    std::int64_t moves_left = options_.improvement_moves;
    static const int retries = std::getenv("RETRY") ? std::atoi(std::getenv("RETRY")) : 0;
    int failures = 0;
    while (rows_.size() > lower_bound_ && moves_left > 0) {
      if (!remove_row(failures > 0)) break;
      if (repair(moves_left)) {
        best = rows_;
        failures = 0;
        continue;
      }
      if (++failures > retries) break;
      rows_ = best;
      count_.assign(space_.total(), 0);
      for (std::uint32_t i : uncovered_) position_[i] = kNotListed;
      uncovered_.clear();
      for (const Row& r : rows_) space_.for_each_tuple(r, [&](std::size_t i) { ++count_[i]; });
    }
    return best;
  }

 private:
  // The t-subset k seen from one of its columns: tuple index = offset + sum(value * place).
  struct Incidence {
    std::size_t offset;
    std::array<std::size_t, 2> other_col;
    std::array<std::size_t, 2> other_place;
    std::size_t self_place;
  };

  [[nodiscard]] bool forced(std::size_t r, std::size_t c) const {
    return r < seeds_ && options_.seed_rows[r][c] != kDontCare;
  }

  void mark_uncovered(std::size_t i) {
    since_[i] = iteration_;
    position_[i] = static_cast<std::uint32_t>(uncovered_.size());
    uncovered_.push_back(static_cast<std::uint32_t>(i));
  }
  void mark_covered(std::size_t i) {
    const std::uint32_t at = position_[i];
    const std::uint32_t last = uncovered_.back();
    uncovered_[at] = last;
    position_[last] = at;
    uncovered_.pop_back();
    position_[i] = kNotListed;
  }

  // Drops the non-seed row covering the fewest tuples alone; false when only seed rows are left.
  bool remove_row(bool random = false) {
    if (rows_.size() <= seeds_) return false;
    if (random) {
      const std::size_t r = seeds_ + rng_.below(rows_.size() - seeds_);
      space_.for_each_tuple(rows_[r], [&](std::size_t i) {
        if (--count_[i] == 0) mark_uncovered(i);
      });
      std::swap(rows_[r], rows_.back());
      rows_.pop_back();
      return true;
    }
    std::size_t best_r = seeds_;
    std::size_t fewest = std::numeric_limits<std::size_t>::max();
    std::size_t ties = 0;
    for (std::size_t r = seeds_; r < rows_.size(); ++r) {
      std::size_t alone = 0;
      space_.for_each_tuple(rows_[r], [&](std::size_t i) { alone += count_[i] == 1 ? 1 : 0; });
      if (alone < fewest) {
        fewest = alone;
        best_r = r;
        ties = 1;
      } else if (alone == fewest && rng_.below(++ties) == 0) {
        best_r = r;
      }
    }
    space_.for_each_tuple(rows_[best_r], [&](std::size_t i) {
      if (--count_[i] == 0) mark_uncovered(i);
    });
    std::swap(rows_[best_r], rows_.back());
    rows_.pop_back();
    return true;
  }

  // Change in the number (first) and weight (second) of uncovered tuples if cell (r, c) took value v.
  [[nodiscard]] std::pair<std::int64_t, std::int64_t> delta(std::size_t r, std::size_t c, int v) const {
    const Row& row = rows_[r];
    const auto old_value = static_cast<std::size_t>(row[c]);
    const auto new_value = static_cast<std::size_t>(v);
    std::int64_t d = 0;
    std::int64_t w = 0;
    std::int64_t w2 = 0;
    for (const Incidence& inc : incidence_[c]) {
      const std::size_t base = inc.offset + static_cast<std::size_t>(row[inc.other_col[0]]) * inc.other_place[0] +
                               static_cast<std::size_t>(row[inc.other_col[1]]) * inc.other_place[1];
      const std::size_t lost = base + old_value * inc.self_place;
      const std::size_t gained = base + new_value * inc.self_place;
      if (count_[lost] == 1) {
        ++d;
        w += weight_[lost];
      }
      if (count_[gained] == 0) {
        --d;
        w -= weight_[gained];
      }
      if (secondary_) {
        if (count_[lost] == 2) ++w2;
        if (count_[gained] == 1) --w2;
      }
    }
    return {d, w * 1024 + w2};
  }

  void apply(std::size_t r, std::size_t c, int v) {
    Row& row = rows_[r];
    const auto old_value = static_cast<std::size_t>(row[c]);
    const auto new_value = static_cast<std::size_t>(v);
    for (const Incidence& inc : incidence_[c]) {
      const std::size_t base = inc.offset + static_cast<std::size_t>(row[inc.other_col[0]]) * inc.other_place[0] +
                               static_cast<std::size_t>(row[inc.other_col[1]]) * inc.other_place[1];
      const std::size_t lost = base + old_value * inc.self_place;
      const std::size_t gained = base + new_value * inc.self_place;
      if (--count_[lost] == 0) mark_uncovered(lost);
      if (count_[gained]++ == 0) mark_covered(gained);
    }
    prev_value_[r * static_cast<std::size_t>(space_.columns()) + c] = row[c];
    row[c] = v;
    changed_at_[r * static_cast<std::size_t>(space_.columns()) + c] = iteration_;
  }

  [[nodiscard]] bool valid_with(std::size_t r, std::size_t c, int v) {
    if (!violates_) return true;
    Row& row = rows_[r];
    const int old_value = row[c];
    row[c] = v;
    const bool ok = !violates_(row);
    row[c] = old_value;
    return ok;
  }

  // Tabu search until every required tuple is covered; false when the patience or budget runs out.
  bool repair(std::int64_t& moves_left) {
    const auto cells = rows_.size() * static_cast<std::size_t>(space_.columns());
    changed_at_.assign(cells, std::numeric_limits<std::int64_t>::min() / 2);
    weight_.assign(space_.total(), 1);
    prev_value_.assign(cells, -1);
    std::size_t best = uncovered_.size();
    std::int64_t since_best = 0;
#ifdef CA_DEBUG
    std::fprintf(stderr, "try rows=%zu uncovered=%zu it=%lld\n", rows_.size(), uncovered_.size(), (long long)iteration_);
#endif
    while (!uncovered_.empty()) {
      if (moves_left <= 0 || since_best >= options_.improvement_patience) {
#ifdef CA_DEBUG
        std::fprintf(stderr, "fail rows=%zu best=%zu it=%lld\n", rows_.size(), best, (long long)iteration_);
#endif
        return false;
      }
      --moves_left;
      ++iteration_;
#ifdef CA_DEBUG
      if (std::getenv("ALG") && std::string(std::getenv("ALG")) == "sa") sa_step(); else
#endif
      step(best);
      if (uncovered_.size() < best) {
        best = uncovered_.size();
        since_best = 0;
      } else {
        ++since_best;
      }
    }
    return true;
  }

  // One move: among the rows one cell away from a random uncovered tuple, change the cell whose
  // change leaves the fewest tuples uncovered, unless it was changed recently (tabu) and does not
  // beat the best count of this repair. With no such move, a random cell moves toward the tuple.
#ifdef CA_DEBUG
  void sa_step() {
    static const double temp = std::getenv("TEMP") ? std::atof(std::getenv("TEMP")) : 0.5;
    static const int mode = std::getenv("MODE") ? std::atoi(std::getenv("MODE")) : 0;
    const std::size_t tuple = uncovered_[rng_.below(uncovered_.size())];
    const std::size_t k = space_.combo_of_tuple(tuple);
    const auto t = static_cast<std::size_t>(space_.t());
    std::array<std::size_t, 3> cols{};
    std::array<int, 3> values{};
    {
      std::size_t local = tuple - space_.offset(k);
      for (std::size_t j = t; j-- > 0;) {
        cols[j] = static_cast<std::size_t>(space_.combo(k)[j]);
        const auto l = static_cast<std::size_t>(space_.level(space_.combo(k)[j]));
        values[j] = static_cast<int>(local % l);
        local /= l;
      }
    }
    std::size_t r = 0;
    if (mode == 0) {
      // random one-away row
      std::size_t seen = 0;
      for (std::size_t q = 0; q < rows_.size(); ++q) {
        std::size_t matches = 0;
        for (std::size_t j = 0; j < t; ++j) matches += rows_[q][cols[j]] == values[j];
        if (matches + 1 == t && rng_.below(++seen) == 0) r = q;
      }
      if (seen == 0) r = rng_.below(rows_.size());
    } else {
      r = rng_.below(rows_.size());
    }
    const auto before = static_cast<std::int64_t>(uncovered_.size());
    std::array<int, 3> old{};
    for (std::size_t j = 0; j < t; ++j) {
      old[j] = rows_[r][cols[j]];
      if (old[j] != values[j]) apply(r, cols[j], values[j]);
    }
    const auto d = static_cast<std::int64_t>(uncovered_.size()) - before;
    if (d <= 0) return;
    const double u = static_cast<double>(rng_.next() >> 11) * 0x1.0p-53;
    if (u < std::exp(-static_cast<double>(d) / temp)) return;
    for (std::size_t j = t; j-- > 0;)
      if (rows_[r][cols[j]] != old[j]) apply(r, cols[j], old[j]);
  }
#endif
  // Exact change in uncovered count if row r took values vals at columns cols (those that differ).
  std::int64_t multi_delta(std::size_t r, const std::array<std::size_t, 3>& cols, const std::array<int, 3>& vals, std::size_t t) {
    Row& row = rows_[r];
    scratch_ = row;
    std::array<std::size_t, 3> changed{};
    std::size_t m = 0;
    for (std::size_t j = 0; j < t; ++j)
      if (row[cols[j]] != vals[j]) {
        changed[m++] = cols[j];
        scratch_[cols[j]] = vals[j];
      }
    std::int64_t d = 0;
    for (std::size_t a = 0; a < m; ++a) {
      const std::size_t c = changed[a];
      for (const Incidence& inc : incidence_[c]) {
        bool dup = false;
        for (std::size_t b = 0; b < a; ++b) dup = dup || inc.other_col[0] == changed[b] || inc.other_col[1] == changed[b];
        if (dup) continue;
        const std::size_t lost = inc.offset + static_cast<std::size_t>(row[inc.other_col[0]]) * inc.other_place[0] +
                                 static_cast<std::size_t>(row[inc.other_col[1]]) * inc.other_place[1] +
                                 static_cast<std::size_t>(row[c]) * inc.self_place;
        const std::size_t gained = inc.offset + static_cast<std::size_t>(scratch_[inc.other_col[0]]) * inc.other_place[0] +
                                   static_cast<std::size_t>(scratch_[inc.other_col[1]]) * inc.other_place[1] +
                                   static_cast<std::size_t>(scratch_[c]) * inc.self_place;
        d += (count_[lost] == 1 ? 1 : 0) - (count_[gained] == 0 ? 1 : 0);
      }
    }
    return d;
  }

  void full_step(std::size_t best) {
    const auto t = static_cast<std::size_t>(space_.t());
    const auto n = static_cast<std::size_t>(space_.columns());
    const std::size_t tuple = uncovered_[rng_.below(uncovered_.size())];
    const std::size_t k = space_.combo_of_tuple(tuple);
    std::array<std::size_t, 3> cols{};
    std::array<int, 3> values{};
    {
      std::size_t local = tuple - space_.offset(k);
      for (std::size_t j = t; j-- > 0;) {
        cols[j] = static_cast<std::size_t>(space_.combo(k)[j]);
        const auto l = static_cast<std::size_t>(space_.level(space_.combo(k)[j]));
        values[j] = static_cast<int>(local % l);
        local /= l;
      }
    }
    const auto uncovered = static_cast<std::int64_t>(uncovered_.size());
    std::int64_t best_delta = std::numeric_limits<std::int64_t>::max();
    std::size_t best_r = 0;
    std::size_t ties = 0;
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      bool tabu = false;
      bool blocked = false;
      for (std::size_t j = 0; j < t; ++j)
        if (rows_[r][cols[j]] != values[j]) {
          tabu = tabu || iteration_ - changed_at_[r * n + cols[j]] <= options_.improvement_tabu_tenure;
          blocked = blocked || forced(r, cols[j]);
        }
      if (blocked) continue;
      const std::int64_t d = multi_delta(r, cols, values, t);
      if (d > best_delta) continue;
      if (tabu && uncovered + d >= static_cast<std::int64_t>(best)) continue;
      if (d < best_delta) {
        best_delta = d;
        ties = 0;
      }
      if (rng_.below(++ties) == 0) best_r = r;
    }
    if (ties == 0) return;
    for (std::size_t j = 0; j < t; ++j)
      if (rows_[best_r][cols[j]] != values[j]) apply(best_r, cols[j], values[j]);
  }

  void step(std::size_t best) {
    static const bool full = std::getenv("FULL") != nullptr;
    if (full) { full_step(best); return; }
    static const std::size_t nt = std::getenv("NT") ? std::strtoul(std::getenv("NT"), nullptr, 10) : 1;
    const auto t = static_cast<std::size_t>(space_.t());
    const auto n = static_cast<std::size_t>(space_.columns());
    const auto uncovered = static_cast<std::int64_t>(uncovered_.size());
    std::int64_t best_delta = std::numeric_limits<std::int64_t>::max();
    std::size_t best_r = 0;
    std::size_t best_c = 0;
    int best_v = 0;
    std::size_t ties = 0;
    std::array<std::size_t, 3> cols{};
    std::array<int, 3> values{};
    const std::size_t samples = std::min(nt, uncovered_.size());
    for (std::size_t sample = 0; sample < samples; ++sample) {
    std::size_t tuple = samples == uncovered_.size() ? uncovered_[sample] : uncovered_[rng_.below(uncovered_.size())];
    static const double oldest_p = std::getenv("OLD") ? std::atof(std::getenv("OLD")) : 0.0;
    if (oldest_p > 0 && static_cast<double>(rng_.next() >> 11) * 0x1.0p-53 < oldest_p) {
      for (std::uint32_t i : uncovered_) if (since_[i] < since_[tuple]) tuple = i;
    }
    const std::size_t k = space_.combo_of_tuple(tuple);
    {
      std::size_t local = tuple - space_.offset(k);
      for (std::size_t j = t; j-- > 0;) {
        cols[j] = static_cast<std::size_t>(space_.combo(k)[j]);
        const auto l = static_cast<std::size_t>(space_.level(space_.combo(k)[j]));
        values[j] = static_cast<int>(local % l);
        local /= l;
      }
    }
    static const std::size_t max_cand = std::getenv("MAXC") ? std::strtoul(std::getenv("MAXC"), nullptr, 10) : 1000000;
    std::size_t found = 0;
    const std::size_t start = max_cand < 1000000 ? rng_.below(rows_.size()) : 0;
    for (std::size_t rr = 0; rr < rows_.size() && found < max_cand; ++rr) {
      const std::size_t r = (start + rr) % rows_.size();
      std::size_t matches = 0;
      std::size_t j_off = 0;
      for (std::size_t j = 0; j < t; ++j) {
        if (rows_[r][cols[j]] == values[j]) {
          ++matches;
        } else {
          j_off = j;
        }
      }
      if (matches + 1 != t || forced(r, cols[j_off])) continue;
      ++found;
      static const double noise = std::getenv("NOISE") ? std::atof(std::getenv("NOISE")) : 0.0;
      static const std::uint64_t noise_cut = static_cast<std::uint64_t>(noise * 18446744073709551615.0);
      auto [d, w] = delta(r, cols[j_off], values[j_off]);
      if (noise_cut && rng_.next() < noise_cut) w = -1000000;
      if (w > best_delta) continue;
      static const bool value_tabu = std::getenv("VTABU") != nullptr;
      const bool tabu = iteration_ - changed_at_[r * n + cols[j_off]] <= options_.improvement_tabu_tenure &&
                        (!value_tabu || prev_value_[r * n + cols[j_off]] == values[j_off]);
      if (tabu && uncovered + d >= static_cast<std::int64_t>(best)) continue;
      if (!valid_with(r, cols[j_off], values[j_off])) continue;
      if (w < best_delta) {
        best_delta = w;
        ties = 0;
      }
      if (rng_.below(++ties) == 0) {
        best_r = r;
        best_c = cols[j_off];
        best_v = values[j_off];
      }
    }
    }
    if (ties > 0) {
      apply(best_r, best_c, best_v);
      return;
    }
    const std::size_t r = rng_.below(rows_.size());
    const std::size_t j = rng_.below(t);
    if (rows_[r][cols[j]] != values[j] && !forced(r, cols[j]) && valid_with(r, cols[j], values[j]))
      apply(r, cols[j], values[j]);
  }


  static constexpr std::uint32_t kNotListed = std::numeric_limits<std::uint32_t>::max();

  const TupleSpace& space_;
  const RowViolates& violates_;
  const CoveringArrayOptions& options_;
  Rng rng_;
  std::vector<std::vector<Incidence>> incidence_;  // per column, the t-subsets containing it
  std::size_t lower_bound_ = 0;
  std::vector<Row> rows_;
  std::size_t seeds_ = 0;
  std::vector<std::uint32_t> count_;     // rows containing each tuple
  std::vector<std::uint32_t> uncovered_;  // required tuples with count 0, in no particular order
  std::vector<std::uint32_t> position_;  // index in uncovered_, or kNotListed
  std::vector<std::int64_t> changed_at_;  // iteration each cell last changed (row-major)
  std::vector<std::uint32_t> weight_;
  std::vector<std::int64_t> since_;
  std::vector<int> prev_value_;
  Row scratch_;
  bool secondary_ = std::getenv("SEC") != nullptr;
  std::int64_t iteration_ = 0;
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
  if (options.improvement_moves < 0 || options.improvement_patience < 1 || options.improvement_tabu_tenure < 0)
    throw std::invalid_argument("improvement_moves and improvement_tabu_tenure must be >= 0, improvement_patience >= 1");
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
  if (options.improvement_moves > 0) {
    Improver improver(space, feasibility, violates, options, options.seed * 0x100000001B3ULL + 0x5EED);
    best.rows = improver.improve(std::move(best.rows), options.seed_rows.size());
  }
  return best;
}

CoverageReport check_covering_array(const std::vector<int>& levels, int strength,
                                    const std::vector<std::vector<int>>& rows, const RowViolates& violates) {
  CoverageReport report;
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
