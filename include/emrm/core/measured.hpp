#pragma once

// Measured quantities as sensors record them: what is noise, read as the value it stands for, and
// what is physically wrong, refused. Shared by every reader of recorded data (calibration traces,
// recorded trajectories).

#include <fmt/format.h>

#include <optional>
#include <string>

namespace emrm::core {

/// Wheel-speed and GNSS traces dither around zero at standstill by a few cm/s: a measured speed down
/// to −kStandstillDither_mps is a car at rest, read as 0; a more negative one is refused.
inline constexpr double kStandstillDither_mps = 0.05;

/// A measured speed as emrm reads it: 0 for the dither of a car at rest, the value itself when it is
/// ≥ 0, nothing when it is below −kStandstillDither_mps (or NaN).
[[nodiscard]] constexpr std::optional<double> measured_speed_mps(double v) noexcept {
  if (v >= 0.0) return v;
  if (v >= -kStandstillDither_mps) return 0.0;
  return std::nullopt;
}

/// What a refused measured speed is told: "expected a speed >= 0 m/s (a car at rest may dither down
/// to -0.05 m/s), got -0.5".
[[nodiscard]] inline std::string measured_speed_refusal(double v) {
  return fmt::format("expected a speed >= 0 m/s (a car at rest may dither down to -{} m/s), got {}",
                     kStandstillDither_mps, v);
}

}  // namespace emrm::core
