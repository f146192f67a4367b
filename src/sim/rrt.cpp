#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "emrm/sim/planner.hpp"

// The dual-tree kinodynamic RRT ("rrt"): see planner.hpp.

namespace emrm::sim {
namespace {

struct Node {
  VehicleState state;
  ActuatorState actuators;  // where the actuators are at `state` (commands still in flight)
  double t_s = 0.0;
  int parent = -1;
  std::vector<PathPoint> edge;       // the path that led here from the parent
  std::vector<ControlSegment> plan;  // the controls of that edge
};

// What the sampling reads of a node: its position, whether it still moves (at 0.5 m/s or more), and
// its weight for random_moving_node (e^(-t/0.3 s) when moving, else 0).
struct NodeSummary {
  core::Vec2 position;
  double weight = 0.0;
  bool moving = false;
};

class Rrt {
 public:
  Rrt(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, std::uint64_t seed, bool keep_tree)
      : scene_(scene),
        roller_(scene, model, limits),
        limits_(limits),
        rng_(seed),
        keep_tree_(keep_tree),
        free_(scene.free_bands(scene.config().simulation.horizon_s)),
        // Where the hazard is when the car, keeping its speed, would reach it (t = TTC): where it
        // stands, or ahead of where it appeared when it drives along the road; the goal's x range.
        goal_near_x_m_(scene.initial_distance_m() + (scene.passed_x_m(scene.ttc_s()) - scene.passed_x_m()) -
                       scene.config().ego.length_m),
        goal_far_x_m_(scene.passed_x_m(scene.ttc_s()) + scene.config().ego.length_m) {
    const double half_width = scene.config().ego.width_m / 2.0;
    for (std::size_t i = 0; i < free_.count; ++i) {
      const double lo = free_.band[i].low_m + half_width + 0.1;
      const double hi = free_.band[i].high_m - half_width - 0.1;
      if (hi > lo) passage_bands_.emplace_back(lo, hi);
    }
  }

  PlanResult run() {
    const auto started = std::chrono::steady_clock::now();
    const auto& cfg = scene_.config();
    const auto& pc = cfg.planner;

    // Perception latency: nothing is commanded until perception_latency_s.
    Node root;
    root.state = scene_.ego_initial();
    root.actuators = Actuators::at_rest(root.state);
    if (cfg.actuation.perception_latency_s > 0.0) {
      RolloutResult coast =
          roller_.roll(root.state, 0.0, {hold(Control{}, cfg.actuation.perception_latency_s)}, std::nullopt, 5);
      ++result_.stats.rollouts;
      if (coast.termination != Termination::kOpen) {
        if (coast.avoided())
          result_.avoidance = std::move(coast);
        else
          result_.collision = std::move(coast);
        return finish(started);
      }
      root.state = coast.end_state;
      root.actuators = std::move(coast.end_actuators);
      root.t_s = coast.end_time_s;
      root.edge = coast.path;
      root.plan = coast.maneuver.plan;
    }
    add_node(std::move(root));
    result_.stats.nodes = 1;
    if (fail_safes(0)) return finish(started);

    std::uniform_real_distribution<double> unit(0.0, 1.0);
    while (result_.stats.nodes < pc.max_nodes && iterations_ < 3 * pc.max_nodes) {
      if (elapsed_ms(started) > pc.max_time_ms) {
        result_.stats.time_limited = true;
        break;
      }
      const core::Vec2 target = sample_target(unit(rng_) < pc.goal_bias);
      // Half the time a uniformly chosen node: in a kinodynamic tree the nearest node in the plane is
      // nearly always a deep one, and the early decisions (where a short TTC is won or lost) would
      // never be revisited.
      const int near = unit(rng_) < 0.5 ? random_moving_node() : nearest(target);
      if (near < 0) break;
      if (extend(near, target)) break;
    }
    return finish(started);
  }

 private:
  static double elapsed_ms(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
  }

  PlanResult finish(std::chrono::steady_clock::time_point started) {
    result_.stats.time_ms = elapsed_ms(started);
    return std::move(result_);
  }

