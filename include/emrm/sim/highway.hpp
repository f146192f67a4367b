#pragma once

// The highway of the family "highway_obstacle" (docs/families.md, "highway_obstacle"; the paper's
// introduction): a multi-lane carriageway with a hard shoulder on the right and the median barrier on
// the left, and the obstacle that enters it from the right roadside — a truck or a deer — with its
// body and how it stops. The scene's `highway:` block; the cell's factors pick the obstacle, how far
// it reaches into the road and what lies beyond the right edge.

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "emrm/core/config.hpp"
#include "emrm/core/enum_names.hpp"
#include "emrm/sim/obstacle_config.hpp"

namespace emrm::sim {

/// The obstacle's kinds, the levels of the factor `obstacle` (in this order).
enum class HighwayObstacle : std::uint8_t { kTruck, kDeer };
/// What lies beyond the right edge, the levels of the factor `roadside` (in this order).
enum class HighwayRoadside : std::uint8_t { kGuardrail, kEmbankment };

struct HighwayConfig {
  int lanes = 2;  ///< in the ego's direction
  double lane_width_m = 3.75;
  double shoulder_m = 2.5;  ///< the hard shoulder, drivable, right of the lanes
  int ego_lane = 1;         ///< counted from the right
  /// The embankment's slope, horizontal run per unit of drop (2: 1V:2H, steeper than the critical
  /// 1V:3H: docs/physics.md, "Road departure").
  double embankment_slope_h = 2.0;
  /// A rigid truck entering from a field access or a rest area; it stops `blocked_m` into the road.
  ObstacleConfig truck{.length_m = 12.0,
                       .width_m = 2.55,
                       .mass_kg = 18000.0,
                       .yaw_inertia_kgm2 = 226000.0,
                       .speed_kph = 10.0,
                       .decel_mps2 = 4.0};
  /// A white-tailed deer (docs/families.md, "Sources"): 1.6 m long, 70 kg, walking in at 10 km/h.
  ObstacleConfig deer{
      .length_m = 1.6, .width_m = 0.5, .mass_kg = 70.0, .yaw_inertia_kgm2 = 16.4, .speed_kph = 10.0, .decel_mps2 = 4.0};

  /// The drivable area's right edge (the shoulder's outer edge) and left edge (the median barrier),
  /// y = 0 on the right lane's outer line.
  [[nodiscard]] double min_y_m() const noexcept { return -shoulder_m; }
  [[nodiscard]] double max_y_m() const noexcept { return lanes * lane_width_m; }
  [[nodiscard]] double ego_y_m() const noexcept { return (ego_lane - 0.5) * lane_width_m; }

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, lanes, core::at_least(1, "lane"));
    EMRM_FIELD(a, lane_width_m, core::positive);
    EMRM_FIELD(a, shoulder_m, core::non_negative);
    EMRM_FIELD(a, ego_lane, core::at_least(1, "lane"));
    EMRM_FIELD(a, embankment_slope_h, core::positive);
    EMRM_FIELD(a, truck);
    EMRM_FIELD(a, deer);
    a.ensure(ego_lane <= lanes, "ego_lane", "expected one of the {} lanes, got lane {}", lanes, ego_lane);
    // It stops blocked_m into the road: it must brake.
    a.ensure(truck.decel_mps2 > 0.0, "truck.decel_mps2", "expected a value > 0 (it stops in the road), got {}",
             truck.decel_mps2);
    a.ensure(deer.decel_mps2 > 0.0, "deer.decel_mps2", "expected a value > 0 (it stops in the road), got {}",
             deer.decel_mps2);
  }
};

/// The shipped "highway_obstacle" family (sim/highway_obstacle.cpp).
struct ScenarioFamilyInfo;
[[nodiscard]] ScenarioFamilyInfo highway_obstacle_family();

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::HighwayObstacle> {
  static constexpr std::array<std::pair<emrm::sim::HighwayObstacle, std::string_view>, 2> kNames{{
      {emrm::sim::HighwayObstacle::kTruck, "truck"},
      {emrm::sim::HighwayObstacle::kDeer, "deer"},
  }};
};

template <>
struct emrm::core::EnumNames<emrm::sim::HighwayRoadside> {
  static constexpr std::array<std::pair<emrm::sim::HighwayRoadside, std::string_view>, 2> kNames{{
      {emrm::sim::HighwayRoadside::kGuardrail, "guardrail"},
      {emrm::sim::HighwayRoadside::kEmbankment, "embankment"},
  }};
};
