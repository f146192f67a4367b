#include "emrm/sim/rollout.hpp"

#include "emrm/core/trig.hpp"
#include "termination_tests.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace emrm::sim {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The rear axle "slides" (dodge's constraint) when it is saturated at a real slip angle; a
// straight ABS stop saturates the axle longitudinally at zero slip angle and is within grip.
constexpr double kSlidingSlipAngle_rad = 0.035;

core::Vec2 world_velocity(const VehicleState& s) {
  const auto [c, sn] = core::cos_sin(s.yaw_rad);
  return {s.vx_mps * c - s.vy_mps * sn, s.vx_mps * sn + s.vy_mps * c};
}

// The built-in checks answer through `why` and return whether the step ends the rollout: plain
// flags rather than std::optional<Termination>, whose piecewise stores and whole reads stalled the
// per-step loop on store forwarding (measured: ~6 % of a cheap cell).
using termination::end;

// check() of a list of checks, from its ends().
template <class Checks>
std::optional<Termination> answer_of(const Checks& checks, Step& step, RolloutResult& result) {
  Termination why{};
  return checks.ends(step, result, why) ? std::optional<Termination>(why) : std::nullopt;
}

// ---- validity ---------------------------------------------------------------------------------

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
  MotionBound(const Scene& scene, const VehicleParams& p)
      : reach_m_(std::hypot(std::max(p.cg_to_front_m(), p.cg_to_rear_m()), 0.5 * p.width_m)),
        accel_mps2_(2.0 * scene.cell().mu * kGravity_mps2),
        yaw_accel_radps2_(2.0 * std::max(p.cg_to_front_axle_m, p.cg_to_rear_axle_m) * scene.cell().mu *
                              p.mass_kg * kGravity_mps2 / p.yaw_inertia_kgm2 +
                          10.0),
        truck_speed_mps_(scene.cell().truck_speed_kph / 3.6) {}

  [[nodiscard]] double rate_mps(const Step& step, bool with_truck) const noexcept {
    const double speed = std::max(step.before.speed_mps(), step.state.speed_mps()) + accel_mps2_ * step.dt_s;
    const double yaw_rate = std::max(std::abs(step.before.yaw_rate_radps), std::abs(step.state.yaw_rate_radps)) +
                            yaw_accel_radps2_ * step.dt_s;
    return speed + yaw_rate * reach_m_ + (with_truck ? truck_speed_mps_ : 0.0);
  }
  [[nodiscard]] double reach_m() const noexcept { return reach_m_; }

 private:
  double reach_m_;
  double accel_mps2_;
  double yaw_accel_radps2_;
  double truck_speed_mps_;
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

template <class Gap>
std::optional<double> first_touch(double dt_s, double rate_mps, Gap&& gap) {
  double previous = 0.0;
  double tau = 0.0;
  for (;;) {
    const double g = gap(tau);
    if (g <= 0.0) {
      double lo = previous;
      double hi = tau;
      while (hi - lo > 1e-7) {
        const double mid = 0.5 * (lo + hi);
        if (gap(mid) <= 0.0) hi = mid;
        else lo = mid;
      }
      return hi;
    }
    if (tau >= dt_s) return std::nullopt;
    previous = tau;
    tau = std::min(dt_s, tau + (g + kTolerance_m) / rate_mps);
  }
}

