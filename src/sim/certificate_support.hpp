#pragma once

// The convex-analysis pieces of the unavoidability certificate (docs/physics.md, "Unavoidability
// certificates", (C5) and (C10)): the Fiala envelope of a slip bound and the support of an axle's
// friction disc cut to a lateral band, for one axle and for both under a shared total grip.
// Internal to src/sim; certificate.cpp is the only user.

namespace emrm::sim::certificate_support {

/// Fiala envelope (C5): the largest lateral force an axle with grip N and slope K can give at
/// |tan(alpha)| ≤ t. f(z) = z − z²/3 + z³/27 up to z = 3, then 1.
[[nodiscard]] double fiala_cap(double grip_n, double slope_n_per_rad, double tan_bound);

/// One axle's part of a functional: max{ a|q| + b|p| : p² + q² ≤ N², |q| ≤ cap } as a function of
/// the friction disc's radius N (the support of the disc cut to the band |q| ≤ cap). Concave and
/// nondecreasing in N: linear with slope s = √(a² + b²) up to N_switch = cap·s/a, then
/// a·cap + b·√(N² − cap²).
struct AxleSupport {
  double a, b, s, cap, switch_n;

  AxleSupport(double a_in, double b_in, double cap_in);
  [[nodiscard]] double value(double n) const;
  [[nodiscard]] double slope(double n) const;
  /// max over 0 ≤ N ≤ n_max of (value(N) − nu·N), in closed form (where the slope falls to nu).
  [[nodiscard]] double value_minus(double n_max, double nu) const;
};

/// Both axles (C10): max of a_f|q_f| + b|p_f| + a_r|q_r| + b|p_r| with each axle in its friction
/// disc (radius ≤ its grip), its body-lateral component within its cap, and the two radii summing
/// to at most total_n. Bounded from above by weak duality over the sum constraint.
[[nodiscard]] double axle_pair_support(double a_f, double a_r, double b, double grip_f, double grip_r, double cap_f,
                                       double cap_r, double total_n);

}  // namespace emrm::sim::certificate_support
