#pragma once

// The player's state (player.hpp), private to src/openscenario: the entities as they move, the
// storyboard's elements with esmini's states and transitions, the running actions and the
// conditions' memories.

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emrm/openscenario/player.hpp"
#include "emrm/openscenario/scenario.hpp"

namespace emrm::openscenario::detail {

/// esmini's SMALL_NUMBER: the slack of its rules (a > b + 1e-6), of "target reached", of "no speed".
constexpr double kSmall = 1e-6;

/// An entity as it moves. On a road it is held in lane coordinates and its world pose derived;
/// following a trajectory, or without roads, it is held in the world frame.
struct EntityState {
  const Entity* spec = nullptr;
  bool on_lane = false;  ///< `lane` holds its position (else x, y, heading do)
  LaneCoord lane;
  int direction = 1;                ///< +1 driving towards increasing s, -1 towards decreasing s
  double heading_offset_rad = 0.0;  ///< heading relative to the driving direction (a lane change's)
  WorldPose pose;
  double speed_mps = 0.0;
  bool moved_longitudinally = false;  ///< an action moved it this step (the default controller does not)
  /// When the default controller first found its lane ending without a successor (esmini's end of
  /// road timestamp); cleared when it moves on.
  std::optional<double> end_of_road_since_s;
  /// When it was first found beyond its road's lanes (esmini's off road timestamp); cleared when
  /// it is back on them.
  std::optional<double> off_road_since_s;
};

/// What the actions, positions and conditions share: the entities and the roads.
struct World {
  const Scenario* scenario = nullptr;
  const RoadAccess* roads = nullptr;  ///< null without a road network
  std::vector<EntityState> entities;
  std::map<std::string, std::string> parameters;  ///< the global parameters' values as ParameterActions set them
  double time_s = 0.0;
  /// PlayOptions::element_started, when given.
  const std::function<void(double, const std::string&)>* element_started = nullptr;

  [[nodiscard]] EntityState& entity(const std::string& name);
  [[nodiscard]] const EntityState& entity(const std::string& name) const;
  /// Sets an entity's lane coordinates and derives its world pose.
  void place_on_lane(EntityState& e, const LaneCoord& at, int direction) const;
  /// Re-derives the world pose of an entity held in lane coordinates.
  void update_pose(EntityState& e) const;
  /// Holds an entity at a world pose and finds the lane it is in; false when there is none.
  bool place_at(EntityState& e, const WorldPose& pose) const;
};

/// A position resolved: the world pose and, when it is on a road, its lane coordinates.
struct ResolvedPosition {
  WorldPose pose;
  std::optional<LaneCoord> lane;
  int direction = 1;
};
/// Resolves `position` against the world as it is now; `subject` is the entity it will be applied
/// to (its heading is the default orientation of a relative position), or nullptr.
[[nodiscard]] ResolvedPosition resolve(const World& world, const Position& position, const EntityState* subject);

// ---- storyboard elements ----

enum class State { kInit, kStandby, kRunning, kComplete };
enum class StateTransition { kNone, kStart, kEnd, kStop, kSkip, kInitToStandby };

struct StateChange {
  State state = State::kInit;
  StateTransition transition = StateTransition::kNone;
};

class ActionRuntime;
class ConditionRuntime;
class TriggerRuntime;

/// What a running action may be stopped for: the domains it controls.
enum Domain : unsigned { kLongitudinal = 1U, kLateral = 2U };

/// One element of the storyboard tree with esmini's state machine (StoryboardElement.cpp).
struct Node {
  ElementType type = ElementType::kStory;
  bool is_storyboard = false;
  std::string name;
  State state = State::kInit;
  StateTransition transition = StateTransition::kNone;
  int executions = 0;
  int max_executions = 1;  ///< -1: no limit
  Priority priority = Priority::kOverride;
  Node* parent = nullptr;
  std::vector<Node*> children;
  std::unique_ptr<TriggerRuntime> start_trigger, stop_trigger;
  std::unique_ptr<ActionRuntime> action;  ///< for an action element
  std::vector<ConditionRuntime*> listeners;
};

/// The storyboard as it runs.
class StoryboardRuntime {
 public:
  StoryboardRuntime(const Scenario& scenario, World& world);
  ~StoryboardRuntime();

  /// esmini's StoryBoard::Start: Init actions started, the storyboard running.
  void start();
  /// One step at `time_s` (the time before it): triggers evaluated, then the running actions
  /// stepped, Init's first. Returns false when the storyboard's StopTrigger ended it.
  bool step(double time_s, double dt_s);

 private:
  void build(const Scenario& scenario);
  Node* add(ElementType type, const std::string& name, Node* parent);
  void start(Node& node, double time_s);
  void start_event(Node& event, double time_s);
  void end(Node& node);
  void stop(Node& node);
  void eval_triggers(Node& node, double time_s);
  void step(Node& node, double time_s, double dt_s);
  void propagate(Node& node);
  void set_state(Node& node, State state, StateTransition transition);
  void reset(Node& node);

