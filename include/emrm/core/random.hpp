#pragma once

// Seeded random streams that are the same on every platform, run, thread and shard: a stream's
// seed is derived from a parent seed and a key (a cell, a strategy, a scenario), and numbers are
// drawn with std::mt19937_64 or SplitMix64 (whose sequences are fixed: by the standard, and by
// the algorithm below) and our own conversions (the standard's distributions and std::shuffle are
// implementation-defined).

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
#include <ranges>
#include <string_view>

namespace emrm::core {

/// The output function of splitmix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
/// generators", 2014; Vigna's splitmix64.c): a bijective mix of all 64 bits of `z`.
[[nodiscard]] constexpr std::uint64_t splitmix64_mix(std::uint64_t z) noexcept {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// splitmix64: a 64-bit state advanced by the golden-ratio increment, each output the mix of the
/// new state. Small, fast and the same sequence on every platform; satisfies
/// UniformRandomBitGenerator, so it can drive std algorithms where their results may differ between
/// standard libraries (use index_below and shuffle below where they must not). Not for
/// cryptography; a copy continues the same sequence.
class SplitMix64 {
 public:
  using result_type = std::uint64_t;
  /// The state's increment per draw: 2^64 / φ, rounded to odd.
  static constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ull;

  /// Every seed is valid, 0 included; equal seeds give equal sequences.
  constexpr explicit SplitMix64(std::uint64_t seed) noexcept : state_(seed) {}

  [[nodiscard]] static constexpr result_type min() noexcept { return 0; }
  [[nodiscard]] static constexpr result_type max() noexcept { return std::numeric_limits<result_type>::max(); }
  /// The next number, uniform over all 64-bit values.
  constexpr result_type operator()() noexcept { return splitmix64_mix(state_ += kGamma); }

 private:
  std::uint64_t state_;
};

/// A 64-bit seed from a parent seed and a key: the first output of SplitMix64 seeded with the
/// parent seed XOR the key's FNV-1a hash.
[[nodiscard]] std::uint64_t derive_seed(std::uint64_t seed, std::string_view key) noexcept;

/// Uniform in [0, 1), from the top 53 bits of one draw.
[[nodiscard]] inline double uniform01(std::mt19937_64& rng) noexcept {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform integer in [0, n), n > 0 (multiply-shift; bias below 2^-32 for n < 2^32).
[[nodiscard]] inline std::uint64_t uniform_index(std::mt19937_64& rng, std::uint64_t n) noexcept {
  return static_cast<std::uint64_t>(uniform01(rng) * static_cast<double>(n)) % n;
}

/// An integer in [0, n) from one draw of `rng`, as the draw modulo n (bias below n / 2^64).
/// Requires n > 0.
[[nodiscard]] inline std::size_t index_below(SplitMix64& rng, std::size_t n) noexcept {
  return static_cast<std::size_t>(rng() % n);
}

/// Shuffles `items` in place (Fisher-Yates from the back: item i - 1 swaps with index_below(i),
/// for i from the size down to 2): the same order on every platform for the same stream.
template <std::ranges::random_access_range R>
requires std::ranges::sized_range<R>
void shuffle(R&& items, SplitMix64& rng) {
  using Offset = std::ranges::range_difference_t<R>;
  const auto first = std::ranges::begin(items);
  for (auto i = static_cast<std::size_t>(std::ranges::size(items)); i > 1; --i)
    std::ranges::iter_swap(first + static_cast<Offset>(i - 1), first + static_cast<Offset>(index_below(rng, i)));
}

}  // namespace emrm::core
