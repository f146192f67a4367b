// A rollout's validity checks (validity.hpp): the built-in ones — the strategy's constraint, contact
// with the truck, leaving the drivable area — and the impact assessments of a contact and of a
// departure.

#include "emrm/sim/validity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "check_chain.hpp"
#include "check_support.hpp"

namespace emrm::sim {
namespace detail {

// The rear axle "slides" (dodge's constraint) when it is saturated at a real slip angle; a
// straight ABS stop saturates the axle longitudinally at zero slip angle and is within grip.
constexpr double kSlidingSlipAngle_rad = 0.035;

// Dodge's constraint: neither a locked rear axle nor a rear axle sliding at a real slip angle.
class RearSlidingCheck {
 public:
  RearSlidingCheck(const VehicleModel& model, double mu) : model_(model), mu_(mu) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.applied.rear_lock || model_.rear_axle_sliding(step.state, step.applied, mu_, kSlidingSlipAngle_rad))
      return end(why, Termination::kConstraint);
    return false;
  }

 private:
  const VehicleModel& model_;
  double mu_;
};

// Relative motion inside one step, for conservative advancement: no point of the ego moves
// faster than `rate_mps` relative to the truck (or to the road's edges) during the step.
// Speeds and yaw rates are taken at both ends plus what the largest accelerations the model can
// produce add within the step (tire forces within mu·m·g, doubled for the low-speed blend).
class MotionBound {
 public:
  MotionBound(const Scene& scene, const VehicleParams& p, double actor_speed_mps = 0.0)
      : reach_m_(std::hypot(std::max(p.cg_to_front_m(), p.cg_to_rear_m()), 0.5 * p.width_m)),
        accel_mps2_(2.0 * scene.friction() * kGravity_mps2),
        yaw_accel_radps2_(2.0 * std::max(p.cg_to_front_axle_m, p.cg_to_rear_axle_m) * scene.friction() * p.mass_kg *
                              kGravity_mps2 / p.yaw_inertia_kgm2 +
                          10.0),
        actor_speed_mps_(actor_speed_mps) {}

  /// How fast the gap to an actor (with `with_actor`) or to the road's edge can close in the step.
  [[nodiscard]] double rate_mps(const Step& step, bool with_actor) const noexcept {
    const double speed = std::max(step.before.speed_mps(), step.state.speed_mps()) + accel_mps2_ * step.dt_s;
    const double yaw_rate = std::max(std::abs(step.before.yaw_rate_radps), std::abs(step.state.yaw_rate_radps)) +
                            yaw_accel_radps2_ * step.dt_s;
    return speed + yaw_rate * reach_m_ + (with_actor ? actor_speed_mps_ : 0.0);
  }
  [[nodiscard]] double reach_m() const noexcept { return reach_m_; }

 private:
  double reach_m_;
  double accel_mps2_;
  double yaw_accel_radps2_;
  double actor_speed_mps_;
};

// Conservative advancement inside a step: walks τ from the step's start, each time by no more
// than the distance `gap(τ)` (a lower bound on the true distance) plus kTolerance_m can shrink at
// `rate_mps`, until the gap closes (τ of the first touch, timed by bisection to well under a
// millimetre of travel) or the step ends (nothing). A touch that lasts less than kTolerance_m of
// relative travel may be missed: that is the promised tolerance (docs/physics.md).
constexpr double kTolerance_m = 0.5e-3;

// The pose inside a step by cubic Hermite interpolation of position (with the world velocities)
// and yaw (with the yaw rates) at both ends: what the probes of conservative advancement use
// instead of re-integrating the model. For the model's smooth motion over a 10 ms step it is
// within micrometres of the integrated path (its error is O(dt^4)); the state at the moment
// found is then integrated properly.
class PoseInStep {
 public:
  explicit PoseInStep(const Step& step)
      : p0_{step.before.x_m, step.before.y_m},
        p1_{step.state.x_m, step.state.y_m},
        v0_(world_velocity(step.before) * step.dt_s),
        v1_(world_velocity(step.state) * step.dt_s),
        yaw0_(step.before.yaw_rad),
        yaw1_(step.state.yaw_rad),
        r0_(step.before.yaw_rate_radps * step.dt_s),
        r1_(step.state.yaw_rate_radps * step.dt_s),
        dt_s_(step.dt_s) {}