  core::Vec2 sample_target(bool towards_passage) {
    const Road& road = scene_.road();
    const auto& ego = scene_.config().ego;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double y_min = road.min_y_m;
    const double x0 = nodes_.front().state.x_m;
    const double far_x = goal_far_x_m_;
    if (towards_passage && free_.count > 0) {
      // A free band beside the hazard once it has stopped (or later); of two, either at random.
      const FreeBand& band = free_.band[free_.count == 1 || unit(rng_) < 0.5 ? 0 : 1];
      const double lo = band.low_m + ego.width_m / 2.0;
      const double hi = std::max(lo, band.high_m - ego.width_m / 2.0);
      const double near_x = goal_near_x_m_;
      return {near_x + unit(rng_) * (far_x + ego.length_m - near_x), lo + unit(rng_) * (hi - lo)};
    }
    return {x0 + unit(rng_) * (far_x + ego.length_m - x0), y_min + unit(rng_) * (road.max_y_m - y_min)};
  }

  // Nodes never change once added: what the sampling loops read of them is worked out here once,
  // and kept side by side for a fast scan.
  void add_node(Node node) {
    NodeSummary summary{{node.state.x_m, node.state.y_m}, 0.0, node.state.speed_mps() >= 0.5};
    if (summary.moving) summary.weight = std::exp(-node.t_s / 0.3);
    summaries_.push_back(summary);
    nodes_.push_back(std::move(node));
  }

  // A random moving node, early ones preferred (weight e^(-t/0.3 s)): with a short TTC the first
  // few tenths of a second decide the outcome, so that is where the search should branch most.
  int random_moving_node() {
    double total = 0.0;
    for (const NodeSummary& n : summaries_) total += n.weight;  // 0 for nodes at rest
    if (total <= 0.0) return -1;
    double pick = std::uniform_real_distribution<double>(0.0, total)(rng_);
    for (std::size_t i = 0; i < summaries_.size(); ++i) {
      pick -= summaries_[i].weight;
      if (pick <= 0.0 && summaries_[i].weight > 0.0) return static_cast<int>(i);
    }
    for (std::size_t i = summaries_.size(); i-- > 0;)
      if (summaries_[i].weight > 0.0) return static_cast<int>(i);
    return -1;
  }

