#pragma once

// An OpenSCENARIO scenario as emrm reads it (the supported subset: supported.hpp): its parameters,
// entities, Init and Storyboard, with every reference checked and every number in SI units.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "emrm/core/error.hpp"
#include "emrm/openscenario/dynamics.hpp"
#include "emrm/openscenario/parameters.hpp"
#include "emrm/openscenario/road_access.hpp"

namespace emrm::openscenario {

// ---- Entities ----

enum class EntityKind { kVehicle, kPedestrian, kMiscObject };

struct BoundingBox {
  double center_x_m = 0.0, center_y_m = 0.0, center_z_m = 0.0;  ///< from the reference point
  double width_m = 0.0, length_m = 0.0, height_m = 0.0;
};

/// A Vehicle's Performance; a pedestrian is not limited, a MiscObject cannot drive (all 0), as in
/// esmini: a speed action on it leaves it standing; a teleport or a trajectory still moves it.
struct Performance {
  double max_speed_mps = 1e9;
  double max_acceleration_mps2 = 1e9;
  double max_deceleration_mps2 = 1e9;
};

/// A controller other than esmini's default, as esmini types it (its esminiController property, else
/// the Controller's name: InteractiveController, ACCController, ...) and where the type is written.
/// Only the ego may have one: emrm drives the ego after the threat onset (before it, the ego follows
/// its storyboard as under esmini's default controller); every other entity plays open loop.
struct ControllerRef {
  std::string type;
  SourceLocation where;
};

struct Entity {
  std::string name;
  EntityKind kind = EntityKind::kVehicle;
  std::string category;  ///< vehicleCategory, pedestrianCategory or miscObjectCategory
  BoundingBox box;
  Performance performance;
  std::optional<double> mass_kg;  ///< its mass attribute (optional on a Vehicle before 1.1)
  SourceLocation where;
  std::optional<ControllerRef> controller;  ///< its ObjectController, when not esmini's default
};

// ---- Positions ----

/// An Orientation: heading (rad), relative to the road or the reference entity, or absolute.
struct Orientation {
  double h_rad = 0.0;
  bool relative = true;  ///< OpenSCENARIO's default type is relative
};

struct WorldPosition {
  double x_m = 0.0, y_m = 0.0;
  std::optional<double> h_rad;
};
struct LanePosition {
  std::string road_id;
  int lane_id = 0;
  double s_m = 0.0;
  double offset_m = 0.0;
  std::optional<Orientation> orientation;
};
struct RoadPosition {
  std::string road_id;
  double s_m = 0.0, t_m = 0.0;
  std::optional<Orientation> orientation;
};
struct RelativeWorldPosition {
  std::string entity;
  double dx_m = 0.0, dy_m = 0.0;
  std::optional<Orientation> orientation;
};
struct RelativeObjectPosition {  ///< dx, dy in the entity's own frame
  std::string entity;
  double dx_m = 0.0, dy_m = 0.0;
  std::optional<Orientation> orientation;
};
struct RelativeLanePosition {
  std::string entity;
  int d_lane = 0;
  double ds_m = 0.0;
  bool ds_along_lane = false;  ///< dsLane instead of ds (the same along a lane without curvature)
  double offset_m = 0.0;
  std::optional<Orientation> orientation;
};
struct RelativeRoadPosition {
  std::string entity;
  double ds_m = 0.0, dt_m = 0.0;
  std::optional<Orientation> orientation;
};

using PositionKind = std::variant<WorldPosition, LanePosition, RoadPosition, RelativeWorldPosition,
                                  RelativeObjectPosition, RelativeLanePosition, RelativeRoadPosition>;
struct Position {
  PositionKind kind;
  SourceLocation where;
};

// ---- Actions ----

struct TransitionDynamics {
  DynamicsShape shape = DynamicsShape::kStep;
  DynamicsDimension dimension = DynamicsDimension::kTime;
  double value = 0.0;  ///< s, m or (rate) units per s
};

struct SpeedAction {
  TransitionDynamics dynamics;
  double value = 0.0;                   ///< absolute m/s, or the delta (m/s) or factor
  std::string parameter;                ///< the global parameter an absolute value is ($name), if it is one
  std::optional<std::string> relative;  ///< RelativeTargetSpeed's entityRef
  bool delta = true;                    ///< speedTargetValueType delta (or factor)
  bool continuous = false;
};

struct LaneChangeAction {
  TransitionDynamics dynamics;
  int value = 0;                        ///< the absolute lane id, or the number of lanes to the left
  std::optional<std::string> relative;  ///< RelativeTargetLane's entityRef
  double target_lane_offset_m = 0.0;
};

struct LaneOffsetAction {
  DynamicsShape shape = DynamicsShape::kSinusoidal;
  double max_lateral_acc_mps2 = 0.0;
  double value_m = 0.0;
  std::optional<std::string> relative;  ///< RelativeTargetLaneOffset's entityRef
  bool continuous = false;
};

struct TeleportAction {
  Position position;
};

struct PolylineVertex {
  std::optional<double> time_s;
  Position position;
};
struct ClothoidShape {
  double curvature_1pm = 0.0;
  double curvature_rate_1pm2 = 0.0;
  double length_m = 0.0;
  std::optional<double> start_time_s, stop_time_s;
  std::optional<Position> start;  ///< absent: the entity's position when the action starts
};
struct Trajectory {
  std::string name;
  bool closed = false;
  std::variant<std::vector<PolylineVertex>, ClothoidShape> shape;
};

struct Timing {
  bool absolute = true;  ///< domainAbsoluteRelative
  double scale = 1.0;
  double offset_s = 0.0;
};

struct FollowTrajectoryAction {
  Trajectory trajectory;
  std::optional<Timing> timing;  ///< TimeReference None: no timing
  double initial_distance_offset_m = 0.0;
};

/// A GlobalAction's EnvironmentAction: read and ignored (weather, light and the road's friction do not
/// change the open-loop motion); it ends in its first step, as in esmini.
struct EnvironmentAction {};

/// A ControllerAction (or 1.0's ActivateControllerAction): it has no effect on the open-loop play
/// and completes at once. `assigned` is the controller an AssignControllerAction gives, when it is
/// not esmini's default (the ego's only: see ControllerRef).
struct ControllerAction {
  std::optional<ControllerRef> assigned;
};

/// A GlobalAction's ParameterAction: sets a global parameter's value (SetAction) or adds to or
/// multiplies it (ModifyAction), for the ParameterConditions; nothing else reads it again (esmini
/// resolves every other use when reading). The value is set when it starts, as in esmini.
struct ParameterAction {
  std::string parameter;
  std::optional<std::string> set;  ///< SetAction's value; else ModifyAction's rule
  double add = 0.0, multiply = 1.0;
};

/// A VisibilityAction (seen by traffic) or an AppearanceAction (lights, animations): neither changes
/// the open-loop motion; it ends in its first step, as in esmini.
struct AppearanceOnlyAction {};

using PrivateActionKind =
    std::variant<SpeedAction, LaneChangeAction, LaneOffsetAction, TeleportAction, FollowTrajectoryAction,
                 EnvironmentAction, ControllerAction, AppearanceOnlyAction, ParameterAction>;

struct Action {
  std::string name;
  std::string actor;  ///< the entity it acts on (a Private's entityRef; empty: each of the group's actors)
  PrivateActionKind kind;
  SourceLocation where;
};

// ---- Conditions ----

enum class Rule { kGreaterThan, kLessThan, kEqualTo, kGreaterOrEqual, kLessOrEqual, kNotEqualTo };
enum class ConditionEdge { kNone, kRising, kFalling, kRisingOrFalling };
enum class DistanceType { kLongitudinal, kLateral, kEuclidean };
enum class CoordinateSystem { kEntity, kLane, kRoad, kTrajectory };

struct DistanceSpec {
  bool freespace = false;
  DistanceType type = DistanceType::kEuclidean;
  CoordinateSystem system = CoordinateSystem::kEntity;
};

struct SimulationTimeCondition {
  double value_s = 0.0;
  Rule rule = Rule::kGreaterThan;
};
struct TimeHeadwayCondition {
  std::string entity;
  double value_s = 0.0;
  Rule rule = Rule::kLessThan;
  DistanceSpec distance;
};
struct TimeToCollisionCondition {
  std::variant<std::string, Position> target;
  double value_s = 0.0;
  Rule rule = Rule::kLessThan;
  DistanceSpec distance;
};
struct RelativeDistanceCondition {
  std::string entity;
  double value_m = 0.0;
  Rule rule = Rule::kLessThan;
  DistanceSpec distance;
};
struct ReachPositionCondition {
  Position position;
  double tolerance_m = 0.0;
};
struct DistanceCondition {
  Position position;
  double value_m = 0.0;
  Rule rule = Rule::kLessThan;
  DistanceSpec distance;
};
struct SpeedCondition {
  double value_mps = 0.0;
  Rule rule = Rule::kGreaterThan;
};
/// The entity's bounding box overlaps `entity`'s, or that of any other entity of `kind` (ByType).
struct CollisionCondition {
  std::string entity;  ///< empty: by type
  EntityKind kind = EntityKind::kVehicle;
};
/// A global parameter's value (as a ParameterAction leaves it) against `value`: as numbers when
/// both read as numbers, else as text (equalTo, notEqualTo).
struct ParameterCondition {
  std::string parameter;
  std::string value;
  Rule rule = Rule::kEqualTo;
};
/// The entity has been beyond its road's lanes for more than `duration_s`.
struct OffroadCondition {
  double duration_s = 0.0;
};
/// The entity has stood at the end of a lane without a successor for at least `duration_s`.
struct EndOfRoadCondition {
  double duration_s = 0.0;
};
/// The triggering entity's speed minus `entity`'s (esmini's, without a direction).
struct RelativeSpeedCondition {
  std::string entity;
  double value_mps = 0.0;
  Rule rule = Rule::kGreaterThan;
};

enum class ElementState {
  kStartTransition,
  kEndTransition,
  kStopTransition,
  kSkipTransition,
  kCompleteState,
  kRunningState,
  kStandbyState
};
enum class ElementType { kStory, kAct, kManeuverGroup, kManeuver, kEvent, kAction };
struct StoryboardElementStateCondition {
  ElementType type = ElementType::kEvent;
  std::string ref;
  ElementState state = ElementState::kEndTransition;
};

using ConditionKind =
    std::variant<SimulationTimeCondition, TimeHeadwayCondition, TimeToCollisionCondition, RelativeDistanceCondition,
                 ReachPositionCondition, DistanceCondition, SpeedCondition, RelativeSpeedCondition, EndOfRoadCondition,
                 CollisionCondition, OffroadCondition, ParameterCondition, StoryboardElementStateCondition>;

struct Condition {
  std::string name;
  double delay_s = 0.0;
  ConditionEdge edge = ConditionEdge::kNone;
  std::vector<std::string> triggering_entities;  ///< empty for a ByValueCondition
  bool all_entities = false;                     ///< triggeringEntitiesRule all (or any)
  ConditionKind kind;
  SourceLocation where;
};

/// A trigger: true when any group holds, a group when all its conditions do. No groups: never.
struct Trigger {
  std::vector<std::vector<Condition>> groups;
};

// ---- Storyboard ----

enum class Priority { kOverwrite, kOverride, kSkip, kParallel };

struct Event {
  std::string name;
  Priority priority = Priority::kOverride;
  int max_executions = 1;
  std::vector<Action> actions;
  std::optional<Trigger> start;  ///< absent: starts with its maneuver
};
struct Maneuver {
  std::string name;
  std::vector<Event> events;
};
struct ManeuverGroup {
  std::string name;
  int max_executions = 1;
  std::vector<std::string> actors;
  std::vector<Maneuver> maneuvers;
};
struct Act {
  std::string name;
  std::vector<ManeuverGroup> groups;
  std::optional<Trigger> start;  ///< absent: starts with its story
  std::optional<Trigger> stop;
};
struct Story {
  std::string name;
  std::vector<Act> acts;
};

struct Storyboard {
  std::vector<Action> init;  ///< the Init's private actions, in document order
  std::vector<Story> stories;
  std::optional<Trigger> stop;
};

/// An attribute that refers to a global parameter: the parameter, and where. A numeric attribute
/// whose whole value it is (`$name`) also has the attribute's unit (m, s, m/s, ...); others (an
/// expression, a text, a pure number) have none.
struct ParameterUse {
  std::string parameter;
  std::string unit;
  SourceLocation where;
};

/// A scenario read by load_openscenario (reader.hpp).
struct Scenario {
  std::filesystem::path file;
  std::vector<Parameter> parameters;  ///< the global declarations, resolved (overrides applied)
  std::vector<ParameterUse> uses;     ///< in document order (the parameters that matter, their units)
  ParameterOverrides overrides;       ///< those it was read with
  std::vector<Entity> entities;
  /// The entity emrm drives: ReadOptions::ego, else default_ego's choice; empty when there is none.
  std::string ego;
  Storyboard storyboard;
  std::shared_ptr<const opendrive::RoadNetwork> network;  ///< the RoadNetwork's LogicFile; null without one
  std::shared_ptr<const RoadAccess> roads;                ///< the player's view of `network`

  [[nodiscard]] const Entity* find_entity(const std::string& name) const;
  /// The names of the storyboard's elements (stories, acts, maneuver groups, maneuvers, events,
  /// actions), in document order.
  [[nodiscard]] std::vector<std::string> element_names() const;
};

}  // namespace emrm::openscenario