  [[nodiscard]] VehicleState at(double tau_s) const noexcept {
    const double u = tau_s / dt_s_;
    const double u2 = u * u;
    const double u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
    VehicleState s;
    s.x_m = h00 * p0_.x + h10 * v0_.x + h01 * p1_.x + h11 * v1_.x;
    s.y_m = h00 * p0_.y + h10 * v0_.y + h01 * p1_.y + h11 * v1_.y;
    s.yaw_rad = h00 * yaw0_ + h10 * r0_ + h01 * yaw1_ + h11 * r1_;
    return s;
  }

 private:
  core::Vec2 p0_, p1_, v0_, v1_;
  double yaw0_, yaw1_, r0_, r1_, dt_s_;
};

// The first moment in [lo, hi] the gap closes, to 0.1 µs, given it is open at lo and closed at hi.
template <class Gap>
double bisect_touch(double lo, double hi, Gap&& gap) {
  while (hi - lo > 1e-7) {
    const double mid = 0.5 * (lo + hi);
    (gap(mid) <= 0.0 ? hi : lo) = mid;
  }
  return hi;
}

template <class Gap>
std::optional<double> first_touch(double dt_s, double rate_mps, Gap&& gap) {
  double previous = 0.0;
  double tau = 0.0;
  for (;;) {
    const double g = gap(tau);
    if (g <= 0.0) return bisect_touch(previous, tau, gap);
    if (tau >= dt_s) return std::nullopt;
    previous = tau;
    tau = std::min(dt_s, tau + (g + kTolerance_m) / rate_mps);
  }
}

// Contact with an actor, between samples too: the moment it began is found inside the step, so the
// impact speed is not a step late, and the impact is assessed there. The hazard (actor 0) is where
// the step put it (Step::truck); any other actor is placed here.
class ActorContactCheck {
 public:
  ActorContactCheck(const Scene& scene, const VehicleModel& model, std::size_t actor)
      : scene_(scene),
        model_(model),
        actor_(&scene.actors()[actor]),
        hazard_(actor == 0),
        motion_(scene, model.params(), actor_->top_speed_mps()),
        circumradii_m_(0.5 * std::hypot(scene.config().ego.length_m, scene.config().ego.width_m) +
                       0.5 * std::hypot(actor_->body().length_m, actor_->body().width_m)) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const double rate = motion_.rate_mps(step, true);
    const double move = rate * step.dt_s;
    const core::OrientedBox box = hazard_ ? step.truck.box : actor_->at(step.t_s).box;
    // Far apart (the common case): farther than the step can close, by the boxes' centres alone.
    const core::Vec2 d = step.ego.center - box.center;
    const double reach = circumradii_m_ + move;
    if (d.dot(d) > reach * reach) return false;
    if (core::separation_lower_bound(step.ego, box) > move) return false;
    const double mu = scene_.friction();
    const double start = step.t_s - step.dt_s;
    const PoseInStep pose(step);
    const auto touch = first_touch(step.dt_s, rate, [&](double tau) {
      return core::separation_lower_bound(scene_.ego_box(pose.at(tau)), actor_->at(start + tau).box);
    });
    if (!touch) return false;
    step.state = model_.step(step.before, step.applied, mu, *touch);
    step.t_s = start + *touch;
    step.ego = scene_.ego_box(step.state);
    result.impact = actor_impact(scene_, actor_->body(), step.state, actor_->at(step.t_s));
    return end(why, Termination::kContact);
  }

 private:
  const Scene& scene_;
  const VehicleModel& model_;
  const Actor* actor_;
  bool hazard_;
  MotionBound motion_;
  double circumradii_m_;
};

// Leaving the drivable area, between samples too; the departure is assessed against the roadside:
// a barrier is an immovable body met by the corner that crossed the edge (the truck's impact
// model with an infinite mass), open ground scores L4 with no impact.
class RoadDepartureCheck {
 public:
  RoadDepartureCheck(const Scene& scene, const VehicleModel& model)
      : scene_(scene),
        model_(model),
        motion_(scene, model.params()),
        min_y_m_(scene.road().min_y_m),
        max_y_m_(scene.road().max_y_m) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const double rate = motion_.rate_mps(step, false);
    const double move = rate * step.dt_s;
    // Cheap first: the CG's distance to the edges less the car's reach.
    if (std::min(step.state.y_m - min_y_m_, max_y_m_ - step.state.y_m) - motion_.reach_m() > move) return false;
    if (scene_.edge_gap_m(step.ego) > move) return false;
    const double mu = scene_.friction();
    const PoseInStep pose(step);
    const auto touch =
        first_touch(step.dt_s, rate, [&](double tau) { return scene_.edge_gap_m(scene_.ego_box(pose.at(tau))); });
    if (!touch) return false;
    step.state = model_.step(step.before, step.applied, mu, *touch);
    step.t_s = step.t_s - step.dt_s + *touch;
    step.ego = scene_.ego_box(step.state);
    result.impact = roadside_impact(scene_, step.state);
    return end(why, Termination::kRoadDeparture);
  }

 private:
  const Scene& scene_;
  const VehicleModel& model_;
  MotionBound motion_;
  double min_y_m_;
  double max_y_m_;
};

}  // namespace detail

