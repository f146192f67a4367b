// Private actions as the document writes them (read_context.hpp).

#include <fmt/format.h>

#include <cmath>

#include "read_context.hpp"

namespace emrm::openscenario::detail {
namespace {

constexpr double kMaxSpeed_mps = 300.0;
constexpr double kMaxRange = 1e6;  // s, m or units per s of a transition

// A transition's dynamics; `rate_unit` is that of a rate (the changed quantity's per second).
TransitionDynamics read_dynamics(const xml::Element& e, std::string_view rate_unit, const ReadContext& c) {
  TransitionDynamics d;
  d.shape = static_cast<DynamicsShape>(c.choice(e, "dynamicsShape", {"step", "linear", "cubic", "sinusoidal"}));
  d.dimension = static_cast<DynamicsDimension>(c.choice(e, "dynamicsDimension", {"time", "distance", "rate"}));
  const std::string_view unit = d.dimension == DynamicsDimension::kTime       ? "s"
                                : d.dimension == DynamicsDimension::kDistance ? "m"
                                                                              : rate_unit;
  // A rate's sign is the direction of the change, which the target gives (esmini takes its size).
  d.value = d.dimension == DynamicsDimension::kRate ? std::fabs(c.number(e, "value", unit, -kMaxRange, kMaxRange))
                                                    : c.number(e, "value", unit, 0.0, kMaxRange);
  if (d.dimension == DynamicsDimension::kRate && d.shape != DynamicsShape::kStep && d.value <= 0.0)
    e.fail("value", "value: expected a rate > 0 (a rate of 0 never reaches the target)");
  return d;
}

SpeedAction read_speed(const xml::Element& e, const ReadContext& c) {
  SpeedAction a;
  a.dynamics = read_dynamics(e.required_child("SpeedActionDynamics"), "m/s2", c);
  const xml::Element target = c.chosen(e.required_child("SpeedActionTarget"), "SpeedActionTarget");
  if (target.name() == "AbsoluteTargetSpeed") {
    a.value = c.number(target, "value", "m/s", -kMaxSpeed_mps, kMaxSpeed_mps);
    a.parameter = c.parameter_of(target, "value").value_or("");
  } else {
    a.relative = c.entity_ref(target, "entityRef");
    a.delta = c.choice(target, "speedTargetValueType", {"delta", "factor"}) == 0;
    a.value = a.delta ? c.number(target, "value", "m/s", -kMaxSpeed_mps, kMaxSpeed_mps)
                      : c.number(target, "value", "", -100.0, 100.0);
    a.continuous = c.boolean(target, "continuous", false);
  }
  return a;
}

LaneChangeAction read_lane_change(const xml::Element& e, const ReadContext& c) {
  LaneChangeAction a;
  a.dynamics = read_dynamics(e.required_child("LaneChangeActionDynamics"), "m/s", c);
  a.target_lane_offset_m = c.optional_number(e, "targetLaneOffset", "m", -100.0, 100.0).value_or(0.0);
  const xml::Element holder = e.required_child("LaneChangeTarget");
  const auto children = holder.children();
  if (children.empty()) holder.fail("<LaneChangeTarget> needs RelativeTargetLane or AbsoluteTargetLane");
  const xml::Element& target = children.front();
  if (target.name() == "RelativeTargetLane") {
    a.relative = c.entity_ref(target, "entityRef");
    a.value = c.integer(target, "value", -100, 100);
  } else if (target.name() == "AbsoluteTargetLane") {
    a.value = c.integer(target, "value", -100, 100);
    if (a.value == 0) target.fail("value", "value: lane 0 is the centre lane, which has no width to drive in");
  } else {
    target.fail(
        fmt::format("{} is not supported in LaneChangeTarget (supported: RelativeTargetLane, "
                    "AbsoluteTargetLane)",
                    target.name()));
  }
  return a;
}

LaneOffsetAction read_lane_offset(const xml::Element& e, const ReadContext& c) {
  LaneOffsetAction a;
  a.continuous = c.boolean(e, "continuous", false);
  const xml::Element dynamics = e.required_child("LaneOffsetActionDynamics");
  a.shape = static_cast<DynamicsShape>(c.choice(dynamics, "dynamicsShape", {"step", "linear", "cubic", "sinusoidal"}));
  a.max_lateral_acc_mps2 = c.optional_number(dynamics, "maxLateralAcc", "m/s2", 0.0, 1000.0).value_or(0.5);
  a.max_lateral_acc_mps2 = std::max(a.max_lateral_acc_mps2, 1e-10);  // esmini: a tiny acceleration for 0
  const xml::Element holder = e.required_child("LaneOffsetTarget");
  const auto children = holder.children();
  if (children.empty()) holder.fail("<LaneOffsetTarget> needs RelativeTargetLaneOffset or AbsoluteTargetLaneOffset");
  const xml::Element& target = children.front();
  if (target.name() == "RelativeTargetLaneOffset") a.relative = c.entity_ref(target, "entityRef");
  a.value_m = c.number(target, "value", "m", -100.0, 100.0);
  return a;
}

Trajectory read_trajectory(const xml::Element& e, const ReadContext& outer) {
  // A trajectory may declare parameters of its own.
  ParameterScope scope(&outer.scope());
  declare_parameters(e, scope, outer, {});
  const ReadContext c = outer.with(scope);
  Trajectory t;
  t.name = c.text(e, "name");
  t.closed = c.boolean(e, "closed", false);
  const xml::Element shape = c.chosen(e.required_child("Shape"), "Shape");
  if (shape.name() == "Polyline") {
    std::vector<PolylineVertex> vertices;
    std::optional<double> previous;
    for (const xml::Element& v : shape.children("Vertex")) {
      PolylineVertex vertex{c.optional_number(v, "time", "s", -1e6, 1e6),
                            read_position(v.required_child("Position"), c)};
      if (vertex.time_s && previous && *vertex.time_s < *previous)
        v.fail("time", fmt::format("time: expected a time not before the previous vertex's ({} s)", *previous));
      if (vertex.time_s) previous = vertex.time_s;
      vertices.push_back(std::move(vertex));
    }
    if (vertices.empty()) shape.fail("<Polyline> needs at least one <Vertex>");
    t.shape = std::move(vertices);
  } else {
    ClothoidShape k;
    k.curvature_1pm = c.number(shape, "curvature", "1/m", -100.0, 100.0);
    const auto dot = c.optional_number(shape, "curvatureDot", "1/m2", -1e3, 1e3);
    const auto prime = c.optional_number(shape, "curvaturePrime", "1/m2", -1e3, 1e3);
    k.curvature_rate_1pm2 = prime.value_or(dot.value_or(0.0));
    k.length_m = c.number(shape, "length", "m", 0.0, 1e6);
    k.start_time_s = c.optional_number(shape, "startTime", "s", -1e6, 1e6);
    k.stop_time_s = c.optional_number(shape, "stopTime", "s", -1e6, 1e6);
    if (k.start_time_s && k.stop_time_s && *k.stop_time_s < *k.start_time_s)
      shape.fail("stopTime", "stopTime: expected a time not before startTime");
    if (const auto p = shape.child("Position")) k.start = read_position(*p, c);
    t.shape = k;
  }
  return t;
}

FollowTrajectoryAction read_follow_trajectory(const xml::Element& e, const ReadContext& c) {
  FollowTrajectoryAction a;
  a.initial_distance_offset_m = c.optional_number(e, "initialDistanceOffset", "m", 0.0, 1e6).value_or(0.0);
  std::optional<xml::Element> holder = e.child("TrajectoryRef");
  const xml::Element& source = holder ? *holder : e;
  if (const auto t = source.child("Trajectory")) {
    a.trajectory = read_trajectory(*t, c);
  } else if (const auto ref = source.child("CatalogReference")) {
    const CatalogEntry entry = resolve_catalog_reference(*ref, c);
    if (entry.element.name() != "Trajectory")
      ref.value().fail(fmt::format("the catalog entry is a {}, not a Trajectory", entry.element.name()));
    a.trajectory = read_trajectory(entry.element, c.with(*entry.scope));
  } else {
    e.fail("<FollowTrajectoryAction> needs a Trajectory, a TrajectoryRef or a CatalogReference");
  }
  const xml::Element time_reference = e.required_child("TimeReference");
  if (const auto timing = time_reference.child("Timing")) {
    a.timing = Timing{c.choice(*timing, "domainAbsoluteRelative", {"absolute", "relative"}) == 0,
                      c.number(*timing, "scale", "", 1e-6, 1e6), c.number(*timing, "offset", "s", -1e6, 1e6)};
  }
  return a;
}

}  // namespace

Action read_private_action(const xml::Element& private_action, const std::string& actor, const ReadContext& c) {
  const xml::Element kind = c.chosen(private_action, "PrivateAction");
  Action action{"", actor, SpeedAction{}, kind.where()};
  if (const auto parent = private_action.parent(); parent && parent->name() == "Action")
    action.name = c.text(*parent, "name");
  if (kind.name() == "ActivateControllerAction") {
    action.kind = ControllerAction{};
    return action;
  }
  if (kind.name() == "ControllerAction") {
    ControllerAction controller;
    for (const xml::Element& child : kind.children()) {
      if (child.name() == "ActivateControllerAction") continue;
      if (child.name() != "AssignControllerAction")
        child.fail(
            fmt::format("{} is not supported in ControllerAction (supported: AssignControllerAction, "
                        "ActivateControllerAction)",
                        child.name()));
      controller.assigned = read_controller(child, c);
    }
    action.kind = controller;
    return action;
  }
  if (kind.name() == "VisibilityAction") {
    // Graphics and sensors change nothing in the motion; an entity other traffic cannot see may
    // change how the others move (esmini's traffic), which the open-loop play does not model.
    if (!c.boolean(kind, "traffic", true))
      kind.fail("traffic", "traffic: false is not supported (an entity invisible to traffic; supported: true)");
    action.kind = AppearanceOnlyAction{};
    return action;
  }
  if (kind.name() == "AppearanceAction") {
    action.kind = AppearanceOnlyAction{};
    return action;
  }
  if (kind.name() == "TeleportAction") {
    action.kind = TeleportAction{read_position(kind.required_child("Position"), c)};
    return action;
  }
  const xml::Element inner = c.chosen(kind, kind.name());
  action.where = inner.where();
  if (inner.name() == "SpeedAction") {
    action.kind = read_speed(inner, c);
  } else if (inner.name() == "LaneChangeAction") {
    action.kind = read_lane_change(inner, c);
  } else if (inner.name() == "LaneOffsetAction") {
    action.kind = read_lane_offset(inner, c);
  } else {
    action.kind = read_follow_trajectory(inner, c);
  }
  return action;
}

}  // namespace emrm::openscenario::detail
