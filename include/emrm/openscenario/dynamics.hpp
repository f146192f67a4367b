#pragma once

// TransitionDynamics: how a value (a speed, a lateral offset) goes from its start to its target
// over a parameter range (a duration, a distance), in the standard's four shapes, as esmini
// evaluates them. With a = start, b = target - start, P = the range and x in [0, P]:
//   step        f(x) = a + b                       (at once)
//   linear      f(x) = a + b x/P
//   cubic       f(x) = a + b (x/P)^2 (3 - 2 x/P)   (zero slope at both ends)
//   sinusoidal  f(x) = a + b (1 - cos(pi x/P))/2   (zero slope at both ends)

#include <string_view>

namespace emrm::openscenario {

enum class DynamicsShape { kStep, kLinear, kCubic, kSinusoidal };
enum class DynamicsDimension { kTime, kDistance, kRate };

[[nodiscard]] std::string_view shape_name(DynamicsShape shape) noexcept;
[[nodiscard]] std::string_view dimension_name(DynamicsDimension dimension) noexcept;

/// The transition of one value: start, target and the parameter range P (s or m) it takes.
struct Transition {
  DynamicsShape shape = DynamicsShape::kStep;
  double start = 0.0;
  double target = 0.0;
  double range = 0.0;  ///< P; a step, or P <= 0, jumps to the target at once

  /// f(x), with x clamped to [0, P].
  [[nodiscard]] double value(double x) const;
  /// f'(x), with x clamped to [0, P]; 0 for a step.
  [[nodiscard]] double slope(double x) const;
  /// Whether f jumps (a step, or an empty range).
  [[nodiscard]] bool jumps() const noexcept;
};

/// The range P over which `shape` goes from `start` to `target` with its steepest slope equal to
/// `peak_rate` (dynamicsDimension rate): |b|/|rate| times 1 (linear), pi/2 (sinusoidal), 3/2 (cubic).
[[nodiscard]] double range_for_peak_rate(DynamicsShape shape, double start, double target, double peak_rate);

/// The range P over which `shape` goes from `start` to `target` with its largest second derivative
/// equal to `peak_curvature` (a LaneOffsetAction's maxLateralAcc): pi sqrt(|b|/(2 a)) for
/// sinusoidal, sqrt(6 |b|/a) for cubic and, as esmini, for linear (whose own is unbounded).
[[nodiscard]] double range_for_peak_second_derivative(DynamicsShape shape, double start, double target,
                                                      double peak_second_derivative);

/// A speed change over `distance_m` expressed as a duration, as esmini does: the shapes are
/// symmetric, so the distance covered is the duration times the mean of the two speeds, and
/// T = 2 d / |v0 + v1| (through zero speed, the two parts each at their own mean).
[[nodiscard]] double duration_for_distance(double start_speed, double target_speed, double distance_m);

}  // namespace emrm::openscenario