namespace {

// Whether an actor moving along an axis never meets the box: the band it sweeps across that axis
// (its extent across it, widened along y by the drift still to come) misses the box. An actor moving
// along y keeps its x; one along x keeps its y but for the drift.
bool outside_band(const Actor& actor, double t_s, const core::OrientedBox& box) noexcept {
  const ActorMotion& m = actor.motion();
  if (m.track) return false;  // no axis to sweep along
  const Extent a = extent_of(actor.at(t_s).box);
  const Extent b = extent_of(box);
  if (m.direction.x == 0.0) return a.max_x < b.min_x || a.min_x > b.max_x;
  if (m.direction.y != 0.0) return false;
  const double drift_m = m.lateral_mps * std::max(m.lateral_for_s - t_s, 0.0);
  return a.max_y + std::max(drift_m, 0.0) < b.min_y || a.min_y + std::min(drift_m, 0.0) > b.max_y;
}

// Whether an actor is past the box for good: wholly beyond it along its direction of travel, along
// which it never turns back, and no longer drifting sideways unless across its direction's y (a
// drift along y cannot bring back a body that is past along x).
bool moved_past(const Actor& actor, const core::OrientedBox& at, const core::OrientedBox& box, double t_s) noexcept {
  const ActorMotion& m = actor.motion();
  if (m.track) return false;  // it may turn back
  if (m.lateral_mps != 0.0 && t_s < m.lateral_for_s && m.direction.y != 0.0) return false;
  double actor_low = std::numeric_limits<double>::infinity();
  double box_high = -actor_low;
  for (const core::Vec2& c : at.corners()) actor_low = std::min(actor_low, c.dot(m.direction));
  for (const core::Vec2& c : box.corners()) box_high = std::max(box_high, c.dot(m.direction));
  return actor_low > box_high;
}

}  // namespace

std::optional<TouchAtRest> touch_at_rest(const Scene& scene, const VehicleState& s, double t_s) noexcept {
  constexpr int kMaxAdvances = 1'000'000;  // a guard: an actor gliding past at a hair's breadth takes thousands
  const core::OrientedBox ego = scene.ego_box(s);
  std::optional<TouchAtRest> first;
  for (std::size_t k = 0; k < scene.actors().size(); ++k) {
    const Actor& actor = scene.actors()[k];
    const double rate = actor.top_speed_mps();
    if (!(rate > 0.0) || outside_band(actor, t_s, ego)) continue;
    const double rest_s = std::max(actor.motion().rest_time_s(), t_s);
    const double until_s = first ? first->t_s : std::numeric_limits<double>::infinity();
    const auto gap = [&](double t) { return core::separation_lower_bound(ego, actor.at(t).box); };
    double previous = t_s;
    double t = t_s;
    for (int n = 0; n < kMaxAdvances && t < until_s; ++n) {
      const core::OrientedBox at = actor.at(t).box;
      const double g = core::separation_lower_bound(ego, at);
      if (g <= 0.0) {
        if (const double touch_s = detail::bisect_touch(previous, t, gap); touch_s < until_s)
          first = TouchAtRest{k, touch_s};
        break;
      }
      if (t >= rest_s || moved_past(actor, at, ego, t)) break;
      previous = t;
      t = std::min(rest_s, t + (g + detail::kTolerance_m) / rate);
    }
  }
  return first;
}

