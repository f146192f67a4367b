// Triggers and conditions as the document writes them (read_context.hpp).

#include <fmt/format.h>

#include "read_context.hpp"

namespace emrm::openscenario::detail {
namespace {

constexpr double kMaxDistance_m = 1e7;
constexpr double kMaxTime_s = 1e7;

Rule read_rule(const xml::Element& e, const ReadContext& c) {
  return static_cast<Rule>(
      c.choice(e, "rule", {"greaterThan", "lessThan", "equalTo", "greaterOrEqual", "lessOrEqual", "notEqualTo"}));
}

DistanceSpec read_distance(const xml::Element& e, const ReadContext& c) {
  DistanceSpec d;
  d.freespace = c.boolean(e, "freespace", false);
  // OpenSCENARIO 1.0: along the route means in road coordinates; esmini leaves the distance's type
  // at its default, euclidean (its cut-in_external changes lanes by it).
  if (e.attribute("alongRoute") && c.boolean(e, "alongRoute", false)) d.system = CoordinateSystem::kRoad;
  if (e.attribute("coordinateSystem"))
    d.system = static_cast<CoordinateSystem>(c.choice(e, "coordinateSystem", {"entity", "lane", "road", "trajectory"}));
  if (d.system == CoordinateSystem::kTrajectory)
    e.fail("coordinateSystem", "coordinateSystem: trajectory is not supported (supported: entity, lane, road)");
  if (e.attribute("relativeDistanceType")) {
    const std::size_t type =
        c.choice(e, "relativeDistanceType", {"longitudinal", "lateral", "euclidianDistance", "cartesianDistance"});
    d.type = static_cast<DistanceType>(std::min<std::size_t>(type, 2));
  }
  return d;
}

ConditionKind read_entity_condition(const xml::Element& e, const ReadContext& c) {
  const std::string_view kind = e.name();
  if (kind == "SpeedCondition") {
    if (const auto direction = c.optional_text(e, "direction"); direction && *direction != "longitudinal")
      e.fail("direction", fmt::format("direction: {} is not supported (supported: longitudinal, or none)", *direction));
    return SpeedCondition{c.number(e, "value", "m/s", -1000.0, 1000.0), read_rule(e, c)};
  }
  if (kind == "CollisionCondition") {
    if (const auto ref = e.child("EntityRef")) return CollisionCondition{c.entity_ref(*ref, "entityRef"), {}};
    const xml::Element by_type = e.required_child("ByType");
    const std::size_t type = c.choice(by_type, "type", {"vehicle", "pedestrian", "miscellaneous"});
    return CollisionCondition{"", static_cast<EntityKind>(type)};
  }
  if (kind == "OffroadCondition") return OffroadCondition{c.number(e, "duration", "s", 0.0, kMaxTime_s)};
  if (kind == "EndOfRoadCondition") return EndOfRoadCondition{c.number(e, "duration", "s", 0.0, kMaxTime_s)};
  if (kind == "RelativeSpeedCondition") {
    if (const auto direction = c.optional_text(e, "direction"))
      e.fail("direction",
             fmt::format("direction: {} is not supported (supported: none, the speeds' difference)", *direction));
    return RelativeSpeedCondition{c.entity_ref(e, "entityRef"), c.number(e, "value", "m/s", -1000.0, 1000.0),
                                  read_rule(e, c)};
  }
  if (kind == "TimeHeadwayCondition")
    return TimeHeadwayCondition{c.entity_ref(e, "entityRef"), c.number(e, "value", "s", 0.0, kMaxTime_s),
                                read_rule(e, c), read_distance(e, c)};
  if (kind == "TimeToCollisionCondition") {
    TimeToCollisionCondition t{std::string{}, c.number(e, "value", "s", 0.0, kMaxTime_s), read_rule(e, c),
                               read_distance(e, c)};
    const xml::Element target = e.required_child("TimeToCollisionConditionTarget");
    if (const auto ref = target.child("EntityRef")) {
      t.target = c.entity_ref(*ref, "entityRef");
    } else {
      t.target = read_position(target.required_child("Position"), c);
    }
    return t;
  }
  if (kind == "RelativeDistanceCondition")
    return RelativeDistanceCondition{c.entity_ref(e, "entityRef"), c.number(e, "value", "m", 0.0, kMaxDistance_m),
                                     read_rule(e, c), read_distance(e, c)};
  if (kind == "ReachPositionCondition")
    return ReachPositionCondition{read_position(e.required_child("Position"), c),
                                  c.number(e, "tolerance", "m", 0.0, kMaxDistance_m)};
  return DistanceCondition{read_position(e.required_child("Position"), c),
                           c.number(e, "value", "m", 0.0, kMaxDistance_m), read_rule(e, c), read_distance(e, c)};
}

ConditionKind read_value_condition(const xml::Element& e, const ReadContext& c) {
  if (e.name() == "ParameterCondition") {
    ParameterCondition p{e.required("parameterRef"), c.text(e, "value"), read_rule(e, c)};
    if (c.scope().find(p.parameter) == nullptr)
      e.fail("parameterRef", fmt::format("parameterRef: no parameter '{}' is declared", p.parameter));
    return p;
  }
  if (e.name() == "SimulationTimeCondition")
    return SimulationTimeCondition{c.number(e, "value", "s", -kMaxTime_s, kMaxTime_s), read_rule(e, c)};
  StoryboardElementStateCondition s;
  static constexpr ElementType kTypes[] = {ElementType::kStory, ElementType::kAct,    ElementType::kManeuver,
                                           ElementType::kEvent, ElementType::kAction, ElementType::kManeuverGroup};
  s.type =
      kTypes[c.choice(e, "storyboardElementType", {"story", "act", "maneuver", "event", "action", "maneuverGroup"})];
  // OpenSCENARIO 1.1+ may name the element by its path, "Story::Act::...::Name": its last part
  // names it (elements are matched by name and type).
  s.ref = c.text(e, "storyboardElementRef");
  if (const auto last = s.ref.rfind("::"); last != std::string::npos) s.ref = s.ref.substr(last + 2);
  if (c.elements_ != nullptr && !(*c.elements_)[s.type].contains(s.ref))
    e.fail("storyboardElementRef", fmt::format("storyboardElementRef: the storyboard has no {} named '{}'",
                                               e.attribute("storyboardElementType").value_or(""), s.ref));
  s.state = static_cast<ElementState>(c.choice(e, "state",
                                               {"startTransition", "endTransition", "stopTransition", "skipTransition",
                                                "completeState", "runningState", "standbyState"}));
  return s;
}

Condition read_condition(const xml::Element& e, const ReadContext& c) {
  Condition condition;
  condition.where = e.where();
  // A condition's name is referred to by nothing: one written as esmini's string arithmetic
  // ("${Brake + _ + $Time}", not an expression of the standard) is kept as written.
  try {
    condition.name = c.text(e, "name");
  } catch (const InputError&) {
    condition.name = e.attribute("name").value_or("");
  }
  condition.delay_s = c.number(e, "delay", "s", 0.0, kMaxTime_s);
  condition.edge =
      static_cast<ConditionEdge>(c.choice(e, "conditionEdge", {"none", "rising", "falling", "risingOrFalling"}));
  const xml::Element by = c.chosen(e, "Condition");
  if (by.name() == "ByValueCondition") {
    condition.kind = read_value_condition(c.chosen(by, "ByValueCondition"), c);
    return condition;
  }
  const xml::Element entities = by.required_child("TriggeringEntities");
  condition.all_entities = c.choice(entities, "triggeringEntitiesRule", {"any", "all"}) == 1;
  for (const xml::Element& ref : entities.children("EntityRef"))
    condition.triggering_entities.push_back(c.entity_ref(ref, "entityRef"));
  if (condition.triggering_entities.empty()) entities.fail("<TriggeringEntities> needs at least one <EntityRef>");
  condition.kind = read_entity_condition(c.chosen(by.required_child("EntityCondition"), "EntityCondition"), c);
  return condition;
}

}  // namespace

Trigger read_trigger(const xml::Element& trigger, const ReadContext& c) {
  Trigger t;
  for (const xml::Element& group : trigger.children("ConditionGroup")) {
    t.groups.emplace_back();
    for (const xml::Element& condition : group.children("Condition"))
      t.groups.back().push_back(read_condition(condition, c));
  }
  return t;
}

}  // namespace emrm::openscenario::detail