  World& world_;
  std::vector<std::unique_ptr<Node>> nodes_;
  Node* root_ = nullptr;
  std::vector<std::unique_ptr<ActionRuntime>> init_;
};

// ---- actions ----

/// A trajectory resolved into the world frame when its action starts: poses along its arc length,
/// and the time (relative to the trajectory's own clock) at which each is reached when timed.
struct ResolvedTrajectory {
  std::vector<WorldPose> points;  ///< a polyline's vertices (heading: the segment's)
  std::vector<double> arc_m;      ///< arc length at each vertex
  std::vector<double> times_s;    ///< vertex times (empty when the vertices have none)
  std::optional<ClothoidShape> clothoid;
  WorldPose clothoid_start;
  [[nodiscard]] double length_m() const;
  [[nodiscard]] WorldPose at_arc(double s_m) const;
  /// The arc length reached at trajectory time `t_s` (clamped to the timed span).
  [[nodiscard]] double arc_at_time(double t_s) const;
  [[nodiscard]] double start_time_s() const;
  [[nodiscard]] double end_time_s() const;
  [[nodiscard]] bool timed() const;
};

/// A private action on one entity: started once, stepped while running, ended by itself.
class ActionRuntime {
 public:
  ActionRuntime(const Action& spec, std::string actor) : spec_(spec), actor_(std::move(actor)) {}
  /// Starts the action; returns true when it is done at once (a teleport).
  bool start(World& world, double time_s);
  /// Steps the action; returns true when it has ended in this step.
  bool step(World& world, double time_s, double dt_s);
  [[nodiscard]] unsigned domains() const;
  [[nodiscard]] const std::string& actor() const noexcept { return actor_; }
  [[nodiscard]] bool running() const noexcept { return running_; }
  void set_running(bool running) noexcept { running_ = running; }
  [[nodiscard]] const Action& spec() const noexcept { return spec_; }

 private:
  void start_speed(World& world, const SpeedAction& a);
  bool step_speed(World& world, const SpeedAction& a, double dt_s);
  void start_lane_change(World& world, const LaneChangeAction& a);
  bool step_lane_change(World& world, double dt_s);
  void start_lane_offset(World& world, const LaneOffsetAction& a);
  bool step_lane_offset(World& world, const LaneOffsetAction& a, double dt_s);
  void start_trajectory(World& world, const FollowTrajectoryAction& a);
  bool step_trajectory(World& world, const FollowTrajectoryAction& a, double time_s, double dt_s);
  [[nodiscard]] double speed_target(const World& world, const SpeedAction& a) const;

  const Action& spec_;
  std::string actor_;
  bool running_ = false;
  openscenario::Transition transition_;  // of speed (m/s) or lateral offset (m, lane-agnostic sign)
  double param_ = 0.0;                   // x of the transition: s or m since the start
  double scale_ = 1.0;                   // a speed transition stretched to the vehicle's acceleration
  bool reached_ = false;
  DynamicsDimension lane_change_dimension_ = DynamicsDimension::kTime;
  LaneCoord internal_;  // a lane change's position in its target lane
  ResolvedTrajectory path_;
  double path_time_s_ = 0.0;
  double path_s_m_ = 0.0;
};

// ---- conditions and triggers ----

/// One condition's memory: its last value (for edges), its value history (for delays) and, for
/// a storyboard element state, the state changes it has not seen yet.
class ConditionRuntime {
 public:
  explicit ConditionRuntime(const Condition& spec) : spec_(spec) {}
  bool evaluate(const World& world, double time_s);
  void reset();
  void set_idle() noexcept { evaluated_ = false; }
  void notify(const StateChange& change) { pending_.push_back(change); }
  [[nodiscard]] const Condition& spec() const noexcept { return spec_; }

 private:
  bool check(const World& world, double time_s);
  bool check_state();
  bool delayed_value(double time_s);
  void register_value(double time_s, bool value);

  const Condition& spec_;
  bool last_result_ = false;
  bool evaluated_ = false;
  bool value_ = false;
  std::vector<std::pair<double, bool>> history_;
  std::size_t history_index_ = 0;
  std::vector<StateChange> pending_;
  StateChange latest_;
};

class TriggerRuntime {
 public:
  explicit TriggerRuntime(const Trigger& spec);
  bool evaluate(const World& world, double time_s);
  void reset();
  [[nodiscard]] std::vector<std::vector<std::unique_ptr<ConditionRuntime>>>& groups() noexcept { return groups_; }

 private:
  std::vector<std::vector<std::unique_ptr<ConditionRuntime>>> groups_;
};

/// The distance from `from` to `to` as a condition measures it (DistanceSpec); signed for a
/// longitudinal or lateral distance (positive: ahead, to the left).
[[nodiscard]] double measured_distance(const World& world, const EntityState& from, const EntityState& to,
                                       const DistanceSpec& spec);
[[nodiscard]] double measured_distance(const World& world, const EntityState& from, const WorldPose& to,
                                       const DistanceSpec& spec);
/// Whether the two entities' bounding boxes overlap in the plane (esmini's Object::Collision).
[[nodiscard]] bool boxes_overlap(const EntityState& a, const EntityState& b);

}  // namespace emrm::openscenario::detail
