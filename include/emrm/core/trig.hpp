#pragma once

// cos and sin of one angle at once, fast and the same on every platform: what the simulator's hot
// paths (box headings, the vehicle model's yaw and steering) use instead of two library calls; and
// the wrapping of an angle, exact and cheap for the angles a simulation meets.

#include <cmath>
#include <numbers>

namespace emrm::core {

// cos and sin of box headings, inlined: the library's sincos is a call that costs as much as the
// whole rest of the separating-axis test. fdlibm's kernel polynomials on [-π/4, π/4] (evaluated
// by Estrin's scheme), after a three-part Cody–Waite reduction by π/2 that is exact for
// |x| < 2^19·π/2; the result is within a few ulp of the library's. Larger angles, infinities and
// NaN go to the library.
struct CosSin {
  double cos;
  double sin;
};

constexpr double kFastAngleLimit = 8.0e5;

[[gnu::always_inline]] inline CosSin cos_sin_kernel(double x) noexcept {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00;  // first 33 bits of π/2: k·kPio2Hi is exact
  constexpr double kPio2Mid = 6.07710050630396597660e-11;
  constexpr double kPio2Lo = 2.02226624871116645580e-21;
  constexpr double kRound = 6755399441055744.0;  // 1.5·2^52: adding and subtracting it rounds to nearest
  const double kd = (x * kTwoOverPi + kRound) - kRound;
  const double r = ((x - kd * kPio2Hi) - kd * kPio2Mid) - kd * kPio2Lo;

  const double z = r * r;
  const double z2 = z * z;
  const double z4 = z2 * z2;
  const double sin_poly = (-1.66666666666666324348e-01 + z * 8.33333333332248946124e-03) +
                          z2 * (-1.98412698298579493134e-04 + z * 2.75573137070700676789e-06) +
                          z4 * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10);
  const double cos_poly = (4.16666666666666019037e-02 + z * -1.38888888888741095749e-03) +
                          z2 * (2.48015872894767294178e-05 + z * -2.75573143513906633035e-07) +
                          z4 * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11);
  const double sin_r = r + r * z * sin_poly;
  const double cos_r = 1.0 - 0.5 * z + z2 * cos_poly;
  switch (static_cast<long long>(kd) & 3) {
    case 0:
      return {cos_r, sin_r};
    case 1:
      return {-sin_r, cos_r};
    case 2:
      return {-cos_r, -sin_r};
    default:
      return {sin_r, -cos_r};
  }
}

inline CosSin cos_sin(double x) noexcept {
  if (!(std::abs(x) < kFastAngleLimit)) return {std::cos(x), std::sin(x)};
  return cos_sin_kernel(x);
}

// std::remainder(x, 2π), the angle wrapped into [-π, π], without the library call for the usual
// angle within ±3 rad: there the quotient rounds to 0 and the (exact) IEEE remainder is x itself.
inline double wrap_angle(double x) noexcept {
  if (std::abs(x) <= 3.0) return x;
  return std::remainder(x, 2.0 * std::numbers::pi);
}

}  // namespace emrm::core
