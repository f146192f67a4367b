// The family "pedestrian_crossing" (docs/families.md, "pedestrian_crossing"; Euro NCAP's CPNC): on a
// two-lane street a pedestrian steps out from behind a parked car on the right and walks across
// (+y) without stopping; the ego drives in the right lane; an oncoming car may fill the left lane. A
// row of parked cars stands beyond the right edge, a kerb and a sidewalk beyond the left one.

#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "emrm/sim/crossing.hpp"
#include "emrm/sim/family.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace {

// The family's own factors' positions in its cells, after the method's three (a namespace of their
// own, named in full where used: the unity builds put this file beside the other families).
namespace crossing_cell {
enum Position : std::size_t { kPedestrianSpeed = kMethodFactors, kOncoming, kFactors };
}  // namespace crossing_cell

// The fastest a pedestrian runs: a sprinter's 36 km/h bounds any walking or running speed.
constexpr double kMaxPedestrianSpeed_kph = 36.0;

FactorTable crossing_factors(const SceneConfig& config) {
  std::vector<Factor> factors = method_factors(40.0, 1.2, 1.0);
  factors.resize(crossing_cell::kFactors);
  factors[crossing_cell::kPedestrianSpeed] = {
      .key = "pedestrian_speed_kph",
      .unit = "km/h",
      .what = "pedestrian speed",
      .axis = "pedestrian speed (km/h)",
      .plural = "pedestrian speeds",
      .held = "pedestrian at {} km/h",
      .brief = "pedestrian {:g} km/h",
      .default_value = config.crossing.pedestrian.speed_kph,
      .limits = {.high = kMaxPedestrianSpeed_kph},
      .why_high = fmt::format("a pedestrian runs at most about {:g} km/h", kMaxPedestrianSpeed_kph),
      .name = "pedestrian speed"};
  factors[crossing_cell::kOncoming] =
      categorical_factor("oncoming", "oncoming traffic", core::enum_names<OncomingTraffic>());
  return FactorTable(std::move(factors));
}

SceneLayout crossing_layout(const SceneConfig& config, const CellInput& cell) {
  const CrossingConfig& crossing = config.crossing;
  SceneLayout out;
  out.road = {.min_y_m = crossing.min_y_m(),
              .max_y_m = crossing.max_y_m(),
              .right = Roadside::kBarrier,  // the row of parked cars
              .left = Roadside::kOpen};     // a kerb and the sidewalk
  out.ego_y_m = crossing.ego_y_m();
  const double speed_mps = cell.ego_speed_kph() / 3.6;
  out.initial_distance_m = speed_mps * cell.time_to_collision_s();
  const ObstacleConfig& p = crossing.pedestrian;
  const double pedestrian_x = out.initial_distance_m + p.width_m / 2.0;
  // The pedestrian (the hazard): its front at the parked car's side when it comes into view, walking +y.
  out.actors.emplace_back(
      ActorBody{ActorKind::kPedestrian, p.length_m, p.width_m, p.mass_kg, p.yaw_inertia_kgm2, "pedestrian"},
      ActorMotion{.front = {pedestrian_x, -crossing.parked_gap_m},
                  .direction = {0.0, 1.0},
                  .speed_mps = cell[crossing_cell::kPedestrianSpeed] / 3.6});
  // The parked car it stepped out from behind, just short of it, beyond the right edge.
  const ObstacleConfig& parked = crossing.parked;
  constexpr double kBehind_m = 0.1;
  out.actors.emplace_back(
      ActorBody{ActorKind::kCar, parked.length_m, parked.width_m, parked.mass_kg, parked.yaw_inertia_kgm2,
                "parked car"},
      ActorMotion{.front = {out.initial_distance_m - kBehind_m, -crossing.parked_gap_m - parked.width_m / 2.0}});
  // The oncoming car: centred in the left lane, level with the pedestrian at t = TTC.
  if (static_cast<OncomingTraffic>(cell[crossing_cell::kOncoming]) == OncomingTraffic::kCar) {
    const ObstacleConfig& o = crossing.oncoming;
    const double oncoming_mps = o.speed_kph / 3.6;
    out.actors.emplace_back(
        ActorBody{ActorKind::kCar, o.length_m, o.width_m, o.mass_kg, o.yaw_inertia_kgm2, "oncoming car"},
        ActorMotion{.front = {pedestrian_x + oncoming_mps * cell.time_to_collision_s(), 1.5 * crossing.lane_width_m},
                    .direction = {-1.0, 0.0},
                    .speed_mps = oncoming_mps});
  }
  out.passed_x_m = out.initial_distance_m + p.width_m;
  return out;
}

// The ego's lane and the oncoming one.
std::vector<RoadLane> crossing_lanes(const SceneConfig& config) {
  const double w = config.crossing.lane_width_m;
  return {{w, "driving"}, {w, "driving", true}};
}

}  // namespace

ScenarioFamilyInfo pedestrian_crossing_family() {
  return {.name = "pedestrian_crossing",
          .description =
              "Euro NCAP's CPNC: on a two-lane street a pedestrian steps out from behind a parked car on the right "
              "and walks across; an oncoming car may fill the other lane",
          .factors = crossing_factors,
          .layout = crossing_layout,
          .lanes = crossing_lanes};
}

}  // namespace emrm::sim