// Contact with the truck, between samples too: the moment it began is found inside the step,
// so the impact speed is not a step late, and the impact is assessed there.
class TruckContactCheck {
 public:
  TruckContactCheck(const Scene& scene, const VehicleModel& model)
      : scene_(scene),
        model_(model),
        motion_(scene, model.params()),
        circumradii_m_(0.5 * std::hypot(scene.config().ego.length_m, scene.config().ego.width_m) +
                       0.5 * std::hypot(scene.config().truck.length_m, scene.config().truck.width_m)) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const double rate = motion_.rate_mps(step, true);
    const double move = rate * step.dt_s;
    // Far apart (the common case): farther than the step can close, by the boxes' centres alone.
    const core::Vec2 d = step.ego.center - step.truck.box.center;
    const double reach = circumradii_m_ + move;
    if (d.dot(d) > reach * reach) return false;
    if (core::separation_lower_bound(step.ego, step.truck.box) > move) return false;
    const double mu = scene_.cell().mu;
    const double start = step.t_s - step.dt_s;
    const PoseInStep pose(step);
    const auto touch = first_touch(step.dt_s, rate, [&](double tau) {
      return core::separation_lower_bound(scene_.ego_box(pose.at(tau)), scene_.truck_at(start + tau).box);
    });
    if (!touch) return false;
    step.state = model_.step(step.before, step.applied, mu, *touch);
    step.t_s = start + *touch;
    step.ego = scene_.ego_box(step.state);
    result.impact = truck_impact(scene_, step.state, scene_.truck_at(step.t_s));
    return end(why, Termination::kContact);
  }

 private:
  const Scene& scene_;
  const VehicleModel& model_;
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
        min_y_m_(scene.config().road.drivable_min_y_m()),
        max_y_m_(scene.config().road.drivable_max_y_m()) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const double rate = motion_.rate_mps(step, false);
    const double move = rate * step.dt_s;
    // Cheap first: the CG's distance to the edges less the car's reach.
    if (std::min(step.state.y_m - min_y_m_, max_y_m_ - step.state.y_m) - motion_.reach_m() > move) return false;
    if (scene_.edge_gap_m(step.ego) > move) return false;
    const double mu = scene_.cell().mu;
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

}  // namespace

ImpactAssessment truck_impact(const Scene& scene, const VehicleState& s, const TruckState& truck,
                              core::Contact* contact_out) noexcept {
  const auto& cfg = scene.config();
  const core::OrientedBox ego_box = scene.ego_box(s);
  // The boxes touch at the first touch; the contact test wants an overlap, which the state
  // integrated to that moment has to within micrometres of the probes' path: if it falls short,
  // nudge the ego on along its motion relative to the truck until they meet.
  core::Contact c = core::contact(ego_box, truck.box);
  const core::Vec2 closing = world_velocity(s) - truck.velocity_mps;
  const double closing_speed = closing.norm();
  for (double nudge_m = 1e-6; !c.touching && closing_speed > 0.0 && nudge_m <= 1e-2; nudge_m *= 10.0) {
    core::OrientedBox nudged = ego_box;
    nudged.center = nudged.center + closing * (nudge_m / closing_speed);
    c = core::contact(nudged, truck.box);
  }
  if (contact_out != nullptr) *contact_out = c;
  const ImpactBody ego{cfg.ego.mass_kg, cfg.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, world_velocity(s),
                       s.yaw_rate_radps};
  const ImpactBody other{cfg.truck.mass_kg, cfg.truck.yaw_inertia_kgm2, truck.box.center, truck.velocity_mps, 0.0};
  return assess_impact(ego, other, c, cfg.severity);
}

ImpactAssessment roadside_impact(const Scene& scene, const VehicleState& s, core::Vec2* point_out) noexcept {
  const auto& cfg = scene.config();
  const core::OrientedBox ego_box = scene.ego_box(s);
  const double min_y = cfg.road.drivable_min_y_m();
  const double max_y = cfg.road.drivable_max_y_m();
  // The corner nearest to (or across) the edge it meets; the barrier's normal points out of the road.
  const bool right = ego_box.center.y - min_y < max_y - ego_box.center.y;
  core::Vec2 corner = ego_box.corners()[0];
  for (const auto& c : ego_box.corners())
    if (right ? c.y < corner.y : c.y > corner.y) corner = c;
  if (point_out != nullptr) *point_out = corner;
  if (!cfg.roadside.barrier()) {
    ImpactAssessment open;
    open.impact_speed_mps = s.speed_mps();
    open.loss_level = loss_level(false, true, 0.0, 0.0, cfg.severity);
    return open;
  }
  core::Contact contact;
  contact.touching = true;
  contact.normal = right ? core::Vec2{0.0, -1.0} : core::Vec2{0.0, 1.0};
  contact.point = corner;
  const ImpactBody ego{cfg.ego.mass_kg, cfg.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, world_velocity(s),
                       s.yaw_rate_radps};
  const ImpactBody barrier{0.0, 0.0, corner, {0.0, 0.0}, 0.0};  // immovable
  return assess_impact(ego, barrier, contact, cfg.severity);
}

bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s) noexcept {
  return stable_with_room_to_stop(scene, s, scene.ego_box(s));
}

