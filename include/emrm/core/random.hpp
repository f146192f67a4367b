#pragma once

// Seeded random streams that are the same on every platform, run, thread and shard: a stream's
// seed is derived from a parent seed and a key (a cell, a strategy, a scenario), and numbers are
// drawn with std::mt19937_64 (whose sequence the standard fixes) and our own conversions
// (the standard's distributions are implementation-defined).

#include <cstdint>
#include <random>
#include <string_view>

namespace emrm::core {

/// A 64-bit seed from a parent seed and a key (FNV-1a over the key, mixed with splitmix64).
[[nodiscard]] std::uint64_t derive_seed(std::uint64_t seed, std::string_view key) noexcept;

/// Uniform in [0, 1), from the top 53 bits of one draw.
[[nodiscard]] inline double uniform01(std::mt19937_64& rng) noexcept {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform integer in [0, n), n > 0 (multiply-shift; bias below 2^-32 for n < 2^32).
[[nodiscard]] inline std::uint64_t uniform_index(std::mt19937_64& rng, std::uint64_t n) noexcept {
  return static_cast<std::uint64_t>(uniform01(rng) * static_cast<double>(n)) % n;
}

}  // namespace emrm::core
