// The family "cut_in" (docs/families.md, "cut_in"; Euro NCAP's cut-in, UN R157's cut-in scenario):
// on a two-lane highway a car from the left lane cuts in ahead of the ego, slower than it by the
// relative speed, drifting right at the lateral speed until it is centred in the ego's lane, and
// brakes at the target deceleration. The TTC is the gap over the relative speed. A following car may
// occupy the left lane behind the ego; the hard shoulder lies right of the lanes, a guardrail beyond it.

#include "emrm/sim/cut_in.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "emrm/sim/family.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace {

// The family's own factors' positions in its cells, after the method's three (a namespace of their
// own, named in full where used: the unity builds put this file beside the other families).
namespace cut_in_cell {
enum Position : std::size_t { kRelativeSpeed = kMethodFactors, kLateralSpeed, kTargetDecel, kFollowing, kFactors };
}  // namespace cut_in_cell

// A car's lateral speed in a lane change stays well below this (Euro NCAP's cut-ins: 0.5 to 2 m/s),
// and no car brakes harder than this on any road (the friction limit kMaxFriction · g).
constexpr double kMaxLateralSpeed_mps = 5.0;
constexpr double kMaxTargetDecel_mps2 = 20.0;

FactorTable cut_in_factors(const SceneConfig& /*config*/) {
  std::vector<Factor> factors = method_factors(100.0, 1.5, 1.0);
  factors.resize(cut_in_cell::kFactors);
  factors[cut_in_cell::kRelativeSpeed] = {.key = "relative_speed_kph",
                                          .unit = "km/h",
                                          .what = "relative speed",
                                          .axis = "relative speed (km/h)",
                                          .plural = "relative speeds",
                                          .held = "relative speed {} km/h",
                                          .brief = "relative speed {:g} km/h",
                                          .default_value = 20.0,
                                          .limits = {.high = kMaxEgoSpeed_kph},
                                          .why_high = std::string(kWhyMaxSpeed),
                                          .name = "relative speed"};
  factors[cut_in_cell::kLateralSpeed] = {
      .key = "lateral_speed_mps",
      .unit = "m/s",
      .what = "lateral speed",
      .axis = "lateral speed (m/s)",
      .plural = "lateral speeds",
      .held = "lateral {} m/s",
      .brief = "lateral {:g} m/s",
      .default_value = 1.0,
      .limits = {.high = kMaxLateralSpeed_mps},
      .why_high = fmt::format("a lane change drifts sideways at a few m/s, not beyond {:g} m/s", kMaxLateralSpeed_mps),
      .name = "lateral speed"};
  factors[cut_in_cell::kTargetDecel] = {
      .key = "target_decel_mps2",
      .unit = "m/s²",
      .what = "target deceleration",
      .axis = "cutting car's deceleration (m/s²)",
      .plural = "decelerations",
      .held = "target brakes {} m/s²",
      .brief = "target brakes {:g} m/s²",
      .default_value = 4.0,
      .limits = {.low = 0.0, .low_inclusive = true, .high = kMaxTargetDecel_mps2},
      .why_high =
          fmt::format("no car brakes harder than {:g} m/s² (the deceleration is in m/s²)", kMaxTargetDecel_mps2),
      .name = "target deceleration"};
  factors[cut_in_cell::kFollowing] =
      categorical_factor("following", "following car", core::enum_names<FollowingTraffic>());
  return FactorTable(std::move(factors));
}

SceneLayout cut_in_layout(const SceneConfig& config, const CellInput& cell) {
  const CutInConfig& cut = config.cut_in;
  SceneLayout out;
  out.road = {.min_y_m = cut.min_y_m(),
              .max_y_m = cut.max_y_m(),
              .right = Roadside::kBarrier,  // the guardrail beyond the hard shoulder
              .left = Roadside::kBarrier};  // the median barrier
  out.ego_y_m = cut.ego_y_m();
  const double ego_mps = cell.ego_speed_kph() / 3.6;
  const double relative_mps = cell[cut_in_cell::kRelativeSpeed] / 3.6;
  if (relative_mps > ego_mps)
    out.infeasible = fmt::format("the cutting car would be {:g} km/h slower than the ego, which drives {:g} km/h",
                                 cell[cut_in_cell::kRelativeSpeed], cell.ego_speed_kph());
  // The gap closes at the relative speed: the TTC is the gap over it.
  out.initial_distance_m = relative_mps * cell.time_to_collision_s();
  // The cutting car (the hazard): its right side on the lane line, drifting right until centred in
  // the ego's lane, braking from brake_delay_s on.
  const CarBody& c = cut.cutting;
  const double lateral_mps = cell[cut_in_cell::kLateralSpeed];
  const double start_y = cut.lane_width_m + c.width_m / 2.0;
  out.actors.emplace_back(
      ActorBody{ActorKind::kCar, c.length_m, c.width_m, c.mass_kg, c.yaw_inertia_kgm2, "cutting car"},
      ActorMotion{.front = {out.initial_distance_m + c.length_m, start_y},
                  .direction = {1.0, 0.0},
                  .speed_mps = std::max(ego_mps - relative_mps, 0.0),
                  .decel_mps2 = cell[cut_in_cell::kTargetDecel],
                  .brake_from_s = cut.brake_delay_s,
                  .lateral_mps = -lateral_mps,
                  .lateral_for_s = (start_y - out.ego_y_m) / lateral_mps});
  // The following car: centred in the left lane, the time gap behind the ego's rear, overtaking.
  if (static_cast<FollowingTraffic>(cell[cut_in_cell::kFollowing]) == FollowingTraffic::kCar) {
    const CarBody& f = cut.follower;
    out.actors.emplace_back(
        ActorBody{ActorKind::kCar, f.length_m, f.width_m, f.mass_kg, f.yaw_inertia_kgm2, "following car"},
        ActorMotion{.front = {-config.ego.length_m - ego_mps * cut.following_gap_s, 1.5 * cut.lane_width_m},
                    .direction = {1.0, 0.0},
                    .speed_mps = ego_mps + cut.follower_faster_kph / 3.6});
  }
  out.passed_x_m = out.initial_distance_m + c.length_m;
  return out;
}

// The paved strip and the two lanes.
std::vector<RoadLane> cut_in_lanes(const SceneConfig& config) {
  const CutInConfig& cut = config.cut_in;
  std::vector<RoadLane> lanes;
  if (cut.shoulder_m > 0.0) lanes.push_back({cut.shoulder_m, "shoulder"});
  lanes.push_back({cut.lane_width_m, "driving"});
  lanes.push_back({cut.lane_width_m, "driving"});
  return lanes;
}

}  // namespace

ScenarioFamilyInfo cut_in_family() {
  return {.name = "cut_in",
          .description =
              "Euro NCAP's and UN R157's cut-in: on a two-lane highway a slower car cuts in from the left lane and "
              "brakes; a car may be overtaking in the left lane behind the ego",
          .factors = cut_in_factors,
          .layout = cut_in_layout,
          .lanes = cut_in_lanes,
          .stop_boundary = false};
}

}  // namespace emrm::sim
