// The family "highway_obstacle" (docs/families.md, "highway_obstacle"; the paper's introduction): on
// a multi-lane highway a truck or a deer enters from the right roadside, heading +y, and stops with
// its front `blocked_m` into the drivable area. The ego drives in its lane; the median barrier is on
// the left, a guardrail or an embankment beyond the hard shoulder on the right.

#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "emrm/sim/family.hpp"
#include "emrm/sim/highway.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace {

// The family's own factors' positions in its cells, after the method's three (a namespace of their own:
// the unity builds put this file beside tjunction.cpp).
namespace highway_cell {
enum Position : std::size_t { kObstacle = kMethodFactors, kBlocked, kRoadside, kFactors };
}  // namespace highway_cell
using highway_cell::kBlocked;
using highway_cell::kFactors;
using highway_cell::kObstacle;
using highway_cell::kRoadside;

FactorTable highway_factors(const SceneConfig& config) {
  const HighwayConfig& highway = config.highway;
  const double width_m = highway.max_y_m() - highway.min_y_m();
  std::vector<Factor> factors = method_factors(100.0, 1.2, 0.8);
  factors.resize(kFactors);
  factors[kObstacle] = categorical_factor("obstacle", "obstacle", core::enum_names<HighwayObstacle>());
  factors[kBlocked] = {
      .key = "blocked_m",
      .unit = "m",
      .what = "blocked width",
      .axis = "blocked width (m)",
      .plural = "blocked widths",
      .held = "blocked {} m",
      .brief = "blocked {:g} m",
      .default_value = highway.shoulder_m + highway.lane_width_m,
      .limits = {.high = width_m},
      .why_high = fmt::format("the drivable area is {:g} m wide: the obstacle cannot reach further into it", width_m),
      .name = "blocked width"};
  factors[kRoadside] = categorical_factor("roadside", "roadside", core::enum_names<HighwayRoadside>());
  return FactorTable(std::move(factors));
}

SceneLayout highway_layout(const SceneConfig& config, const CellInput& cell) {
  const HighwayConfig& highway = config.highway;
  SceneLayout out;
  const bool embankment = static_cast<HighwayRoadside>(cell[kRoadside]) == HighwayRoadside::kEmbankment;
  out.road = {.min_y_m = highway.min_y_m(),
              .max_y_m = highway.max_y_m(),
              .right = embankment ? Roadside::kEmbankment : Roadside::kBarrier,
              .left = Roadside::kBarrier,  // the median barrier
              .right_slope_h = embankment ? highway.embankment_slope_h : 0.0};
  out.ego_y_m = highway.ego_y_m();
  out.initial_distance_m = cell.ego_speed_kph() / 3.6 * cell.time_to_collision_s();
  const bool deer = static_cast<HighwayObstacle>(cell[kObstacle]) == HighwayObstacle::kDeer;
  const ObstacleConfig& o = deer ? highway.deer : highway.truck;
  // It stops with its front blocked_m into the road: it starts its braking distance short of that.
  const double speed_mps = o.speed_kph / 3.6;
  const double travel_m = speed_mps * speed_mps / (2.0 * o.decel_mps2);
  const ActorMotion motion{
      .front = {out.initial_distance_m + o.width_m / 2.0, out.road.min_y_m + cell[kBlocked] - travel_m},
      .direction = {0.0, 1.0},  // from the right roadside
      .speed_mps = speed_mps,
      .decel_mps2 = o.decel_mps2};
  out.actors.emplace_back(ActorBody{deer ? ActorKind::kAnimal : ActorKind::kTruck, o.length_m, o.width_m, o.mass_kg,
                                    o.yaw_inertia_kgm2, deer ? "deer" : "truck"},
                          motion);
  out.passed_x_m = out.initial_distance_m + o.width_m;
  return out;
}

std::vector<RoadLane> highway_lanes(const SceneConfig& config) {
  const HighwayConfig& highway = config.highway;
  std::vector<RoadLane> lanes;
  if (highway.shoulder_m > 0.0) lanes.push_back({highway.shoulder_m, "shoulder"});
  for (int i = 0; i < highway.lanes; ++i) lanes.push_back({highway.lane_width_m, "driving"});
  return lanes;
}

}  // namespace

ScenarioFamilyInfo highway_obstacle_family() {
  return {.name = "highway_obstacle",
          .description =
              "the paper's introduction: on a multi-lane highway a truck or a deer enters from the right "
              "roadside and stops blocking the road; a guardrail or an embankment beyond the shoulder",
          .factors = highway_factors,
          .layout = highway_layout,
          .lanes = highway_lanes};
}

}  // namespace emrm::sim
