#include "emrm/core/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <random>
#include <string_view>
#include <vector>

namespace emrm::core {
namespace random_test {

// splitmix64 as published (Vigna, https://prng.di.unimi.it/splitmix64.c), written here
// independently of the library so that the tests pin the library's stream to the algorithm.
struct ReferenceSplitMix64 {
  std::uint64_t x;
  std::uint64_t next() {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
};

static_assert(std::uniform_random_bit_generator<SplitMix64>);

TEST(SplitMix64, FirstOutputsAreThePublishedOnes) {
  // The sequence for seed 1234567 given with the algorithm (e.g. Rosetta Code, "Pseudo-random
  // numbers/Splitmix64"), and the first output for seed 0 of Vigna's splitmix64.c.
  SplitMix64 rng(1234567);
  for (const std::uint64_t expected : {6457827717110365317ull, 3203168211198807973ull, 9817491932198370423ull,
                                       4593380528125082431ull, 16408922859458223821ull})
    EXPECT_EQ(rng(), expected);
  EXPECT_EQ(SplitMix64(0)(), 0xe220a8397b1dcdafull);
}

TEST(SplitMix64, FollowsTheReferenceAlgorithmForAnySeed) {
  for (const std::uint64_t seed : {0ull, 1ull, 42ull, 0x100000001b3ull * 7 + 0x5eed, ~0ull}) {
    SplitMix64 rng(seed);
    ReferenceSplitMix64 reference{seed};
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(rng(), reference.next()) << "seed " << seed << ", draw " << i;
  }
}

TEST(SplitMix64, MixIsTheOutputFunctionOfOneStep) {
  ReferenceSplitMix64 reference{99};
  EXPECT_EQ(splitmix64_mix(99 + SplitMix64::kGamma), reference.next());
}

TEST(SplitMix64, ACopyContinuesTheSameSequence) {
  SplitMix64 a(7);
  (void)a();
  SplitMix64 b = a;
  for (int i = 0; i < 10; ++i) EXPECT_EQ(a(), b());
}

TEST(IndexBelow, IsOneDrawModuloN) {
  SplitMix64 rng(5);
  ReferenceSplitMix64 reference{5};
  for (const std::size_t n : {1u, 2u, 3u, 10u, 1000u, 65537u}) {
    const std::size_t i = index_below(rng, n);
    EXPECT_LT(i, n);
    EXPECT_EQ(i, reference.next() % n);
  }
}

TEST(Shuffle, IsFisherYatesFromTheBackOnTheStream) {
  std::vector<int> items(20);
  std::iota(items.begin(), items.end(), 0);
  std::vector<int> expected = items;
  ReferenceSplitMix64 reference{2024};
  for (std::size_t i = expected.size(); i > 1; --i) std::swap(expected[i - 1], expected[reference.next() % i]);

  SplitMix64 rng(2024);
  shuffle(items, rng);
  EXPECT_EQ(items, expected);
  std::vector<int> sorted = items;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> all(20);
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(sorted, all);  // a permutation
}

TEST(Shuffle, OfNoneOrOneItemDrawsNothing) {
  SplitMix64 rng(3), untouched(3);
  std::vector<int> none, one{1};
  shuffle(none, rng);
  shuffle(one, rng);
  EXPECT_EQ(one, std::vector<int>{1});
  EXPECT_EQ(rng(), untouched());
}

TEST(DeriveSeed, IsSplitMixOfTheSeedXorTheKeysFnv1a) {
  const auto fnv1a = [](std::string_view key) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char c : key) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
    return h;
  };
  for (const std::string_view key : {"", "plan", "covering array", "fine/17"})
    for (const std::uint64_t seed : {0ull, 1ull, 20240601ull}) {
      ReferenceSplitMix64 reference{seed ^ fnv1a(key)};
      EXPECT_EQ(derive_seed(seed, key), reference.next()) << "key '" << key << "', seed " << seed;
    }
  EXPECT_NE(derive_seed(1, "a"), derive_seed(1, "b"));
  EXPECT_NE(derive_seed(1, "a"), derive_seed(2, "a"));
}

}  // namespace random_test
}  // namespace emrm::core
