#pragma once

// The highway of the family "cut_in" (docs/families.md, "cut_in"; Euro NCAP's cut-in and UN R157's
// cut-in scenario): two lanes in the ego's direction, a hard shoulder on the right and the median
// barrier on the left. A car overtaking in the left lane cuts in ahead of the ego, slower than it,
// and brakes; a following car may occupy the left lane behind the ego. The scene's `cut_in:` block;
// the cell's factors set the relative speed, the lateral speed, the cutting car's deceleration and
// whether the left lane is occupied.

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "emrm/core/config.hpp"
#include "emrm/core/enum_names.hpp"

namespace emrm::sim {

/// Whether a car follows in the adjacent lane, the levels of the factor `following` (in this order).
enum class FollowingTraffic : std::uint8_t { kNone, kCar };

/// A car of the cut-in's traffic: its footprint, mass and yaw inertia (its motion is the cell's).
struct CarBody {
  double length_m = 4.5;
  double width_m = 1.8;
  double mass_kg = 1500.0;
  double yaw_inertia_kgm2 = 2500.0;  ///< ≈ m (L² + W²) / 12

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, length_m, core::positive);
    EMRM_FIELD(a, width_m, core::positive);
    EMRM_FIELD(a, mass_kg, core::positive);
    EMRM_FIELD(a, yaw_inertia_kgm2, core::positive);
  }
};

struct CutInConfig {
  double lane_width_m = 3.75;  ///< two lanes: the ego's (y in [0, w]) and the left one (y in [w, 2w])
  /// The paved strip right of the lanes, drivable, with the guardrail beyond it: a motorway without a
  /// hard shoulder (all-lane running, roadworks), where a swerve right has little room.
  double shoulder_m = 0.5;
  /// The car that cuts in: when the hazard appears its right side is on the lane line and its rear
  /// the gap ahead of the ego's front; it drifts right until it is centred in the ego's lane.
  CarBody cutting{};
  /// The cutting car starts braking this long after it appears (0: at once).
  double brake_delay_s = 0.0;
  /// The car following in the left lane (factor `following`): centred in it, its front this time gap
  /// (at the ego's speed) behind the ego's rear, overtaking faster than the ego by this much; it
  /// keeps its speed.
  CarBody follower{};
  double following_gap_s = 0.5;
  double follower_faster_kph = 20.0;

  [[nodiscard]] double min_y_m() const noexcept { return -shoulder_m; }
  [[nodiscard]] double max_y_m() const noexcept { return 2.0 * lane_width_m; }
  [[nodiscard]] double ego_y_m() const noexcept { return lane_width_m / 2.0; }

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, lane_width_m, core::positive);
    EMRM_FIELD(a, shoulder_m, core::non_negative);
    EMRM_FIELD(a, cutting);
    EMRM_FIELD(a, brake_delay_s, core::non_negative);
    EMRM_FIELD(a, follower);
    EMRM_FIELD(a, following_gap_s, core::non_negative);
    EMRM_FIELD(a, follower_faster_kph, core::non_negative);
    // The cutting car starts beside the ego's lane, in the left one: it must fit there.
    a.ensure(cutting.width_m <= lane_width_m, "cutting.width_m",
             "expected a car no wider than the lane ({} m), got {} m", lane_width_m, cutting.width_m);
  }
};

/// The shipped "cut_in" family (sim/cut_in.cpp).
struct ScenarioFamilyInfo;
[[nodiscard]] ScenarioFamilyInfo cut_in_family();

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::FollowingTraffic> {
  static constexpr std::array<std::pair<emrm::sim::FollowingTraffic, std::string_view>, 2> kNames{{
      {emrm::sim::FollowingTraffic::kNone, "none"},
      {emrm::sim::FollowingTraffic::kCar, "car"},
  }};
};
