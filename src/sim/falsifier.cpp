#include "emrm/sim/falsifier.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <nlopt.hpp>
#include <numeric>
#include <utility>
#include <vector>

#include "emrm/sim/swerve.hpp"

namespace emrm::sim {

double falsifier_score(const Scene& scene, const RolloutResult& rollout) noexcept {
  if (rollout.avoided()) return -1.0;
  const double v0 = std::max(scene.initial_speed_mps(), 0.1);
  const double departure_share = std::clamp(rollout.impact.impact_speed_mps / v0, 0.0, 1.0);
  if (rollout.passed_truck)
    return rollout.termination == Termination::kRoadDeparture ? -0.5 * (1.0 - departure_share) : -0.25;
  switch (rollout.termination) {
    case Termination::kContact: {
      const double v = rollout.end_state.speed_mps();
      const double stop_short_m = v * v / (2.0 * std::max(scene.friction(), 0.05) * 9.81);
      const double miss = std::min(lateral_miss_m(scene, rollout), stop_short_m);
      return std::isfinite(miss) ? miss : 10.0;
    }
    case Termination::kRoadDeparture:
      return 0.5 + 0.5 * departure_share;
    default:
      return 10.0;
  }
}

namespace {

// One number of a maneuver the optimiser may move, within bounds, with its first step.
struct Knob {
  double* value;
  double lower;
  double upper;
  double step;
};

class Search {
 public:
  Search(const Scene& scene, const VehicleModel& model, const ControlLimits& limits)
      : scene_(scene), roller_(scene, model, limits), start_(scene.ego_initial()) {}

  // Rolls `maneuver` out, keeps what it found, and returns its score.
  double evaluate(const Maneuver& maneuver) {
    RolloutResult r = roller_.roll(start_, 0.0, maneuver.plan, maneuver.tail, 5);
    ++result_.stats.rollouts;
    const double score = falsifier_score(scene_, r);
    result_.closest_miss_m = std::min(result_.closest_miss_m, std::max(0.0, score));
    if (r.avoided()) {
      if (!result_.avoidance) result_.avoidance = std::move(r);
    } else if (r.termination != Termination::kConstraint &&
               (!result_.collision || less_loss(r.impact, result_.collision->impact))) {
      result_.collision = std::move(r);
    }
    return score;
  }

  // Subplex over `knobs`, from their current values, until an avoidance or the budget: each
  // evaluation sets the knobs and rolls out the maneuver `build` then makes of them.
  void optimise(const std::vector<Knob>& knobs, const std::function<Maneuver()>& build, int evaluations) {
    if (knobs.empty() || evaluations <= 0 || found()) return;
    const auto n = static_cast<unsigned>(knobs.size());
    std::vector<double> lower, upper, step, x;
    for (const Knob& k : knobs) {
      lower.push_back(k.lower);
      upper.push_back(k.upper);
      step.push_back(k.step);
      x.push_back(std::clamp(*k.value, k.lower, k.upper));
    }
    nlopt::opt opt(nlopt::LN_SBPLX, n);
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_initial_step(step);
    opt.set_maxeval(evaluations);
    opt.set_stopval(-0.99);  // an avoidance scores −1
    opt.set_xtol_abs(1e-4);
    struct Objective {
      Search* search;
      const std::vector<Knob>* knobs;
      const std::function<Maneuver()>* build;
    } objective{this, &knobs, &build};
    opt.set_min_objective(
        [](unsigned, const double* at, double*, void* data) {
          const auto* o = static_cast<const Objective*>(data);
          for (std::size_t i = 0; i < o->knobs->size(); ++i) *(*o->knobs)[i].value = at[i];
          return o->search->evaluate((*o->build)());
        },
        &objective);
    double value = 0.0;
    try {
      (void)opt.optimize(x, value);
    } catch (const std::exception&) {
      // NLopt gives up on round-off or a degenerate simplex: what it found so far is kept.
    }
  }

  [[nodiscard]] bool found() const noexcept { return result_.avoidance.has_value(); }
  PlanResult take() { return std::move(result_); }