ImpactAssessment actor_impact(const Scene& scene, const ActorBody& body, const VehicleState& s, const ActorState& truck,
                              core::Contact* contact_out) noexcept {
  const auto& cfg = scene.config();
  const core::OrientedBox ego_box = scene.ego_box(s);
  // The boxes touch at the first touch; the contact test wants an overlap, which the state
  // integrated to that moment has to within micrometres of the probes' path: if it falls short,
  // nudge the ego on along its motion relative to the truck until they meet.
  core::Contact c = core::contact(ego_box, truck.box);
  const core::Vec2 closing = detail::world_velocity(s) - truck.velocity_mps;
  const double closing_speed = closing.norm();
  for (double nudge_m = 1e-6; !c.touching && closing_speed > 0.0 && nudge_m <= 1e-2; nudge_m *= 10.0) {
    core::OrientedBox nudged = ego_box;
    nudged.center = nudged.center + closing * (nudge_m / closing_speed);
    c = core::contact(nudged, truck.box);
  }
  if (contact_out != nullptr) *contact_out = c;
  const ImpactBody ego{
      cfg.ego.mass_kg, cfg.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, detail::world_velocity(s), s.yaw_rate_radps};
  const ImpactBody other{body.mass_kg, body.yaw_inertia_kgm2, truck.box.center, truck.velocity_mps, 0.0};
  const ImpactAssessment occupants = assess_impact(ego, other, c, cfg.severity);
  // A pedestrian's and a cyclist's harm is read from the impact speed (docs/physics.md, "Pedestrians").
  if (vulnerable_road_user(body.kind) && c.touching)
    return with_road_user(occupants, body.kind, closing_speed, cfg.severity);
  return occupants;
}

ImpactAssessment roadside_impact(const Scene& scene, const VehicleState& s, core::Vec2* point_out) noexcept {
  const auto& cfg = scene.config();
  const core::OrientedBox ego_box = scene.ego_box(s);
  const double min_y = scene.road().min_y_m;
  const double max_y = scene.road().max_y_m;
  // The corner nearest to (or across) the edge it meets; the barrier's normal points out of the road.
  const bool right = ego_box.center.y - min_y < max_y - ego_box.center.y;
  core::Vec2 corner = ego_box.corners()[0];
  for (const auto& c : ego_box.corners())
    if (right ? c.y < corner.y : c.y > corner.y) corner = c;
  if (point_out != nullptr) *point_out = corner;
  const Roadside roadside = scene.road().beyond(right);
  if (roadside != Roadside::kBarrier) {
    ImpactAssessment off_road;
    off_road.impact_speed_mps = s.speed_mps();
    if (roadside == Roadside::kEmbankment && rolls_over(scene.road().slope_h(right), cfg.severity)) {
      off_road.p_fatal = cfg.severity.rollover_p_fatal;
      off_road.p_mais3 = cfg.severity.rollover_p_fatal;  // every death is a MAIS3+ injury: a lower bound
    }
    off_road.loss_level = loss_level(false, true, off_road.p_mais3, off_road.p_fatal, cfg.severity);
    return off_road;
  }
  core::Contact contact;
  contact.touching = true;
  contact.normal = right ? core::Vec2{0.0, -1.0} : core::Vec2{0.0, 1.0};
  contact.point = corner;
  const ImpactBody ego{
      cfg.ego.mass_kg, cfg.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, detail::world_velocity(s), s.yaw_rate_radps};
  const ImpactBody barrier{0.0, 0.0, corner, {0.0, 0.0}, 0.0};  // immovable
  return assess_impact(ego, barrier, contact, cfg.severity);
}

namespace detail {

// The built-in validity checks, in their order (CheckChain calls ends() each step).
struct ValidityChecks {
  std::optional<RearSlidingCheck> rear_sliding;
  ActorContactCheck contact;              // the hazard
  std::vector<ActorContactCheck> others;  // every other actor, in the layout's order
  RoadDepartureCheck departure;

  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    if ((rear_sliding && rear_sliding->ends(step, result, why)) || contact.ends(step, result, why)) return true;
    for (const auto& other : others)
      if (other.ends(step, result, why)) return true;
    return departure.ends(step, result, why);
  }
};

}  // namespace detail

template class CheckChain<ValidityChecker, detail::ValidityChecks>;

namespace {

std::vector<detail::ActorContactCheck> other_actors(const Scene& scene, const VehicleModel& model) {
  std::vector<detail::ActorContactCheck> out;
  for (std::size_t i = 1; i < scene.actors().size(); ++i) out.emplace_back(scene, model, i);
  return out;
}

}  // namespace

ValidityChecker::ValidityChecker(const Scene& scene, const VehicleModel& model, const ControlLimits& limits)
    : CheckChain(std::make_unique<const detail::ValidityChecks>(detail::ValidityChecks{
          limits.forbid_rear_sliding ? std::optional<detail::RearSlidingCheck>(std::in_place, model, scene.friction())
                                     : std::nullopt,
          detail::ActorContactCheck(scene, model, 0), other_actors(scene, model),
          detail::RoadDepartureCheck(scene, model)})) {}

}  // namespace emrm::sim
