#include "emrm/scenario/covering_array.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "covering_array_internal.hpp"
#include "emrm/core/error.hpp"
#include "emrm/core/random.hpp"

namespace emrm::scenario {
namespace {

using detail::Bitset;
using detail::Feasibility;
using detail::Row;
using detail::TupleSpace;

bool complete_from(const std::vector<int>& levels, Row& row, std::size_t from, const RowViolates& violates,
                   SearchBudget& budget) {
  budget.spend();
  if (violates && violates(row)) return false;
  while (from < row.size() && row[from] != kDontCare) ++from;
  if (from == row.size()) return true;
  for (int v = 0; v < levels[from]; ++v) {
    row[from] = v;
    if (complete_from(levels, row, from + 1, violates, budget)) return true;
  }
  row[from] = kDontCare;
  return false;
}

Feasibility find_forbidden(const TupleSpace& space, const std::vector<int>& levels, const RowViolates& violates,
                           SearchBudget& budget) {
  Feasibility f{Bitset(space.total()), 0};
  if (!violates) return f;
  Bitset feasible(space.total());
  auto mark_feasible = [&](const Row& r) { space.for_each_tuple(r, [&](std::size_t i) { feasible.set(i); }); };
  auto any = complete_row(levels, Row(levels.size(), kDontCare), violates, budget);
  if (!any) throw std::domain_error("the constraints exclude every row");
  mark_feasible(*any);
  Row partial(levels.size(), kDontCare);
  for (std::size_t k = 0; k < space.combo_count(); ++k)
    for (std::size_t i = space.offset(k); i < space.offset(k) + space.combo_size(k); ++i) {
      if (feasible.test(i)) continue;
      std::fill(partial.begin(), partial.end(), kDontCare);
      space.decode(k, i, partial);
      std::optional<Row> witness;
      if (!violates(partial)) witness = complete_row(levels, partial, violates, budget);
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
  Builder(const TupleSpace& space, const Feasibility& feasibility, const RowViolates& violates, SearchBudget& budget,
          const CoveringArrayOptions& options, std::uint64_t seed)
      : space_(space),
        violates_(violates),
        budget_(budget),
        options_(options),
        rng_(seed),
        covered_(feasibility.forbidden),
        uncovered_in_combo_(space.combo_count(), 0) {
    const int n = space.columns();
    value_base_.resize(static_cast<std::size_t>(n) + 1, 0);
    for (int c = 0; c < n; ++c)
      value_base_[static_cast<std::size_t>(c) + 1] = value_base_[static_cast<std::size_t>(c)] + space.level(c);
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
      order.emplace_back(s + 1e-6 * static_cast<double>(core::index_below(rng_, 1000)), v);
    }
    std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    const auto c = static_cast<std::size_t>(col);
    for (const auto& [s, v] : order) {
      row[c] = v;
      if (!violates_ || complete_row(levels_of_space(), row, violates_, budget_)) {
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
      } else if (u == most && u > 0 && core::index_below(rng_, ++ties) == 0) {
        best_k = k;
      }
    }
    std::size_t pick = 0;
    std::size_t seen = 0;
    for (std::size_t i = space_.offset(best_k); i < space_.offset(best_k) + space_.combo_size(best_k); ++i)
      if (!covered_.test(i) && core::index_below(rng_, ++seen) == 0) pick = i;
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
    core::shuffle(rest, rng_);
    gain = 1;
    for (int c : rest) gain += assign_best(row, assigned, c);
    return row;
  }

  Row fill_seed(const Row& seed) {
    Row row = seed;
    if (violates_ && !complete_row(levels_of_space(), row, violates_, budget_))
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
  SearchBudget& budget_;  // shared with find_forbidden and the other restarts
  const CoveringArrayOptions& options_;
  core::SplitMix64 rng_;
  Bitset covered_;  // covered, or forbidden (never required)
  std::vector<int> uncovered_in_combo_;
  std::size_t uncovered_ = 0;
  std::vector<int> value_base_;
  // Uncovered tuples containing value (c, v) and any value of column j, at [(base[c]+v)*n + j].
  std::vector<int> value_uncovered_;
  std::vector<Row> rows_;
};

// The t-tuples over every t-subset of the factors (as a double: it may not fit an integer).
double tuple_count(const std::vector<int>& levels, int strength) {
  double total = 0.0;
  const std::size_t k = levels.size();
  for (std::size_t a = 0; a < k; ++a)
    for (std::size_t b = a + 1; b < k; ++b) {
      const double pair = static_cast<double>(levels[a]) * levels[b];
      if (strength == 2)
        total += pair;
      else
        for (std::size_t c = b + 1; c < k; ++c) total += pair * levels[c];
    }
  return total;
}

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
  if (!(options.improvement_effort >= 0.0 && options.improvement_effort <= 1e6) || options.improvement_max_moves < 0)
    throw std::invalid_argument("improvement_effort must be in [0, 1e6] and improvement_max_moves >= 0");
  if (const double tuples = tuple_count(levels, options.strength); tuples > static_cast<double>(options.max_tuples))
    throw UsageError(
        fmt::format("the covering array has {:.3g} {}-tuples to cover, more than the limit of {} "
                    "(ca --max-tuples raises it; memory grows with it)",
                    tuples, options.strength, options.max_tuples));
  for (const Row& r : options.seed_rows) {
    if (r.size() != levels.size()) throw std::invalid_argument("a seed row has the wrong number of entries");
    for (std::size_t c = 0; c < r.size(); ++c)
      if (r[c] != kDontCare && (r[c] < 0 || r[c] >= levels[c]))
        throw std::invalid_argument("a seed row has an out-of-range entry");
  }
}

}  // namespace

void SearchBudget::spend() {
  if (used_ >= limit_)
    throw UsageError(
        fmt::format("the constraints took more than {} search steps to satisfy "
                    "(ca --max-search-steps raises it)",
                    limit_));
  ++used_;
}

std::optional<std::vector<int>> complete_row(const std::vector<int>& levels, std::vector<int> partial,
                                             const RowViolates& violates, SearchBudget& budget) {
  if (!complete_from(levels, partial, 0, violates, budget)) return std::nullopt;
  return partial;
}

std::optional<std::vector<int>> complete_row(const std::vector<int>& levels, std::vector<int> partial,
                                             const RowViolates& violates) {
  SearchBudget budget;
  return complete_row(levels, std::move(partial), violates, budget);
}

CoveringArray generate_covering_array(const std::vector<int>& levels, const CoveringArrayOptions& options,
                                      const RowViolates& violates) {
  validate(levels, options);
  const TupleSpace space(levels, options.strength);
  SearchBudget budget(options.max_search_steps);
  const Feasibility feasibility = find_forbidden(space, levels, violates, budget);
  CoveringArray best;
  best.levels = levels;
  best.strength = options.strength;
  best.required_tuples = space.total() - feasibility.forbidden_count;
  best.forbidden_tuples = feasibility.forbidden_count;
  for (int attempt = 0; attempt < options.restarts; ++attempt) {
    Builder builder(space, feasibility, violates, budget, options,
                    options.seed * 0x100000001B3ULL + static_cast<std::uint64_t>(attempt));
    auto rows = builder.build();
    if (attempt == 0 || rows.size() < best.rows.size()) best.rows = std::move(rows);
  }
  if (options.improvement_effort > 0.0 && options.improvement_max_moves > 0) {  // remove rows
    best.rows = detail::remove_rows(space, feasibility, violates, options, options.seed * 0x100000001B3ULL + 0x5EED,
                                    std::move(best.rows), options.seed_rows.size());
  }
  return best;
}

ArrayCheck check_covering_array(const std::vector<int>& levels, int strength, const std::vector<std::vector<int>>& rows,
                                const RowViolates& violates, std::uint64_t max_search_steps) {
  ArrayCheck report;
  SearchBudget budget(max_search_steps);
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
        if (!seen[i] && violates && !complete_row(levels, partial, violates, budget)) continue;  // forbidden
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
