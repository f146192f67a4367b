// The T-junction family "EMRM Scene 1" (docs/families.md, "tjunction"; the paper's simulated
// case): its factors and the layout of a cell. A truck crosses the main road from a side road on the
// left, heading -y, and brakes to a standstill in the ego's path; the passage left on the right is a
// factor.

#include <fmt/format.h>

#include <array>
#include <string_view>
#include <utility>
#include <vector>

#include "emrm/sim/family.hpp"
#include "emrm/sim/scene.hpp"

namespace emrm::sim {
namespace {

using tjunction::kMu;
using tjunction::kPassage;
using tjunction::kSpeed;
using tjunction::kTruckSpeed;
using tjunction::kTtc;

double drivable_width_m(const SceneConfig& config) noexcept {
  return config.road.drivable_max_y_m() - config.road.drivable_min_y_m();
}

// The values each factor accepts, in cell order: the one owner of scenario_factors' limits, which
// validate_cell reads without building the table's texts (it runs for every cell simulated).
std::array<FactorLimits, tjunction::kFactors> factor_limits(const SceneConfig& config) noexcept {
  std::array<FactorLimits, tjunction::kFactors> limits{};
  limits[kSpeed].high = kMaxEgoSpeed_kph;
  limits[kMu].high = kMaxFriction;
  limits[kPassage].high = drivable_width_m(config);
  limits[kTruckSpeed] = {.low = 0.0, .low_inclusive = true, .high = kMaxEgoSpeed_kph};
  return limits;
}

FactorTable tjunction_factors(const SceneConfig& config) {
  const double width_m = drivable_width_m(config);
  const auto limits = factor_limits(config);
  const TJunctionCell defaults;
  std::vector<Factor> factors = method_factors(defaults.speed_kph, defaults.ttc_s, defaults.mu);
  factors.resize(tjunction::kFactors);
  factors[kPassage] = {
      .key = "passage_m",
      .unit = "m",
      .what = "passage width",
      .axis = "passage width (m)",
      .plural = "passage widths",
      .held = "passage {} m",
      .brief = "passage {:g} m",
      .role = FactorRole::kPassage,
      .default_value = defaults.passage_m,
      .limits = limits[kPassage],
      .why_high = fmt::format("the drivable area is {:g} m wide: a wider passage is wider than the road", width_m),
      .name = "passage"};
  factors[kTruckSpeed] = {.key = "truck_speed_kph",
                          .unit = "km/h",
                          .what = "truck speed",
                          .axis = "truck speed (km/h)",
                          .plural = "truck speeds",
                          .held = "truck {} km/h",
                          .brief = "truck {:g} km/h",
                          .role = FactorRole::kOther,
                          .default_value = config.truck.speed_kph,
                          .limits = limits[kTruckSpeed],
                          .why_high = std::string(kWhyMaxSpeed),
                          .band = 1.0,
                          .name = "truck speed"};
  return FactorTable(std::move(factors));
}

void validate_tjunction_cell(const SceneConfig& config, const CellInput& cell) {
  const auto limits = factor_limits(config);
  bool accepted = cell.size() == limits.size();
  for (std::size_t i = 0; accepted && i < limits.size(); ++i) accepted = limits[i].accepts(cell[i]);
  if (!accepted) tjunction_factors(config).validate(cell);  // throws, naming the factor and its limits
}

SceneLayout tjunction_layout(const SceneConfig& config, const CellInput& cell) {
  SceneLayout out;
  const RoadConfig& road = config.road;
  const Roadside roadside = *core::enum_from_name<Roadside>(config.roadside.type);
  const double slope_h = config.roadside.embankment_slope_h;
  out.road = {road.drivable_min_y_m(), road.drivable_max_y_m(), roadside, roadside, slope_h, slope_h};
  out.ego_y_m = road.ego_lane_center_m;
  out.initial_distance_m = cell.ego_speed_kph() / 3.6 * cell.time_to_collision_s();
  // passage_m is the gap once the truck stands (or, never stopping, at t = TTC): the truck
  // starts that far plus its travel until then above the right edge of the drivable area.
  const TruckConfig& truck = config.truck;
  const double speed_mps = cell[kTruckSpeed] / 3.6;
  const double a = truck.decel_mps2;
  const double travel_m = a > 0.0 ? speed_mps * speed_mps / (2.0 * a) : speed_mps * cell.time_to_collision_s();
  const ActorMotion motion{
      .front = {out.initial_distance_m + truck.width_m / 2.0, road.drivable_min_y_m() + cell[kPassage] + travel_m},
      .direction = {0.0, -1.0},  // it crosses from the side road on the left
      .speed_mps = speed_mps,
      .decel_mps2 = a};
  out.actors.emplace_back(
      ActorBody{ActorKind::kTruck, truck.length_m, truck.width_m, truck.mass_kg, truck.yaw_inertia_kgm2, "truck"},
      motion);
  out.passed_x_m = out.initial_distance_m + truck.width_m;
  return out;
}

}  // namespace

ScenarioFamilyInfo tjunction_family() {
  return {.name = "tjunction",
          .description =
              "the paper's EMRM Scene 1: a truck crosses from a side road on the left and stops in the "
              "ego's path, leaving a passage on the right",
          .factors = tjunction_factors,
          .layout = tjunction_layout,
          .validate_cell = validate_tjunction_cell,
          .tjunction_analytics = true};
}

TJunctionCell TJunctionCell::of(const CellInput& cell) noexcept {
  return {cell[kSpeed], cell[kTtc], cell[kMu], cell[kPassage], cell[kTruckSpeed]};
}

}  // namespace emrm::sim