bool stable_with_room_to_stop(const Scene& scene, const VehicleState& s, const core::OrientedBox& ego_box) noexcept {
  const SafeStateConfig& bounds = scene.config().safe_state;
  if (!(std::abs(s.yaw_rate_radps) <= bounds.max_yaw_rate_radps &&
        std::abs(s.slip_angle_rad()) <= bounds.max_slip_angle_rad &&
        std::abs(core::wrap_angle(s.yaw_rad)) <= bounds.max_heading_error_rad &&
        std::abs(s.steer_rad) <= bounds.max_steer_rad))
    return false;
  // A stop from here, through the brakes' dead time and ramp.
  const double stop_distance = scene.config().actuation.stopping_distance_m(s.speed_mps(), scene.cell().mu, false);
  core::OrientedBox at_rest = ego_box;
  at_rest.center = at_rest.center + core::Vec2::unit(s.yaw_rad) * stop_distance;
  return scene.on_drivable_area(at_rest);
}

Extent extent_of(const core::OrientedBox& box) noexcept {
  Extent e{kInfinity, -kInfinity, kInfinity, -kInfinity};
  for (const auto& c : box.corners()) {
    e.min_x = std::min(e.min_x, c.x);
    e.max_x = std::max(e.max_x, c.x);
    e.min_y = std::min(e.min_y, c.y);
    e.max_y = std::max(e.max_y, c.y);
  }
  return e;
}

double pursuit_steer_rate(const VehicleState& s, const core::Vec2& target, const VehicleParams& p, double mu,
                          double grip, double dt_s) noexcept {
  const double dx = target.x - s.x_m;
  const double dy = target.y - s.y_m;
  const double alpha = core::wrap_angle(std::atan2(dy, dx) - s.yaw_rad);
  const double lookahead = std::max(std::hypot(dx, dy), 1.0);
  const double v2 = std::max(s.vx_mps * s.vx_mps, 1.0);
  const double grip_limit = std::min(p.max_steer_rad, std::atan(p.wheelbase_m() * grip * mu * kGravity_mps2 / v2));
  const double wanted =
      std::clamp(std::atan(2.0 * p.wheelbase_m() * std::sin(alpha) / lookahead), -grip_limit, grip_limit);
  return std::clamp((wanted - s.steer_rad) / (2.0 * dt_s), -p.max_steer_rate_radps, p.max_steer_rate_radps);
}

double friction_circle_share(const VehicleState& s, double mu) noexcept {
  const double lateral = std::abs(s.vx_mps * s.yaw_rate_radps) / (mu * kGravity_mps2);
  return std::sqrt(std::max(0.0, 1.0 - lateral * lateral));
}

ControlSchedule::ControlSchedule(const std::vector<ControlSegment>& plan, const std::optional<Tail>& tail,
                                 const VehicleParams& params, const ControlLimits& limits, double mu, double dt_s)
    : plan_(plan),
      tail_(tail),
      params_(params),
      limits_(limits),
      mu_(mu),
      dt_s_(dt_s),
      segment_left_s_(plan.empty() ? 0.0 : plan.front().duration_s) {}

std::optional<Control> ControlSchedule::control_at(const VehicleState& s) {
  while (segment_ < plan_.size() && segment_left_s_ <= 1e-9) {
    ++segment_;
    if (segment_ < plan_.size()) segment_left_s_ = plan_[segment_].duration_s;
  }
  Control u;
  if (recovery_y_m_) {
    // Recovery: back to a straight line ahead, steering only. Braking here would take load off a
    // rear axle that still carries the turn and make it slide; the safe state asks for stability
    // and room to stop, not for a stop.
    const core::Vec2 ahead{s.x_m + std::max(10.0, 1.5 * s.speed_mps()), *recovery_y_m_};
    u.steer_rate_radps = pursuit_steer_rate(s, ahead, params_, mu_, 0.9, dt_s_);
    return u;
  }
  if (segment_ < plan_.size()) {
    const ControlSegment& segment = plan_[segment_];
    u = segment.control;
    if (segment.pursue) {
      u.steer_rate_radps = pursuit_steer_rate(s, *segment.pursue, params_, mu_, segment.pursuit_grip, dt_s_);
      if (segment.friction_circle_brake) u.brake *= friction_circle_share(s, mu_);
    }
  } else if (tail_) {
    const double max_rate = params_.max_steer_rate_radps;
    u = tail_->control;
    // Back to straight at the largest rate that does not overshoot within a few steps.
    if (tail_->straighten) u.steer_rate_radps = std::clamp(-s.steer_rad / (5.0 * dt_s_), -max_rate, max_rate);
    if (tail_->pursue) u.steer_rate_radps = pursuit_steer_rate(s, *tail_->pursue, params_, mu_, 0.9, dt_s_);
    if (tail_->friction_circle_brake) u.brake *= friction_circle_share(s, mu_);
  } else {
    return std::nullopt;
  }
  if (!limits_.allow_rear_lock) u.rear_lock = false;
  return u;
}