  // The node nearest to the target in the plane, among nodes still moving and behind it.
  int nearest(const core::Vec2& target) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < summaries_.size(); ++i) {
      const NodeSummary& n = summaries_[i];
      if (!n.moving) continue;
      const double dx = target.x - n.position.x;
      const double dy = target.y - n.position.y;
      const double d2 = dx * dx + dy * dy + (dx < 0 ? 4.0 * dx * dx : 0.0);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = static_cast<int>(i);
      }
    }
    return best;
  }

  // A random brake level and rear lock; a random steering rate only when the control is held
  // open-loop (pursuit replaces it otherwise).
  Control sample_control(bool open_loop_steer) {
    const auto& p = scene_.config().ego;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    Control u;
    if (open_loop_steer) u.steer_rate_radps = (2.0 * unit(rng_) - 1.0) * p.max_steer_rate_radps;
    const double b = unit(rng_);
    u.brake = b < 0.4 ? 0.0 : (b < 0.7 ? unit(rng_) : 1.0);
    u.rear_lock = limits_.allow_rear_lock && unit(rng_) < 0.25;
    return u;
  }

  // Grows the goal tree from `from` towards `target` (best of a few sampled controls). Returns
  // true when the search is over (its objective is met).
  bool extend(int from, const core::Vec2& target) {
    const auto& pc = scene_.config().planner;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Node& base = nodes_[static_cast<std::size_t>(from)];
    std::optional<RolloutResult> best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
      const Control u = sample_control(k == 2);
      const double duration = pc.min_duration_s + unit(rng_) * (pc.max_duration_s - pc.min_duration_s);
      // Closed-loop pursuit of the sampled point (plain, and braking as hard as the turn allows); an
      // open-loop constant control, which reaches states pursuit would not; and a lane-change
      // primitive (steer in, hold, counter-steer), the maneuver class of the reference planner.
      std::vector<ControlSegment> plan{hold(u, duration)};
      if (k < 2) {
        plan[0].pursue = target;
        // Within grip, or beyond it: on low friction a saturated front still turns hardest.
        plan[0].pursuit_grip = unit(rng_) < 0.5 ? 0.9 : 2.0;
      }
      if (k == 1) {
        plan[0].friction_circle_brake = true;
        plan[0].control.brake = 1.0;
      }
      if (k == 3) plan = lane_change_primitive(base.state, base.actuators.steer_command_rad, target);
      RolloutResult r = roller_.roll(base.state, base.t_s, plan, std::nullopt, 5, &base.actuators);
      ++result_.stats.rollouts;
      if (keep_tree_) result_.tree.push_back({r.path, false});
      if (r.avoided()) {
        record_avoidance(from, r);
        return true;
      }
      if (r.termination != Termination::kOpen) {
        consider_failure_from(from, std::move(r), limits_.accept_contact);
        continue;
      }
      const double dx = target.x - r.end_state.x_m;
      const double dy = target.y - r.end_state.y_m;
      if (dx * dx + dy * dy < best_d2) {
        best_d2 = dx * dx + dy * dy;
        best = std::move(r);
      }
    }
    ++iterations_;
    ++result_.stats.nodes;  // an extension attempt counts against the budget even if all fail
    if (!best) return false;
    Node node;
    node.state = best->end_state;
    node.actuators = std::move(best->end_actuators);
    node.t_s = best->end_time_s;
    node.parent = from;
    node.edge = std::move(best->path);
    node.plan = std::move(best->maneuver.plan);
    add_node(std::move(node));
    return fail_safes(static_cast<int>(nodes_.size()) - 1);
  }

  // Steer towards the target's side at the full rate up to a sampled peak, hold, counter-steer
  // through straight to a sampled fraction of the peak, and straighten; brake held at a sampled level.
  // `steer_command_rad` is where the commanded wheel angle stands (the wheels may lag behind it).
  std::vector<ControlSegment> lane_change_primitive(const VehicleState& s, double steer_command_rad,
                                                    const core::Vec2& target) {
    const auto& p = scene_.config().ego;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double side = target.y < s.y_m ? -1.0 : 1.0;
    // Peaks scale with the steady-state steering angle at the friction limit (small on ice and at
    // speed), from half of it to four times it (a saturated front still turns hardest).
    const double v2 = std::max(s.vx_mps * s.vx_mps, 1.0);
    const double grip_angle = std::atan(p.wheelbase_m() * scene_.friction() * kGravity_mps2 / v2);
    const double peak = std::min(p.max_steer_rad, grip_angle * (0.5 + 3.5 * unit(rng_)));
    const double counter = unit(rng_);
    const double rate = p.max_steer_rate_radps;
    Control c;
    c.brake = unit(rng_) < 0.5 ? 0.0 : unit(rng_);
    c.rear_lock = false;
    std::vector<ControlSegment> plan;
    c.steer_rate_radps = side * rate;
    plan.push_back(hold(c, std::max(0.0, (side * peak - steer_command_rad) / (side * rate))));
    c.steer_rate_radps = 0.0;
    plan.push_back(hold(c, unit(rng_) * 1.2));  // long holds matter on low friction
    c.steer_rate_radps = -side * rate;
    plan.push_back(hold(c, peak * (1.0 + counter) / rate));
    c.steer_rate_radps = 0.0;
    plan.push_back(hold(c, unit(rng_) * 1.0));
    c.steer_rate_radps = side * rate;
    plan.push_back(hold(c, peak * counter / rate));
    return plan;
  }

  // Fail-safe branches from a node: a full stop, and with contact accepted, minimum-momentum
  // collisions (full braking steering away from the truck, and a braked drift). Returns true when
  // one of them avoids the truck.
  bool fail_safes(int index) {
    const Node& n = nodes_[static_cast<std::size_t>(index)];
    const auto& p = scene_.config().ego;
    std::vector<Tail> tails{Tail::full_stop()};
    // A braking swerve: stop as hard as grip allows while steering into a free passage.
    for (const auto& [lo, hi] : passage_bands_) {
      const double speed = n.state.speed_mps();
      const double reach = speed * speed / (2.0 * scene_.friction() * kGravity_mps2) + 2.0;
      tails.push_back(Tail{Control{0.0, 1.0, false}, false, true, core::Vec2{n.state.x_m + reach, 0.5 * (lo + hi)}});
    }
    if (limits_.accept_contact) {
      // Full braking steering towards each side left free of the hazard (right without one).
      for (std::size_t i = 0; i < std::max<std::size_t>(free_.count, 1); ++i) {
        const double side = free_.count == 0 || free_.band[i].right ? -1.0 : 1.0;
        Tail swerve{Control{side * p.max_steer_rate_radps, 1.0, false}, false, false, std::nullopt};
        tails.push_back(swerve);
        swerve.control.rear_lock = true;
        tails.push_back(swerve);
      }
    }
    for (const Tail& tail : tails) {
      RolloutResult r = roller_.roll(n.state, n.t_s, {}, tail, 5, &n.actuators);
      ++result_.stats.rollouts;
      if (keep_tree_) result_.tree.push_back({r.path, true});
      if (r.avoided()) {
        record_avoidance(index, r);
        return true;
      }
      // A fail-safe is what the car does when its search fails: its collision always counts.
      consider_failure_from(index, std::move(r), true);
    }
    return false;
  }

  void record_avoidance(int from, RolloutResult r) {
    result_.closest_miss_m = 0.0;
    prepend_chain(from, r);
    result_.avoidance = std::move(r);
  }

  // Makes a rollout from node `from` a whole path from t = 0, with the controls from t = 0.
  void prepend_chain(int from, RolloutResult& r) const {
    std::vector<int> order;
    for (int i = from; i >= 0; i = nodes_[static_cast<std::size_t>(i)].parent) order.push_back(i);
    std::vector<PathPoint> path;
    std::vector<ControlSegment> plan;
    std::reverse(order.begin(), order.end());  // root first
    for (const int i : order) {
      const Node& node = nodes_[static_cast<std::size_t>(i)];
      path.insert(path.end(), node.edge.begin(), node.edge.end());
      plan.insert(plan.end(), node.plan.begin(), node.plan.end());
    }
    path.insert(path.end(), r.path.begin(), r.path.end());
    plan.insert(plan.end(), r.maneuver.plan.begin(), r.maneuver.plan.end());
    r.path = std::move(path);
    r.maneuver.plan = std::move(plan);
  }

  // Keeps the least-loss failed rollout; `admissible` says whether a collision on this branch may
  // be the strategy's outcome (always for fail-safes, for goal-tree edges only with contact accepted).
  void consider_failure_from(int from, RolloutResult r, bool admissible) {
    result_.closest_miss_m = std::min(result_.closest_miss_m, lateral_miss_m(scene_, r));
    if (r.termination == Termination::kConstraint) return;  // violates the strategy
    if (r.termination == Termination::kContact && !admissible) return;
    if (result_.collision && !less_loss(r.impact, result_.collision->impact)) return;
    prepend_chain(from, r);
    result_.collision = std::move(r);
  }

  const Scene& scene_;
  Roller roller_;
  ControlLimits limits_;
  std::mt19937_64 rng_;
  bool keep_tree_;
  std::vector<Node> nodes_;
  PlanResult result_;
  FreeBands free_;        // beside the hazard at the horizon
  double goal_near_x_m_;  // the goal's x range beside the hazard
  double goal_far_x_m_;
  std::vector<std::pair<double, double>> passage_bands_;  // y ranges the ego's CG may use beside the hazard
  std::vector<NodeSummary> summaries_;                    // per node, what random_moving_node and nearest read
  int iterations_ = 0;                                    // extension attempts, some of which add no node
};

}  // namespace

PlanResult plan_rrt(const Scene& scene, const VehicleModel& model, const ControlLimits& limits, std::uint64_t seed,
                    bool keep_tree) {
  return Rrt(scene, model, limits, seed, keep_tree).run();
}

PlanResult RrtPlanner::plan(const PlanningProblem& p) const {
  return plan_rrt(p.scene, p.model, p.limits, p.seed, p.keep_tree);
}

}  // namespace emrm::sim
