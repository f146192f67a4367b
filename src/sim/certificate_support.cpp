#include "certificate_support.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace emrm::sim::certificate_support {

double fiala_cap(double grip_n, double slope_n_per_rad, double tan_bound) {
  if (grip_n <= 0.0) return 0.0;
  const double z = slope_n_per_rad * tan_bound / grip_n;
  if (z >= 3.0) return grip_n;
  return grip_n * z * (1.0 - z / 3.0 + z * z / 27.0);
}

AxleSupport::AxleSupport(double a_in, double b_in, double cap_in)
    : a(a_in),
      b(b_in),
      s(std::sqrt(a_in * a_in + b_in * b_in)),
      cap(cap_in),
      switch_n(a_in > 0.0 ? cap_in * s / a_in : std::numeric_limits<double>::infinity()) {}

double AxleSupport::value(double n) const {
  if (n <= switch_n) return n * s;
  return a * cap + b * std::sqrt(std::max(0.0, n * n - cap * cap));
}

double AxleSupport::slope(double n) const {
  if (n <= switch_n) return s;
  const double root = std::sqrt(std::max(0.0, n * n - cap * cap));
  return root > 0.0 ? b * n / root : s;
}

double AxleSupport::value_minus(double n_max, double nu) const {
  if (nu >= s || n_max <= 0.0) return 0.0;
  if (n_max <= switch_n) return (s - nu) * n_max;
  double n = n_max;
  if (nu > b) n = std::min(n_max, nu * cap / std::sqrt(nu * nu - b * b));
  n = std::max(n, switch_n);
  return value(n) - nu * n;
}

// For every nu ≥ 0 the value is ≤ nu·S + Σ max_N(support − nu·N) (weak duality over the sum of the
// radii); a few nu are tried.
double axle_pair_support(double a_f, double a_r, double b, double grip_f, double grip_r, double cap_f, double cap_r,
                         double total_n) {
  const AxleSupport front(a_f, b, cap_f);
  const AxleSupport rear(a_r, b, cap_r);
  double best = front.value(grip_f) + rear.value(grip_r);
  if (grip_f + grip_r <= total_n) return best;
  // The slopes at the ends of the feasible splits of the total, and the lesser initial slope.
  const std::array nus{front.slope(grip_f), rear.slope(grip_r), front.slope(std::max(0.0, total_n - grip_r)),
                       rear.slope(std::max(0.0, total_n - grip_f)), std::min(front.s, rear.s)};
  for (double nu : nus)
    best = std::min(best, nu * total_n + front.value_minus(grip_f, nu) + rear.value_minus(grip_r, nu));
  return best;
}

}  // namespace emrm::sim::certificate_support
