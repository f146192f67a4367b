#pragma once

// Planners: the search for a strategy's maneuver, behind one small interface (OMPL's Planner),
// selected by name. Two are built in:
// - "rrt", the dual-tree kinodynamic RRT (docs/planner.md), used by the evasive strategies;
// - "reference", a dense search over a parametric maneuver family, for tests and diagnostics.
//
// The RRT grows a goal tree (green) towards the passage beside the truck; from every new node it
// rolls out fail-safe branches (orange): a full stop, and, when contact is accepted,
// minimum-momentum collision maneuvers. It keeps the best avoidance path and the least-loss
// collision path, is deterministic for a seed, bounded by nodes (and a wall-clock guard), and
// stops early once its strategy's objective is met.

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emrm/sim/loss.hpp"
#include "emrm/sim/rollout.hpp"
#include "emrm/sim/scene.hpp"
#include "emrm/sim/vehicle.hpp"

namespace emrm::sim {

/// One edge of a search tree, kept for figures.
struct TreeEdge {
  std::vector<PathPoint> points;
  bool fail_safe = false;  ///< orange (fail-safe) vs green (goal tree)
};

struct PlannerStats {
  int nodes = 0;
  int rollouts = 0;
  double time_ms = 0.0;
  bool time_limited = false;  ///< the wall-clock guard stopped the search (results may then vary)
  /// Counts another search's work into this one.
  void add(const PlannerStats& other) noexcept {
    nodes += other.nodes;
    rollouts += other.rollouts;
    time_ms += other.time_ms;
    time_limited = time_limited || other.time_limited;
  }
};

/// The planner's answer: the best avoidance (if any) and the least-loss collision (if any).
struct PlanResult {
  std::optional<RolloutResult> avoidance;  ///< full executed path from t = 0
  std::optional<RolloutResult> collision;  ///< least loss, then lowest Δv
  /// How close the search came to getting past the truck: 0 when a rollout got past it (an
  /// avoidance, or a pass whose recovery failed), else the least lateral_miss_m of its contacts;
  /// infinity when it knows nothing (no contact, no pass).
  double closest_miss_m = std::numeric_limits<double>::infinity();
  PlannerStats stats;
  std::vector<TreeEdge> tree;  ///< only when asked for
};

/// What a planner is asked: a cell's scene, the vehicle model, the strategy's limits, a seed
/// (every random choice follows from it) and whether to keep the search tree for figures.
struct PlanningProblem {
  const Scene& scene;
  const VehicleModel& model;
  ControlLimits limits;
  std::uint64_t seed = 0;
  bool keep_tree = false;
};

/// A way of searching for a maneuver. Implementations are stateless and thread-safe: plan() may
/// run concurrently for different problems.
class Planner {
 public:
  virtual ~Planner() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// The best avoidance and least-loss collision found; deterministic for a problem (the RRT's
  /// wall-clock guard aside, which PlannerStats::time_limited reports).
  [[nodiscard]] virtual PlanResult plan(const PlanningProblem& problem) const = 0;
};

/// The dual-tree kinodynamic RRT.
class RrtPlanner final : public Planner {
 public:
  [[nodiscard]] std::string_view name() const override { return "rrt"; }
  [[nodiscard]] PlanResult plan(const PlanningProblem& problem) const override;
};

/// The dense search over a parametric maneuver family (ignores the seed and keep_tree).
class ReferencePlanner final : public Planner {
 public:
  [[nodiscard]] std::string_view name() const override { return "reference"; }
  [[nodiscard]] PlanResult plan(const PlanningProblem& problem) const override;
};

/// The planner registered under `name`, or nullptr. Built in: "rrt" and "reference".
[[nodiscard]] const Planner* find_planner(std::string_view name);
/// The registered planners' names, in registration order.
[[nodiscard]] std::vector<std::string> planner_names();

/// Adds a planner under its name() for as long as the returned registration lives (a test's or a
/// plugin's own planner). Throws UsageError if the name is taken. Register before simulating:
/// registration is not synchronised with running simulations.
class PlannerRegistration {
 public:
  explicit PlannerRegistration(std::unique_ptr<Planner> planner);
  ~PlannerRegistration();
  PlannerRegistration(const PlannerRegistration&) = delete;
  PlannerRegistration& operator=(const PlannerRegistration&) = delete;

 private:
  std::string name_;
};

/// The dual-tree kinodynamic RRT ("rrt"). `seed` fixes every random choice.
[[nodiscard]] PlanResult plan_rrt(const Scene& scene, const VehicleModel& model, const ControlLimits& limits,
                                  std::uint64_t seed, bool keep_tree);

/// The reference planner ("reference"): a dense search over a parametric maneuver family (steer
/// direction, peak steer, hold and counter-steer timing, brake level, rear lock).
[[nodiscard]] PlanResult plan_reference(const Scene& scene, const VehicleModel& model, const ControlLimits& limits);

/// How far a rollout that hit the hazard was from squeezing past it: how far the ego reaches across
/// the hazard's edge beside a free band at the contact, the least over the bands (the T-junction's:
/// the ego's highest corner above the truck's front); 0 when it got past the hazard; infinity for
/// any other end, or with no band free.
[[nodiscard]] double lateral_miss_m(const Scene& scene, const RolloutResult& rollout) noexcept;

/// Least-loss order: lower level first, then lower P(fatal), lower P(MAIS3+), lower Δv (for two
/// impacts, Δv's order; a rollover or a pedestrian's injury is weighed by its risks).
[[nodiscard]] bool less_loss(const ImpactAssessment& a, const ImpactAssessment& b) noexcept;

}  // namespace emrm::sim
