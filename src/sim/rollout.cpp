#include "emrm/sim/rollout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace emrm::sim {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kStoppedSpeed_mps = 0.05;
// The rear axle "slides" (dodge's constraint) when it is saturated at a real slip angle; a
// straight ABS stop saturates the axle longitudinally at zero slip angle and is within grip.
constexpr double kSlidingSlipAngle_rad = 0.035;

core::Vec2 world_velocity(const VehicleState& s) {
  const double c = std::cos(s.yaw_rad);
  const double sn = std::sin(s.yaw_rad);
  return {s.vx_mps * c - s.vy_mps * sn, s.vx_mps * sn + s.vy_mps * c};
}

// The built-in checks answer through `why` and return whether the step ends the rollout: plain
// flags rather than std::optional<Termination>, whose piecewise stores and whole reads stalled the
// per-step loop on store forwarding (measured: ~6 % of a cheap cell).
bool end(Termination& why, Termination reason) noexcept {
  why = reason;
  return true;
}

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
    const AxleForces rear = model_.tire_forces(step.state, step.control, mu_).rear;
    if (step.control.rear_lock || (rear.saturated && std::abs(rear.slip_angle_rad) > kSlidingSlipAngle_rad))
      return end(why, Termination::kConstraint);
    return false;
  }

 private:
  const VehicleModel& model_;
  double mu_;
};

// Contact with the truck; the moment it began is found by bisection inside the step, so the
// impact speed is not a step late, and the impact is assessed there.
class TruckContactCheck {
 public:
  TruckContactCheck(const Scene& scene, const VehicleModel& model) : scene_(scene), model_(model) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    if (!core::overlaps(step.ego, step.truck.box)) return false;
    const double mu = scene_.cell().mu;
    const double start = step.t_s - step.dt_s;
    double lo = 0.0;
    double hi = step.dt_s;
    for (int i = 0; i < 8; ++i) {
      const double mid = 0.5 * (lo + hi);
      const VehicleState probe = model_.step(step.before, step.control, mu, mid);
      if (core::overlaps(scene_.ego_box(probe), scene_.truck_at(start + mid).box)) hi = mid;
      else lo = mid;
    }
    step.state = model_.step(step.before, step.control, mu, hi);
    step.t_s = start + hi;
    result.impact = impact_with(step.state, scene_.ego_box(step.state), scene_.truck_at(step.t_s));
    return end(why, Termination::kContact);
  }

 private:
  ImpactAssessment impact_with(const VehicleState& s, const core::OrientedBox& ego_box,
                               const TruckState& truck) const {
    const auto& cfg = scene_.config();
    const core::Contact c = core::contact(ego_box, truck.box);
    const ImpactBody ego{cfg.ego.mass_kg, cfg.ego.yaw_inertia_kgm2, {s.x_m, s.y_m}, world_velocity(s),
                         s.yaw_rate_radps};
    const ImpactBody other{cfg.truck.mass_kg, cfg.truck.yaw_inertia_kgm2, truck.box.center, truck.velocity_mps,
                           0.0};
    return assess_impact(ego, other, c, cfg.severity);
  }

  const Scene& scene_;
  const VehicleModel& model_;
};

class RoadDepartureCheck {
 public:
  explicit RoadDepartureCheck(const Scene& scene) : scene_(scene) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (scene_.on_drivable_area(step.ego)) return false;
    return end(why, Termination::kRoadDeparture);
  }

 private:
  const Scene& scene_;
};

// ---- termination ------------------------------------------------------------------------------

class PassedTruckTest {
 public:
  explicit PassedTruckTest(const Scene& scene) : truck_far_x_m_(scene.truck_far_x_m()) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.ego_extent.min_x > truck_far_x_m_) return end(why, Termination::kPassed);
    return false;
  }

 private:
  double truck_far_x_m_;
};

class StoppedTest {
 public:
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.state.speed_mps() < kStoppedSpeed_mps) return end(why, Termination::kStopped);
    return false;
  }
};