CheckList& CheckList::add(std::unique_ptr<StepCheck> check) {
  checks_.push_back(std::move(check));
  return *this;
}

bool CheckList::ends(Step& step, RolloutResult& result, Termination& why) const {
  for (const auto& c : checks_)
    if (const auto answer = c->check(step, result)) return end(why, *answer);
  return false;
}

std::optional<Termination> CheckList::check(Step& step, RolloutResult& result) const {
  return answer_of(*this, step, result);
}

struct ValidityChecker::BuiltIn {
  std::optional<RearSlidingCheck> rear_sliding;
  TruckContactCheck contact;
  RoadDepartureCheck departure;
};

ValidityChecker::ValidityChecker(const Scene& scene, const VehicleModel& model, const ControlLimits& limits)
    : built_in_(std::make_unique<const BuiltIn>(
          BuiltIn{limits.forbid_rear_sliding ? std::optional<RearSlidingCheck>(std::in_place, model, scene.cell().mu)
                                             : std::nullopt,
                  TruckContactCheck(scene, model), RoadDepartureCheck(scene, model)})) {}
ValidityChecker::~ValidityChecker() = default;
ValidityChecker::ValidityChecker(ValidityChecker&&) noexcept = default;
ValidityChecker& ValidityChecker::operator=(ValidityChecker&&) noexcept = default;

ValidityChecker& ValidityChecker::add(std::unique_ptr<StepCheck> check) {
  added_.add(std::move(check));
  return *this;
}

bool ValidityChecker::ends(Step& step, RolloutResult& result, Termination& why) const {
  const BuiltIn& b = *built_in_;
  if ((b.rear_sliding && b.rear_sliding->ends(step, result, why)) || b.contact.ends(step, result, why) ||
      b.departure.ends(step, result, why))
    return true;
  return !added_.empty() && added_.ends(step, result, why);
}

std::optional<Termination> ValidityChecker::check(Step& step, RolloutResult& result) const {
  return answer_of(*this, step, result);
}

struct TerminationTest::BuiltIn {
  termination::PassedTruckTest passed;
  termination::StoppedTest stopped;
  termination::StopsShortTest stops_short;
  termination::HorizonTest horizon;
  termination::StabilisedTest stabilised;
};

TerminationTest::TerminationTest(const Scene& scene)
    : built_in_(std::make_unique<const BuiltIn>(BuiltIn{termination::PassedTruckTest(scene), termination::StoppedTest(),
                                                        termination::StopsShortTest(scene),
                                                        termination::HorizonTest(scene),
                                                        termination::StabilisedTest(scene)})) {}
TerminationTest::~TerminationTest() = default;
TerminationTest::TerminationTest(TerminationTest&&) noexcept = default;
TerminationTest& TerminationTest::operator=(TerminationTest&&) noexcept = default;

TerminationTest& TerminationTest::add(std::unique_ptr<StepCheck> check) {
  added_.add(std::move(check));
  return *this;
}

bool TerminationTest::ends(Step& step, RolloutResult& result, Termination& why) const {
  const BuiltIn& b = *built_in_;
  if (step.recovering) {
    if (b.stopped.ends(step, result, why) || b.stabilised.ends(step, result, why) || b.horizon.ends(step, result, why))
      return true;
  } else if (b.passed.ends(step, result, why) || b.stopped.ends(step, result, why) ||
             b.stops_short.ends(step, result, why) || b.horizon.ends(step, result, why)) {
    return true;
  }
  return !added_.empty() && added_.ends(step, result, why);
}

std::optional<Termination> TerminationTest::check(Step& step, RolloutResult& result) const {
  return answer_of(*this, step, result);
}

Roller::Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits)
    : Roller(scene, model, limits, ValidityChecker(scene, model, limits), TerminationTest(scene)) {}

Roller::Roller(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, ValidityChecker validity,
               TerminationTest termination)
    : scene_(scene),
      model_(model),
      limits_(limits),
      validity_(std::move(validity)),
      termination_(std::move(termination)),
      actuators_(scene.config().actuation, model.params(), scene.cell().mu, scene.config().simulation.dt_s),
      instant_actuation_(scene.config().actuation.instant()) {}

