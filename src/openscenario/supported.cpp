// The supported subset of OpenSCENARIO (supported.hpp): the single table the reader asks.

#include "emrm/openscenario/supported.hpp"

#include <fmt/format.h>

#include <array>
#include <string>

namespace emrm::openscenario {
namespace {

constexpr std::array<SupportedElement, 48> kSupported = {{
    {"EntityObject", "Vehicle",
     "BoundingBox, Performance (maxSpeed, maxAcceleration, maxDeceleration), vehicleCategory"},
    {"EntityObject", "Pedestrian", "BoundingBox, pedestrianCategory; not speed-limited"},
    {"EntityObject", "MiscObject", "BoundingBox, miscObjectCategory; never drives (esmini)"},
    {"EntityObject", "CatalogReference", "resolved through CatalogLocations, ParameterAssignments applied"},
    {"InitActions", "Private", "the entity's private actions, started at t = 0 in document order"},
    {"InitActions", "GlobalAction", "EnvironmentAction, ParameterAction"},
    {"Action", "PrivateAction", "in an Event, for each actor of the maneuver group"},
    {"Action", "GlobalAction", "EnvironmentAction, ParameterAction"},
    {"GlobalAction", "EnvironmentAction", "read and ignored: weather, light and friction do not change the motion"},
    {"GlobalAction", "ParameterAction", "SetAction, ModifyAction (AddValue, MultiplyByValue) on a global parameter"},
    {"PrivateAction", "LongitudinalAction", "SpeedAction only"},
    {"PrivateAction", "LateralAction", "LaneChangeAction, LaneOffsetAction"},
    {"PrivateAction", "TeleportAction", "any supported Position"},
    {"PrivateAction", "RoutingAction", "FollowTrajectoryAction only"},
    {"PrivateAction", "ControllerAction",
     "AssignControllerAction (any controller on the ego, esmini's default on the others), ActivateControllerAction"},
    {"PrivateAction", "ActivateControllerAction", "OpenSCENARIO 1.0's; no effect (the default controller)"},
    {"PrivateAction", "VisibilityAction", "graphics, sensors; traffic true only; no effect on the motion"},
    {"PrivateAction", "AppearanceAction", "read and ignored: lights and animations do not change the motion"},
    {"LongitudinalAction", "SpeedAction", "SpeedActionDynamics: every shape, time/distance/rate"},
    {"SpeedActionTarget", "AbsoluteTargetSpeed", "value"},
    {"SpeedActionTarget", "RelativeTargetSpeed", "delta or factor of an entity's speed, continuous"},
    {"LateralAction", "LaneChangeAction", "AbsoluteTargetLane, RelativeTargetLane, targetLaneOffset"},
    {"LateralAction", "LaneOffsetAction", "AbsoluteTargetLaneOffset, RelativeTargetLaneOffset, maxLateralAcc"},
    {"RoutingAction", "FollowTrajectoryAction", "Trajectory or CatalogReference; TimeReference None or Timing"},
    {"Shape", "Polyline", "Vertex time and Position; linear between vertices"},
    {"Shape", "Clothoid", "curvature, curvatureDot/curvaturePrime, length, startTime, stopTime, Position"},
    {"Condition", "ByEntityCondition", "TriggeringEntities any/all"},
    {"Condition", "ByValueCondition", "SimulationTimeCondition, StoryboardElementStateCondition"},
    {"EntityCondition", "TimeHeadwayCondition", "freespace, coordinateSystem, relativeDistanceType"},
    {"EntityCondition", "TimeToCollisionCondition", "entity or position target, freespace, distance type"},
    {"EntityCondition", "RelativeDistanceCondition", "freespace, coordinateSystem, relativeDistanceType"},
    {"EntityCondition", "ReachPositionCondition", "tolerance"},
    {"EntityCondition", "DistanceCondition", "freespace, coordinateSystem, relativeDistanceType"},
    {"EntityCondition", "SpeedCondition", "the entity's speed"},
    {"EntityCondition", "RelativeSpeedCondition", "the speed minus the entityRef's; no direction"},
    {"EntityCondition", "EndOfRoadCondition", "duration at the end of a lane without a successor"},
    {"EntityCondition", "CollisionCondition", "EntityRef or ByType: the bounding boxes overlap"},
    {"EntityCondition", "OffroadCondition", "duration beyond the road's lanes (those of type none left out)"},
    {"ByValueCondition", "SimulationTimeCondition", "every rule"},
    {"ByValueCondition", "StoryboardElementStateCondition", "every state and transition"},
    {"ByValueCondition", "ParameterCondition", "a global parameter: numbers by the rule, text equal or not"},
    {"Position", "WorldPosition", "x, y, h"},
    {"Position", "LanePosition", "roadId, laneId, s, offset, Orientation"},
    {"Position", "RoadPosition", "roadId, s, t, Orientation"},
    {"Position", "RelativeWorldPosition", "dx, dy, Orientation"},
    {"Position", "RelativeObjectPosition", "dx, dy in the entity's frame, Orientation"},
    {"Position", "RelativeLanePosition", "dLane, ds or dsLane, offset, Orientation"},
    {"Position", "RelativeRoadPosition", "ds, dt, Orientation"},
}};

}  // namespace

std::span<const SupportedElement> supported_elements() noexcept { return kSupported; }

bool is_supported(std::string_view choice, std::string_view element) noexcept {
  for (const auto& e : kSupported)
    if (e.choice == choice && e.element == element) return true;
  return false;
}

void require_supported(std::string_view choice, std::string_view element, const SourceLocation& where) {
  if (is_supported(choice, element)) return;
  std::string list;
  for (const auto& e : kSupported)
    if (e.choice == choice) list += (list.empty() ? "" : ", ") + std::string(e.element);
  throw InputError(
      where, fmt::format("{} is not supported in {} (supported: {})", element, choice, list.empty() ? "none" : list));
}

}  // namespace emrm::openscenario