// Braking straight at the friction limit, the rest is closed form: the car stops short of the
// truck, and the rollout jumps to where and when it comes to rest.
class StopsShortTest {
 public:
  explicit StopsShortTest(const Scene& scene) : truck_near_x_m_(scene.initial_distance_m()), mu_(scene.cell().mu) {}
  bool ends(Step& step, RolloutResult& result, Termination& why) const {
    const Control& u = step.control;
    VehicleState& s = step.state;
    if (!(u.brake >= 0.999 && !u.rear_lock && std::abs(s.yaw_rad) < 0.02 && std::abs(s.steer_rad) < 0.005 &&
          std::abs(s.yaw_rate_radps) < 0.01 && std::abs(s.vy_mps) < 0.05))
      return false;
    const double speed = s.speed_mps();
    const double stop_distance = speed * speed / (2.0 * mu_ * kGravity_mps2);
    if (!(step.ego_extent.max_x + stop_distance + 0.05 < truck_near_x_m_ &&
          step.truck_extent.max_y > step.ego_extent.min_y))
      return false;
    result.path.push_back({step.t_s, s, u});
    s.x_m += stop_distance * std::cos(s.yaw_rad);
    s.y_m += stop_distance * std::sin(s.yaw_rad);
    step.t_s += speed / (mu_ * kGravity_mps2);
    s.vx_mps = s.vy_mps = s.yaw_rate_radps = 0.0;
    return end(why, Termination::kStopped);
  }

 private:
  double truck_near_x_m_;
  double mu_;
};

class HorizonTest {
 public:
  explicit HorizonTest(const Scene& scene) : horizon_s_(scene.config().simulation.horizon_s) {}
  bool ends(Step& step, RolloutResult& /*result*/, Termination& why) const {
    if (step.t_s >= horizon_s_ - 1e-9) return end(why, Termination::kHorizon);
    return false;
  }

 private:
  double horizon_s_;
};

}  // namespace

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
  const double alpha = std::remainder(std::atan2(dy, dx) - s.yaw_rad, 2.0 * std::numbers::pi);
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
                  TruckContactCheck(scene, model), RoadDepartureCheck(scene)})) {}
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
  PassedTruckTest passed;
  StoppedTest stopped;
  StopsShortTest stops_short;
  HorizonTest horizon;
};

TerminationTest::TerminationTest(const Scene& scene)
    : built_in_(std::make_unique<const BuiltIn>(
          BuiltIn{PassedTruckTest(scene), StoppedTest(), StopsShortTest(scene), HorizonTest(scene)})) {}
TerminationTest::~TerminationTest() = default;
TerminationTest::TerminationTest(TerminationTest&&) noexcept = default;
TerminationTest& TerminationTest::operator=(TerminationTest&&) noexcept = default;

TerminationTest& TerminationTest::add(std::unique_ptr<StepCheck> check) {
  added_.add(std::move(check));
  return *this;
}

bool TerminationTest::ends(Step& step, RolloutResult& result, Termination& why) const {
  const BuiltIn& b = *built_in_;
  if (b.passed.ends(step, result, why) || b.stopped.ends(step, result, why) || b.stops_short.ends(step, result, why) ||
      b.horizon.ends(step, result, why))
    return true;
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
      termination_(std::move(termination)) {}

[[gnu::flatten]] RolloutResult Roller::roll(const VehicleState& start, double t0_s, const std::vector<ControlSegment>& plan,
                           const std::optional<Tail>& tail, int record_every) const {
  const double dt = scene_.config().simulation.dt_s;
  const double mu = scene_.cell().mu;
  ControlSchedule schedule(plan, tail, model_.params(), limits_, mu, dt);

  RolloutResult r;
  Step step;
  step.state = start;
  step.t_s = t0_s;
  step.dt_s = dt;
  auto finish = [&](Termination why) {
    r.termination = why;
    r.end_time_s = step.t_s;
    r.end_state = step.state;
    if (r.path.back().t_s != step.t_s) r.path.push_back({step.t_s, step.state, step.control});
    return std::move(r);
  };

  for (int n = 0;; ++n) {
    const std::optional<Control> u = schedule.control_at(step.state);
    if (!u) {
      step.control = Control{};
      if (r.path.empty()) r.path.push_back({step.t_s, step.state, step.control});
      return finish(Termination::kOpen);
    }
    step.control = *u;
    if (n == 0) r.path.push_back({step.t_s, step.state, step.control});  // the start, with its control

    step.before = step.state;
    step.state = model_.step(step.state, step.control, mu, dt);
    step.t_s += dt;
    schedule.advance();
    step.ego = scene_.ego_box(step.state);
    step.truck = scene_.truck_at(step.t_s);

    Termination why{};
    if (validity_.ends(step, r, why)) return finish(why);
    step.ego_extent = extent_of(step.ego);
    step.truck_extent = extent_of(step.truck.box);
    if ((n + 1) % record_every == 0) r.path.push_back({step.t_s, step.state, step.control});
    if (termination_.ends(step, r, why)) return finish(why);
  }
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