[[gnu::flatten]] RolloutResult Roller::roll(const VehicleState& start, double t0_s, const std::vector<ControlSegment>& plan,
                           const std::optional<Tail>& tail, int record_every,
                           const ActuatorState* actuators) const {
  const double dt = scene_.config().simulation.dt_s;
  const double mu = scene_.cell().mu;
  ControlSchedule schedule(plan, tail, model_.params(), limits_, mu, dt);

  RolloutResult r;
  r.maneuver.plan = plan;
  r.maneuver.tail = tail;
  Step step;
  step.state = start;
  step.t_s = t0_s;
  step.dt_s = dt;
  ActuatorState act = actuators != nullptr ? *actuators : Actuators::at_rest(start);
  auto finish = [&](Termination why) {
    r.termination = why;
    r.end_actuators = std::move(act);
    r.passed_truck = step.recovering || why == Termination::kPassed;
    r.end_time_s = step.t_s;
    r.end_state = step.state;
    if (r.path.back().t_s != step.t_s) r.path.push_back({step.t_s, step.state, step.control});
    return std::move(r);
  };

  for (int n = 0;; ++n) {
    // Controllers steer the commanded angle: they see it, not the lagging wheels.
    std::optional<Control> u;
    if (instant_actuation_) {
      u = schedule.control_at(step.state);
    } else {
      VehicleState seen = step.state;
      seen.steer_rad = act.steer_command_rad;
      u = schedule.control_at(seen);
    }
    if (!u) {
      step.control = Control{};
      if (r.path.empty()) r.path.push_back({step.t_s, step.state, step.control});
      return finish(Termination::kOpen);
    }
    step.control = *u;
    if (n == 0) r.path.push_back({step.t_s, step.state, step.control});  // the start, with its control

    step.before = step.state;
    if (instant_actuation_) {
      step.applied = step.control;
      step.full_brake_held = step.control.brake >= 0.999;
    } else {
      step.applied = actuators_.apply(act, step.state, step.control, step.t_s);
      step.full_brake_held = actuators_.full_brake_held(act, step.control);
    }
    step.state = model_.step(step.state, step.applied, mu, dt);
    if (instant_actuation_) act.steer_command_rad = step.state.steer_rad;  // the wheels are the command
    step.steer_command_rad = act.steer_command_rad;
    step.t_s += dt;
    schedule.advance();
    step.ego = scene_.ego_box(step.state);
    step.truck = scene_.truck_at(step.t_s);

    Termination why{};
    if (validity_.ends(step, r, why)) return finish(why);
    step.ego_extent = extent_of(step.ego);
    step.truck_extent = extent_of(step.truck.box);
    if ((n + 1) % record_every == 0) r.path.push_back({step.t_s, step.state, step.control});
    if (termination_.ends(step, r, why)) {
      if (why != Termination::kPassed || !recovery_) return finish(why);
      // Passed: not yet an avoidance. The recovery controller takes over until a safe state.
      const auto& road = scene_.config().road;
      const double margin = 0.5 * scene_.config().ego.width_m + 0.3;
      const double low = road.drivable_min_y_m() + margin;
      const double high = std::max(low, road.drivable_max_y_m() - margin);
      step.recovering = true;
      step.recovery_until_s = step.t_s + scene_.config().safe_state.horizon_s;
      schedule.recover(std::clamp(step.state.y_m, low, high));
    }
  }
}

RolloutResult replay(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                     const Maneuver& maneuver) {
  return Roller(scene, model, limits).roll(scene.ego_initial(), 0.0, maneuver.plan, maneuver.tail, 1);
}

RolloutResult no_action_rollout(const Scene& scene, const VehicleModel& model) {
  Roller coast(scene, model, ControlLimits{});
  coast.set_recovery(false);
  return coast.roll(scene.ego_initial(), 0.0, {}, Tail{}, 10);
}

double min_ttc_along(const Scene& scene, const std::vector<PathPoint>& path) {
  double best = kInfinity;
  const double horizon = scene.config().simulation.horizon_s;
  for (const auto& p : path) {
    const TruckState truck = scene.truck_at(p.t_s);
    if (const auto ttc = core::time_to_overlap(scene.ego_box(p.state), world_velocity(p.state), truck.box,
                                               truck.velocity_mps, horizon))
      best = std::min(best, *ttc);
  }
  return best;
}

}  // namespace emrm::sim
