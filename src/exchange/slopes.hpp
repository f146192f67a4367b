#pragma once

// The slope of a recorded coordinate at a sample, from the parabola through it and its neighbours:
// what reading esmini's recordings (the CG's speed) and judging a trajectory (the direction of
// motion, the yaw rate) share. Internal to src/exchange.

#include <cstddef>
#include <utility>

namespace emrm::exchange::detail {

// The slope at t of the parabola through three samples (Lagrange), or of the chord through two.
inline double slope(const double* t, const double* f, int n, double at) {
  if (n == 2) return (f[1] - f[0]) / (t[1] - t[0]);
  const double d0 = ((at - t[1]) + (at - t[2])) / ((t[0] - t[1]) * (t[0] - t[2]));
  const double d1 = ((at - t[0]) + (at - t[2])) / ((t[1] - t[0]) * (t[1] - t[2]));
  const double d2 = ((at - t[0]) + (at - t[1])) / ((t[2] - t[0]) * (t[2] - t[1]));
  return f[0] * d0 + f[1] * d1 + f[2] * d2;
}

// The first of the (up to) three samples around sample k whose parabola gives the slopes at k, and
// how many: the neighbours on both sides inside the recording, else the nearest three.
inline std::pair<std::size_t, int> stencil(std::size_t k, std::size_t n) {
  const int points = n >= 3 ? 3 : 2;
  std::size_t first = k >= 1 ? k - 1 : 0;
  if (first + static_cast<std::size_t>(points) > n) first = n - static_cast<std::size_t>(points);
  return {first, points};
}

}  // namespace emrm::exchange::detail
