#pragma once
// The sample sizes of the suite's slowest tests. scripts/test.sh runs the suite three times: once
// unsanitized, where every test draws its full sample and holds it to its threshold, and twice
// under AddressSanitizer and UndefinedBehaviorSanitizer (GCC, clang), which look for memory and
// undefined-behaviour errors and run the code five to ten times slower. There the slowest tests
// draw a smaller sample through the same code paths, so that the three runs fit in CI's time; a
// threshold that needs the full sample to mean anything (a rate of at most 1 %) is checked in the
// unsanitized run (docs/testing.md).

namespace emrm::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// `full` unsanitized, `sanitized` under the sanitizers.
template <typename T>
constexpr T sample(T full, T sanitized) {
  return kSanitized ? sanitized : full;
}

}  // namespace emrm::test
