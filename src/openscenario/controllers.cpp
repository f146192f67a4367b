// Controllers (read_context.hpp): esmini's type of each controller, and the rule that only the ego
// may have one other than esmini's default (emrm drives the ego; the others play open loop).

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "emrm/openscenario/reader.hpp"
#include "read_context.hpp"

namespace emrm::openscenario {

const Entity* default_ego(const std::vector<Entity>& entities) {
  for (const char* name : {"Ego", "ego", "hero"})
    for (const Entity& e : entities)
      if (e.name == name) return &e;
  for (const Entity& e : entities)
    if (e.kind == EntityKind::kVehicle) return &e;
  return nullptr;
}

namespace detail {
namespace {

// esmini's controllers other than its default (ScenarioReader's controller registry): each moves
// its entity in ways the storyboard does not say.
constexpr std::string_view kOtherControllers[] = {"ACCController",
                                                  "ALKSController",
                                                  "ALKS_R157SM_Controller",
                                                  "ECE_ALKS_RefDriverController",
                                                  "ExternalController",
                                                  "FollowGhostController",
                                                  "FollowReferenceController",
                                                  "FollowRouteController",
                                                  "HIDController",
                                                  "InteractiveController",
                                                  "LoomingController",
                                                  "NaturalDriver",
                                                  "OffroadFollower",
                                                  "SloppyDriverController",
                                                  "SumoController",
                                                  "UDPDriverController"};

// esmini takes the type from the esminiController property, else from the Controller's name; a
// name that is none of its controllers is its default one.
std::optional<ControllerRef> type_of(const xml::Element& controller, const ReadContext& c) {
  ControllerRef ref{c.optional_text(controller, "name").value_or(""), controller.where("name")};
  if (const auto properties = controller.child("Properties"))
    for (const xml::Element& p : properties->children("Property"))
      if (c.text(p, "name") == "esminiController") ref = {c.text(p, "value"), p.where("value")};
  if (std::find(std::begin(kOtherControllers), std::end(kOtherControllers), ref.type) == std::end(kOtherControllers))
    return std::nullopt;
  return ref;
}

void refuse(const ControllerRef& controller, const std::string& entity, const std::string& ego) {
  throw InputError(controller.where,
                   fmt::format("controller {} on '{}' is not supported: only the ego ({}) may have a controller "
                               "other than esmini's DefaultController (emrm drives the ego; the other road users "
                               "play the storyboard open loop)",
                               controller.type, entity, ego.empty() ? "none: the scenario has no vehicle" : ego));
}

void check_actions(const std::vector<Action>& actions, const std::vector<std::string>& actors, const std::string& ego) {
  for (const Action& a : actions) {
    const auto* controller = std::get_if<ControllerAction>(&a.kind);
    if (controller == nullptr || !controller->assigned) continue;
    if (!a.actor.empty()) {
      if (a.actor != ego) refuse(*controller->assigned, a.actor, ego);
      continue;
    }
    for (const std::string& actor : actors)
      if (actor != ego) refuse(*controller->assigned, actor, ego);
  }
}

}  // namespace

std::optional<ControllerRef> read_controller(const xml::Element& holder, const ReadContext& c) {
  if (const auto direct = holder.child("Controller")) return type_of(*direct, c);
  if (const auto ref = holder.child("CatalogReference")) {
    const CatalogEntry entry = resolve_catalog_reference(*ref, c);
    return type_of(entry.element, c.with(*entry.scope));
  }
  return std::nullopt;
}

void check_controllers(const Scenario& scenario) {
  for (const Entity& e : scenario.entities)
    if (e.controller && e.name != scenario.ego) refuse(*e.controller, e.name, scenario.ego);
  check_actions(scenario.storyboard.init, {}, scenario.ego);
  for (const Story& story : scenario.storyboard.stories)
    for (const Act& act : story.acts)
      for (const ManeuverGroup& group : act.groups)
        for (const Maneuver& maneuver : group.maneuvers)
          for (const Event& event : maneuver.events) check_actions(event.actions, group.actors, scenario.ego);
}

}  // namespace detail
}  // namespace emrm::openscenario
