#include "emrm/sim/stop_physics.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "emrm/sim/loss.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

bool stop_boundary_applies(const SceneConfig& scene) { return find_family(scene.family)->stop_boundary; }

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

// Whether the hazard overlaps the car's straight path across the lane from t = `from_s` until it
// rests (the T-junction's truck: its front below the car's left side then, its rear above the car's
// right side at rest): it is then in the way whenever the car, going straight, gets there from
// `from_s` on. Its extent across the road moves one way only (a motion along y, no sideways drift),
// so overlapping at both ends it overlaps throughout. A hazard that keeps going clears the lane in
// the end, so it never stands in the way for certain.
bool in_the_way_from(const Scene& s, double from_s) {
  const ActorMotion& motion = s.hazard().motion();
  if (motion.track || std::isinf(motion.rest_time_s()) || motion.direction.x != 0.0 || motion.lateral_mps != 0.0)
    return false;
  const double lane_y = s.ego_initial().y_m;
  const double half_width = s.config().ego.width_m / 2.0;
  const double top = lane_y + half_width;
  const double bottom = lane_y - half_width;
  constexpr double kOverlap_m = 0.01;  // of the hazard and the car's path, for certain
  const auto overlaps = [&](double t_s) {
    const auto [low, high] = s.hazard().y_extent_at(t_s);
    return low < top - kOverlap_m && high > bottom + kOverlap_m;
  };
  return overlaps(from_s) && overlaps(std::max(from_s, motion.rest_time_s()));
}

// What doing nothing comes to in a cell; none for a cell the car cannot start in.
std::optional<RolloutResult> no_action_of(const SceneConfig& scene, const CellInput& cell) {
  const Scene s(scene, cell);
  if (!s.feasible()) return std::nullopt;
  const auto model = make_vehicle_model(scene.simulation.vehicle_model, scene.ego);
  return no_action_rollout(s, *model);
}

}  // namespace

bool hazard_in_the_way(const SceneConfig& scene, const CellInput& cell) {
  const Scene s(scene, cell);
  return in_the_way_from(s, s.ttc_s());
}

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
  if (!stop_boundary_applies(scene)) return StopCall::kUnknown;
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
