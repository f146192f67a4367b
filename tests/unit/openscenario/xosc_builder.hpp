#pragma once

// Small OpenSCENARIO documents for the openscenario tests, written to a scratch folder: a scenario
// is its parts (parameters, entities, Init, acts, StopTrigger) in a fixed frame that validates
// against the 1.3 XSD.

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "emrm/openscenario/player.hpp"
#include "scratch.hpp"

namespace emrm::openscenario::test {

struct XoscParts {
  std::string parameters;  ///< <ParameterDeclaration .../> elements
  std::string catalogs;    ///< the content of <CatalogLocations>
  std::string road_file;   ///< LogicFile filepath, empty for none
  std::string entities;    ///< <ScenarioObject> elements
  std::string init;        ///< <Private> elements
  std::string acts;        ///< <Act> elements of one story; empty for no story
  std::string stop;        ///< <ConditionGroup> elements of the storyboard's StopTrigger
  int rev_minor = 3;
};

inline std::string xosc(const XoscParts& p) {
  return fmt::format(
      R"(<?xml version="1.0" encoding="UTF-8"?>
<OpenSCENARIO>
  <FileHeader revMajor="1" revMinor="{}" date="2026-01-01T00:00:00" description="test" author="emrm"/>
  <ParameterDeclarations>{}</ParameterDeclarations>
  <CatalogLocations>{}</CatalogLocations>
  <RoadNetwork>{}</RoadNetwork>
  <Entities>{}</Entities>
  <Storyboard>
    <Init><Actions>{}</Actions></Init>
    {}
    {}
  </Storyboard>
</OpenSCENARIO>
)",
      p.rev_minor, p.parameters, p.catalogs,
      p.road_file.empty() ? "" : fmt::format(R"(<LogicFile filepath="{}"/>)", p.road_file), p.entities, p.init,
      p.acts.empty() ? "" : fmt::format(R"(<Story name="story">{}</Story>)", p.acts),
      p.stop.empty() ? "" : fmt::format("<StopTrigger>{}</StopTrigger>", p.stop));
}

inline std::string vehicle_body(const std::string& length = "4", const std::string& width = "2") {
  return fmt::format(
      R"(<BoundingBox><Center x="0" y="0" z="0.75"/><Dimensions width="{}" length="{}" height="1.5"/></BoundingBox>
      <Performance maxSpeed="70" maxAcceleration="100" maxDeceleration="100"/>
      <Axles><FrontAxle maxSteering="0.5" wheelDiameter="0.6" trackWidth="1.6" positionX="2.8" positionZ="0.3"/>
      <RearAxle maxSteering="0" wheelDiameter="0.6" trackWidth="1.6" positionX="0" positionZ="0.3"/></Axles>)",
      width, length);
}

inline std::string vehicle(const std::string& name, const std::string& length = "4", const std::string& width = "2") {
  return fmt::format(
      R"(<ScenarioObject name="{}"><Vehicle name="{}" vehicleCategory="car">{}</Vehicle></ScenarioObject>)", name, name,
      vehicle_body(length, width));
}

inline std::string world_position(double x, double y, double h) {
  return fmt::format(R"(<Position><WorldPosition x="{}" y="{}" z="0" h="{}"/></Position>)", x, y, h);
}

inline std::string teleport(const std::string& position) {
  return fmt::format("<PrivateAction><TeleportAction>{}</TeleportAction></PrivateAction>", position);
}

inline std::string speed(const std::string& value, const std::string& shape = "step",
                         const std::string& dimension = "time", const std::string& dynamics_value = "0") {
  return fmt::format(R"(<PrivateAction><LongitudinalAction><SpeedAction>
      <SpeedActionDynamics dynamicsShape="{}" value="{}" dynamicsDimension="{}"/>
      <SpeedActionTarget><AbsoluteTargetSpeed value="{}"/></SpeedActionTarget>
    </SpeedAction></LongitudinalAction></PrivateAction>)",
                     shape, dynamics_value, dimension, value);
}

/// An entity placed at (x, y, h) with a speed.
inline std::string init_at(const std::string& name, double x, double y, double h, double v) {
  return fmt::format(R"(<Private entityRef="{}">{}{}</Private>)", name, teleport(world_position(x, y, h)),
                     speed(fmt::format("{}", v)));
}

inline std::string condition(const std::string& inner, const std::string& edge = "none", double delay = 0.0) {
  return fmt::format(R"(<Condition name="c" delay="{}" conditionEdge="{}">{}</Condition>)", delay, edge, inner);
}

inline std::string time_condition(double t, const std::string& rule = "greaterThan") {
  return condition(
      fmt::format(R"(<ByValueCondition><SimulationTimeCondition value="{}" rule="{}"/></ByValueCondition>)", t, rule));
}

inline std::string entity_condition(const std::string& entity, const std::string& inner) {
  return condition(fmt::format(R"(<ByEntityCondition><TriggeringEntities triggeringEntitiesRule="any">
      <EntityRef entityRef="{}"/></TriggeringEntities><EntityCondition>{}</EntityCondition></ByEntityCondition>)",
                               entity, inner));
}

inline std::string trigger(const std::string& tag, const std::string& conditions) {
  return fmt::format("<{0}><ConditionGroup>{1}</ConditionGroup></{0}>", tag, conditions);
}

/// An event of private actions (each a <PrivateAction>), started by `start` (a StartTrigger, or empty).
inline std::string event(const std::string& name, const std::string& private_actions, const std::string& start,
                         const std::string& priority = "override") {
  return fmt::format(R"(<Event name="{}" priority="{}"><Action name="{}_action">{}</Action>{}</Event>)", name, priority,
                     name, private_actions, start);
}

/// One act with one maneuver group of `actor` holding one maneuver of `events`.
inline std::string act(const std::string& actor, const std::string& events, const std::string& name = "act") {
  return fmt::format(R"(<Act name="{}"><ManeuverGroup name="{}_group" maximumExecutionCount="1">
      <Actors selectTriggeringEntities="false"><EntityRef entityRef="{}"/></Actors>
      <Maneuver name="{}_maneuver">{}</Maneuver></ManeuverGroup></Act>)",
                     name, name, actor, name, events);
}

inline std::filesystem::path write_file(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << text;
  return file;
}

inline std::filesystem::path write_scenario(const std::string& test, const XoscParts& parts,
                                            const std::string& name = "scenario.xosc") {
  return write_file(emrm::test::scratch_dir("openscenario", test) / name, xosc(parts));
}

}  // namespace emrm::openscenario::test
