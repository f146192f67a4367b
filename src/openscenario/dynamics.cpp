// The shapes of TransitionDynamics (dynamics.hpp).

#include "emrm/openscenario/dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace emrm::openscenario {
namespace {
constexpr double kSmall = 1e-6;  // esmini's SMALL_NUMBER: a shorter range is a jump
}

std::string_view shape_name(DynamicsShape shape) noexcept {
  switch (shape) {
    case DynamicsShape::kStep:
      return "step";
    case DynamicsShape::kLinear:
      return "linear";
    case DynamicsShape::kCubic:
      return "cubic";
    case DynamicsShape::kSinusoidal:
      return "sinusoidal";
  }
  return "step";
}

std::string_view dimension_name(DynamicsDimension dimension) noexcept {
  switch (dimension) {
    case DynamicsDimension::kTime:
      return "time";
    case DynamicsDimension::kDistance:
      return "distance";
    case DynamicsDimension::kRate:
      return "rate";
  }
  return "time";
}

bool Transition::jumps() const noexcept { return shape == DynamicsShape::kStep || range < kSmall; }

double Transition::value(double x) const {
  if (jumps()) return target;
  const double u = std::clamp(x, 0.0, range) / range;
  const double b = target - start;
  switch (shape) {
    case DynamicsShape::kLinear:
      return start + b * u;
    case DynamicsShape::kCubic:
      return start + b * u * u * (3.0 - 2.0 * u);
    case DynamicsShape::kSinusoidal:
      return start + b * (1.0 - std::cos(std::numbers::pi * u)) / 2.0;
    case DynamicsShape::kStep:
      break;
  }
  return target;
}

double Transition::slope(double x) const {
  if (jumps()) return 0.0;
  const double u = std::clamp(x, 0.0, range) / range;
  const double b = target - start;
  switch (shape) {
    case DynamicsShape::kLinear:
      return b / range;
    case DynamicsShape::kCubic:
      return 6.0 * b * u * (1.0 - u) / range;
    case DynamicsShape::kSinusoidal:
      return std::numbers::pi * b * std::sin(std::numbers::pi * u) / (2.0 * range);
    case DynamicsShape::kStep:
      break;
  }
  return 0.0;
}

double range_for_peak_rate(DynamicsShape shape, double start, double target, double peak_rate) {
  const double b = std::fabs(target - start);
  const double rate = std::max(std::fabs(peak_rate), kSmall);
  switch (shape) {
    case DynamicsShape::kLinear:
      return b / rate;
    case DynamicsShape::kCubic:
      return 1.5 * b / rate;
    case DynamicsShape::kSinusoidal:
      return std::numbers::pi * b / (2.0 * rate);
    case DynamicsShape::kStep:
      break;
  }
  return 0.0;
}

double range_for_peak_second_derivative(DynamicsShape shape, double start, double target,
                                        double peak_second_derivative) {
  const double b = std::fabs(target - start);
  const double a = std::max(std::fabs(peak_second_derivative), kSmall);
  switch (shape) {
    case DynamicsShape::kLinear:
    case DynamicsShape::kCubic:
      return std::sqrt(6.0 * b / a);
    case DynamicsShape::kSinusoidal:
      return std::numbers::pi * std::sqrt(b / (2.0 * a));
    case DynamicsShape::kStep:
      break;
  }
  return 0.0;
}

double duration_for_distance(double start_speed, double target_speed, double distance_m) {
  const double v0 = start_speed;
  const double v1 = target_speed;
  if (std::fabs(v1 - v0) < kSmall) return 0.0;
  if (std::fabs(v0) > kSmall && std::fabs(v1) > kSmall && (v0 > 0.0) != (v1 > 0.0)) {
    const double d0 = distance_m * v0 * v0 / (v0 * v0 + v1 * v1);
    return 2.0 * d0 / std::fabs(v0) + 2.0 * (distance_m - d0) / std::fabs(v1);
  }
  return 2.0 * distance_m / std::fabs(v0 + v1);
}

}  // namespace emrm::openscenario
