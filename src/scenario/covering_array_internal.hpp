#pragma once

// Private to the covering-array code: the t-tuple index space and the coverage bitset that the
// greedy builder (covering_array.cpp) and the row-removing tabu search (covering_array_improve.cpp)
// share.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "emrm/scenario/covering_array.hpp"

namespace emrm::scenario::detail {

using Row = std::vector<int>;

// Every t-subset of columns ("combo") owns a contiguous block of tuple indices, so coverage is one
// bitset over all t-tuples and a tuple's index is a few multiplications.
class TupleSpace {
 public:
  TupleSpace(const std::vector<int>& levels, int t) : t_(t), n_(static_cast<int>(levels.size())), levels_(levels) {
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

// Which tuples no valid row contains. A witness row found for one tuple proves all its tuples
// feasible, so the (exponential) completion search runs for few tuples.
struct Feasibility {
  Bitset forbidden;
  std::size_t forbidden_count = 0;
};

/// The post-optimisation of a complete array `rows` whose first `seeds` rows are the seed rows:
/// removes rows while a tabu search (seeded with `seed`) can repair coverage, within the effort
/// and move budget of `options`, and returns the last complete array (`rows` itself when no row
/// could go).
[[nodiscard]] std::vector<Row> remove_rows(const TupleSpace& space, const Feasibility& feasibility,
                                           const RowViolates& violates, const CoveringArrayOptions& options,
                                           std::uint64_t seed, std::vector<Row> rows, std::size_t seeds);

}  // namespace emrm::scenario::detail
