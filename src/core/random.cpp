#include "emrm/core/random.hpp"

namespace emrm::core {

std::uint64_t derive_seed(std::uint64_t seed, std::string_view key) noexcept {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64
  for (char c : key) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return SplitMix64(seed ^ h)();
}

}  // namespace emrm::core