 private:
  const Scene& scene_;
  const Roller roller_;
  const VehicleState start_;
  PlanResult result_;
};

// The numbers of a maneuver's segments after the perception latency's wait: each duration and
// brake level, and the steering rate or the pursuit target and grip.
std::vector<Knob> segment_knobs(Maneuver& m, const Scene& scene) {
  const auto& cfg = scene.config();
  const double rate = cfg.ego.max_steer_rate_radps;
  const double latency = cfg.actuation.perception_latency_s;
  std::vector<Knob> knobs;
  double t = 0.0;
  for (auto& s : m.plan) {
    const double begins = t;
    t += s.duration_s;
    if (begins < latency - 1e-9) continue;  // nothing acts before the car perceives the hazard
    knobs.push_back({&s.duration_s, 0.0, s.duration_s + 0.5, 0.05});
    knobs.push_back({&s.control.brake, 0.0, 1.0, 0.15});
    if (s.pursue) {
      knobs.push_back({&s.pursue->x, s.pursue->x - 5.0, s.pursue->x + 5.0, 0.3});
      knobs.push_back({&s.pursue->y, s.pursue->y - 3.0, s.pursue->y + 3.0, 0.2});
      knobs.push_back({&s.pursuit_grip, 0.3, 2.5, 0.2});
    } else {
      knobs.push_back({&s.control.steer_rate_radps, -rate, rate, 0.2 * rate});
    }
  }
  return knobs;
}

// The drift family: after the perception latency's wait, a braking pursuit with the rear locked
// (when the limits allow it) towards a point of a free passage beside the hazard, a second one
// further along it at half the brake, then the full stop: the class of the narrow braking drifts
// an RRT finds at the braking boundary (docs/planner.md, "The falsifier"). Its numbers are those
// segment_knobs moves. Per free passage: 3 target heights (its middle and halfway to either edge
// of the room the car's centre has) × 3 distances ahead (1.5, 5, 10 m) × brakes {0.6, 1} × grips
// {0.9, 2} × first durations {0.2, 0.4} s × second durations {0.15, 0.35} s.
std::vector<Maneuver> drift_starts(const Scene& scene, bool allow_rear_lock) {
  const auto& cfg = scene.config();
  const double latency = cfg.actuation.perception_latency_s;
  const double x_acts = scene.ego_initial().x_m + scene.initial_speed_mps() * latency;  // where the car acts first
  const double half_width = cfg.ego.width_m / 2.0;
  const FreeBands free = scene.free_bands(cfg.simulation.horizon_s);
  const auto drift = [&](double x, double y, double brake, double grip, double first_s, double second_s) {
    Maneuver m;
    if (latency > 0.0) m.plan.push_back(hold(Control{}, latency));
    Control locked;
    locked.brake = brake;
    locked.rear_lock = allow_rear_lock;
    ControlSegment first = hold(locked, first_s);
    first.pursue = core::Vec2{x, y};
    first.pursuit_grip = grip;
    m.plan.push_back(first);
    ControlSegment second = first;
    second.duration_s = second_s;
    second.control.brake = 0.5 * brake;
    second.pursue = core::Vec2{x + 4.0, y};
    second.pursuit_grip = 2.0;
    m.plan.push_back(second);
    m.tail = Tail::full_stop();
    return m;
  };
  std::vector<Maneuver> starts;
  for (std::size_t i = 0; i < free.count; ++i) {
    const double lo = free.band[i].low_m + half_width + 0.1;
    const double hi = free.band[i].high_m - half_width - 0.1;
    if (hi <= lo) continue;
    const double middle = 0.5 * (lo + hi);
    for (const double y : {middle, 0.5 * (middle + hi), 0.5 * (middle + lo)})
      for (const double ahead : {1.5, 5.0, 10.0})
        for (const double brake : {0.6, 1.0})
          for (const double grip : {0.9, 2.0})
            for (const double first_s : {0.2, 0.4})
              for (const double second_s : {0.15, 0.35})
                starts.push_back(drift(x_acts + ahead, y, brake, grip, first_s, second_s));
  }
  return starts;
}

}  // namespace

PlanResult falsify(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                   const std::vector<Maneuver>& hints) {
  constexpr std::size_t kHintStarts = 3;
  constexpr std::size_t kSwerveStarts = 4;
  constexpr std::size_t kDriftStarts = 3;
  const int evaluations = scene.config().planner.falsifier_evaluations;
  const auto started = std::chrono::steady_clock::now();
  Search search(scene, model, limits);
  // The grid, each swerve scored.
  const std::vector<Swerve> grid = falsifier_swerves(scene, limits.allow_rear_lock);
  std::vector<double> scores;
  for (const Swerve& s : grid) {
    scores.push_back(search.evaluate({swerve_plan(scene, s), Tail::full_stop()}));
    if (search.found()) break;
  }
  // The nearest misses first, one of each score (rollouts that end alike, say in a contact before
  // the counter-steer, are one start).
  const auto nearest_first = [](const std::vector<double>& score) {
    std::vector<std::size_t> order(score.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] < score[b]; });
    order.erase(std::unique(order.begin(), order.end(),
                            [&](std::size_t a, std::size_t b) { return std::abs(score[a] - score[b]) < 1e-9; }),
                order.end());
    return order;
  };
  // The given maneuvers, nearest first, in the numbers of their segments.
  std::vector<Maneuver> starts = hints;
  std::vector<double> hint_scores;
  for (const Maneuver& m : starts) {
    if (search.found()) break;
    hint_scores.push_back(search.evaluate(m));
  }
  if (!search.found()) {
    const auto order = nearest_first(hint_scores);
    for (std::size_t k = 0; k < order.size() && k < kHintStarts; ++k) {
      Maneuver& m = starts[order[k]];
      search.optimise(
          segment_knobs(m, scene), [&m] { return m; }, evaluations);
    }
  }
  // The drift family, scored, and the nearest of it optimised like the hints.
  if (!search.found()) {
    std::vector<Maneuver> drifts = drift_starts(scene, limits.allow_rear_lock);
    std::vector<double> drift_scores;
    for (const Maneuver& m : drifts) {
      if (search.found()) break;
      drift_scores.push_back(search.evaluate(m));
    }
    const auto order = nearest_first(drift_scores);
    for (std::size_t k = 0; k < order.size() && k < kDriftStarts && !search.found(); ++k) {
      Maneuver& m = drifts[order[k]];
      search.optimise(
          segment_knobs(m, scene), [&m] { return m; }, evaluations);
    }
  }
  // The swerve family from its nearest misses.
  if (!search.found()) {
    const double max_steer = scene.config().ego.max_steer_rad;
    const auto order = nearest_first(scores);
    for (std::size_t k = 0; k < order.size() && k < kSwerveStarts; ++k) {
      // The knobs are the swerve's parameters (its side and rear lock held); each evaluation
      // rebuilds its plan.
      Swerve s = grid[order[k]];
      const std::vector<Knob> knobs{{&s.peak_rad, 0.02, max_steer, 0.04}, {&s.hold_s, 0.0, 1.2, 0.08},
                                    {&s.counter, 0.0, 1.5, 0.15},         {&s.counter_hold_s, 0.0, 1.0, 0.1},
                                    {&s.brake, 0.0, 1.0, 0.15},           {&s.brake_hold, 0.0, 1.0, 0.15},
                                    {&s.brake_out, 0.0, 1.0, 0.15}};
      search.optimise(
          knobs,
          [&] {
            return Maneuver{swerve_plan(scene, s), Tail::full_stop()};
          },
          evaluations);
    }
  }
  PlanResult result = search.take();
  result.stats.nodes = result.stats.rollouts;
  result.stats.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

PlanResult FalsifierPlanner::plan(const PlanningProblem& p) const { return falsify(p.scene, p.model, p.limits); }

}  // namespace emrm::sim
