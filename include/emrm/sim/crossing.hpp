#pragma once

// The urban street of the family "pedestrian_crossing" (docs/families.md, "pedestrian_crossing";
// Euro NCAP's CPNC, a child stepping out from behind a parked car): a two-lane road, the ego's lane
// and the oncoming one, with a row of parked cars beyond its right edge; a pedestrian steps out from
// behind one of them and walks across, and an oncoming car may fill the other lane. The scene's
// `crossing:` block; the cell's factors set the pedestrian's walking speed and whether the car comes.

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>

#include "emrm/core/config.hpp"
#include "emrm/core/enum_names.hpp"
#include "emrm/sim/obstacle_config.hpp"

namespace emrm::sim {

/// Whether a car comes the other way, the levels of the factor `oncoming` (in this order).
enum class OncomingTraffic : std::uint8_t { kNone, kCar };

struct CrossingConfig {
  double lane_width_m = 3.5;  ///< two lanes: the ego's (y in [0, w]) and the oncoming one
  double parked_gap_m = 0.3;  ///< from the road's right edge to the parked car's side
  /// The parked car the pedestrian steps out from behind; it stands still (speed 0).
  ObstacleConfig parked{.length_m = 4.5,
                        .width_m = 1.8,
                        .mass_kg = 1400.0,
                        .yaw_inertia_kgm2 = 2300.0,
                        .speed_kph = 0.0,
                        .decel_mps2 = 0.0};
  /// The pedestrian, walking across (along +y) without stopping; speed_kph is the factor's default
  /// (Euro NCAP's child of CPNC walks at 5 km/h).
  ObstacleConfig pedestrian{
      .length_m = 0.3, .width_m = 0.5, .mass_kg = 75.0, .yaw_inertia_kgm2 = 2.1, .speed_kph = 5.0, .decel_mps2 = 0.0};
  /// The oncoming car, centred in its lane, driving −x at its speed; it draws level with the
  /// pedestrian when the ego would (at t = TTC).
  ObstacleConfig oncoming{.length_m = 4.5,
                          .width_m = 1.8,
                          .mass_kg = 1500.0,
                          .yaw_inertia_kgm2 = 2500.0,
                          .speed_kph = 50.0,
                          .decel_mps2 = 0.0};

  [[nodiscard]] double min_y_m() const noexcept { return 0.0; }
  [[nodiscard]] double max_y_m() const noexcept { return 2.0 * lane_width_m; }
  [[nodiscard]] double ego_y_m() const noexcept { return lane_width_m / 2.0; }

  template <class A>
  void serialize(A& a) {
    EMRM_FIELD(a, lane_width_m, core::positive);
    EMRM_FIELD(a, parked_gap_m, core::non_negative);
    EMRM_FIELD(a, parked);
    EMRM_FIELD(a, pedestrian);
    EMRM_FIELD(a, oncoming);
    a.ensure(pedestrian.decel_mps2 == 0.0, "pedestrian.decel_mps2",
             "expected 0 (the pedestrian walks across without stopping), got {}", pedestrian.decel_mps2);
    a.ensure(pedestrian.speed_kph > 0.0, "pedestrian.speed_kph", "expected a walking speed > 0, got {}",
             pedestrian.speed_kph);
  }
};

/// The shipped "pedestrian_crossing" family (sim/pedestrian_crossing.cpp).
struct ScenarioFamilyInfo;
[[nodiscard]] ScenarioFamilyInfo pedestrian_crossing_family();

}  // namespace emrm::sim

template <>
struct emrm::core::EnumNames<emrm::sim::OncomingTraffic> {
  static constexpr std::array<std::pair<emrm::sim::OncomingTraffic, std::string_view>, 2> kNames{{
      {emrm::sim::OncomingTraffic::kNone, "none"},
      {emrm::sim::OncomingTraffic::kCar, "car"},
  }};
};
