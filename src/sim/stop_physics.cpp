#include "emrm/sim/stop_physics.hpp"

#include <algorithm>
#include <optional>

#include "emrm/sim/loss.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

double stop_boundary_ttc_s(double speed_kph, double mu, const ActuationConfig& actuation) noexcept {
  const double v = speed_kph / 3.6;
  return actuation.stopping_distance_m(v, mu, true) / v;
}

double stop_margin_m(double speed_kph, double ttc_s, double mu, const ActuationConfig& actuation) noexcept {
  const double v = speed_kph / 3.6;
  return v * ttc_s - actuation.stopping_distance_m(v, mu, true);
}

bool analytically_stoppable(double speed_kph, double ttc_s, double mu, const ActuationConfig& actuation) noexcept {
  constexpr double kOnTheBoundary_s = 1e-9;
  return stop_margin_m(speed_kph, ttc_s + kOnTheBoundary_s, mu, actuation) >= 0.0;
}

bool analytically_stoppable(const CellInput& cell, const ActuationConfig& actuation) noexcept {
  return analytically_stoppable(cell.ego_speed_kph(), cell.time_to_collision_s(), cell.friction(), actuation);
}

namespace {

// Whether the truck overlaps the car's straight path across the lane from t = `from_s` until it
// rests (its front below the car's left side then, its rear above the car's right side at rest):
// it is then in the way whenever the car, going straight, gets there from `from_s` on. A truck
// that keeps going clears the lane in the end, so it never stands in the way for certain.
bool in_the_way_from(const Scene& s, double from_s) {
  const SceneConfig& scene = s.config();
  if (scene.truck.decel_mps2 <= 0.0 && s.hazard_speed_mps() > 0.0) return false;
  const double top = scene.road.ego_lane_center_m + scene.ego.width_m / 2.0;
  const double bottom = scene.road.ego_lane_center_m - scene.ego.width_m / 2.0;
  const double rest_s = scene.truck.decel_mps2 > 0.0 ? s.hazard_speed_mps() / scene.truck.decel_mps2 : 0.0;
  const double rear_at_rest = s.truck_front_y_at(rest_s) + scene.truck.length_m;
  constexpr double kOverlap_m = 0.01;  // of the truck and the car's path, for certain
  return s.truck_front_y_at(from_s) < top - kOverlap_m && rear_at_rest > bottom + kOverlap_m;
}

// What doing nothing comes to in a cell; none for a cell the car cannot start in.
std::optional<RolloutResult> no_action_of(const SceneConfig& scene, const CellInput& cell) {
  const Scene s(scene, cell);
  if (!s.feasible()) return std::nullopt;
  const auto model = make_vehicle_model(scene.simulation.vehicle_model, scene.ego);
  return no_action_rollout(s, *model);
}

}  // namespace

bool nothing_to_mitigate(const SceneConfig& scene, const CellInput& cell) {
  const auto nothing = no_action_of(scene, cell);
  return nothing && nothing->termination == Termination::kContact &&
         nothing->impact.loss_level <= loss_level(true, false, 0.0, 0.0, scene.severity);
}

bool may_pass_early(const SceneConfig& scene, const CellInput& cell) {
  const Scene s(scene, cell);
  if (!(s.hazard_speed_mps() > 0.0)) return false;
  // Until the first actuator moves (the perception latency, then the quicker of the brakes' and the
  // steering's dead times) the car goes straight at its speed: its front reaches the truck's near
  // side at t = TTC (v·TTC is the gap; rolling on, it loses a few millimetres, hence the 20 ms).
  // Reaching it before it can act, into a truck that is in its way, it hits: no strategy avoids.
  const ActuationConfig& a = scene.actuation;
  const double first_action_s = a.perception_latency_s + std::min(a.brake_dead_time_s, a.steer_dead_time_s);
  constexpr double kRolling_s = 0.02;
  if (!(s.ttc_s() + kRolling_s <= first_action_s)) return true;
  if (in_the_way_from(s, s.ttc_s())) return false;
  // A truck still entering the car's path may meet it before it can act all the same: every
  // strategy drives the car as doing nothing does until then (the same states, step by step), so a
  // contact of the no-action rollout a step before the first action is every strategy's.
  const auto nothing = no_action_of(scene, cell);
  return !(nothing && nothing->termination == Termination::kContact &&
           nothing->end_time_s + scene.simulation.dt_s <= first_action_s);
}

StopCall stop_call(const SceneConfig& scene, const CellInput& cell) {
  const Scene s(scene, cell);
  const double margin = stop_margin_m(s.speed_kph(), s.ttc_s(), s.friction(), scene.actuation);
  if (margin > kStopAgreement_m) return StopCall::kStops;
  if (!(margin < -kStopAgreement_m)) return StopCall::kUnknown;
  // Braking straight, the car's front reaches the truck's near side no earlier than at t = TTC (at
  // its initial speed throughout; v·TTC is the gap) and, short of the stop by more than the margin,
  // it does reach it. So if the truck is in the way from t = TTC on, braking cannot avoid it,
  // neither by stopping short nor by passing in front of it before it arrives.
  return in_the_way_from(s, s.ttc_s()) ? StopCall::kCannotStop : StopCall::kUnknown;
}

}  // namespace emrm::sim
