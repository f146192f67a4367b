// load_openscenario (reader.hpp): the document validated, then read from its parameters to its
// storyboard; the parts in read_*.cpp.

#include "emrm/openscenario/reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "emrm/opendrive/road_network.hpp"
#include "emrm/openscenario/supported.hpp"
#include "read_context.hpp"

namespace emrm::openscenario {
namespace {

using detail::ReadContext;

struct Document {
  xml::Document document;
  xml::Element root;
  int rev_minor = 3;
};

Document open(const std::filesystem::path& file) {
  xml::Document document = xml::Document::load(file);
  xml::validate(document, xml::Schema::kOpenScenario);
  const xml::Element root = document.root();
  const xml::Element header = root.required_child("FileHeader");
  const int rev_minor = static_cast<int>(header.number("revMinor"));
  if (root.child("ParameterValueDistribution"))
    root.fail("this is a ParameterValueDistribution file, not a scenario (load_parameter_distribution reads it)");
  if (root.child("Catalog")) root.fail("this is a catalog file, not a scenario");
  return {document, root, rev_minor};
}

// The storyboard's element names by type, for the StoryboardElementStateConditions to refer to.
std::map<ElementType, std::set<std::string>> element_names(const xml::Element& storyboard) {
  std::map<ElementType, std::set<std::string>> names;
  for (const xml::Element& story : storyboard.children("Story")) {
    names[ElementType::kStory].insert(story.attribute("name").value_or(""));
    for (const xml::Element& act : story.children("Act")) {
      names[ElementType::kAct].insert(act.attribute("name").value_or(""));
      for (const xml::Element& group : act.children("ManeuverGroup")) {
        names[ElementType::kManeuverGroup].insert(group.attribute("name").value_or(""));
        for (const xml::Element& maneuver : group.children("Maneuver")) {
          names[ElementType::kManeuver].insert(maneuver.attribute("name").value_or(""));
          for (const xml::Element& event : maneuver.children("Event")) {
            names[ElementType::kEvent].insert(event.attribute("name").value_or(""));
            for (const xml::Element& action : event.children("Action"))
              names[ElementType::kAction].insert(action.attribute("name").value_or(""));
          }
        }
      }
    }
  }
  return names;
}

// A start or stop trigger: absent when not written or written without a ConditionGroup. esmini
// reads an empty StartTrigger as true (the element starts with its parent, as without one) and an
// empty StopTrigger as false (never), which is what an absent one does (esmini's drive_when_close).
std::optional<Trigger> read_trigger(const xml::Element& parent, std::string_view tag, const ReadContext& c) {
  const auto trigger = parent.child(tag);
  if (!trigger || trigger->children("ConditionGroup").empty()) return std::nullopt;
  return detail::read_trigger(*trigger, c);
}

// A GlobalAction: an EnvironmentAction (nothing moves by it) or a ParameterAction on a global
// parameter.
Action read_global_action(const xml::Element& global_action, const ReadContext& c) {
  const xml::Element global = c.chosen(global_action, "GlobalAction");
  if (global.name() != "ParameterAction") return Action{"", "", EnvironmentAction{}, global.where()};
  ParameterAction p;
  p.parameter = global.required("parameterRef");
  if (c.scope().find(p.parameter) == nullptr)
    global.fail("parameterRef", fmt::format("parameterRef: no parameter '{}' is declared", p.parameter));
  if (const auto set = global.child("SetAction")) {
    p.set = c.text(*set, "value");
  } else {
    const xml::Element rule = global.required_child("ModifyAction").required_child("Rule");
    if (const auto add = rule.child("AddValue")) {
      p.add = c.number(*add, "value", "", -1e12, 1e12);
    } else {
      p.multiply = c.number(rule.required_child("MultiplyByValue"), "value", "", -1e12, 1e12);
    }
  }
  return Action{"", "", p, global.where()};
}

int max_executions(const xml::Element& e, const ReadContext& c) {
  if (!e.attribute("maximumExecutionCount")) return 1;
  return c.integer(e, "maximumExecutionCount", 1, 1000000);
}

Maneuver read_maneuver(const xml::Element& m, const std::vector<std::string>& actors, const ReadContext& outer) {
  ParameterScope scope(&outer.scope());
  declare_parameters(m, scope, outer, {});
  const ReadContext c = outer.with(scope);
  Maneuver maneuver{c.text(m, "name"), {}};
  for (const xml::Element& e : m.children("Event")) {
    Event event;
    event.name = c.text(e, "name");
    event.priority = static_cast<Priority>(c.choice(e, "priority", {"overwrite", "override", "skip", "parallel"}));
    event.max_executions = max_executions(e, c);
    for (const xml::Element& a : e.children("Action")) {
      const xml::Element kind = c.chosen(a, "Action");
      if (kind.name() == "GlobalAction") {
        event.actions.push_back(read_global_action(kind, c));
        event.actions.back().name = c.text(a, "name");
        continue;
      }
      if (actors.empty())
        a.fail(fmt::format("action '{}' is a private action in a maneuver group without actors", c.text(a, "name")));
      event.actions.push_back(detail::read_private_action(kind, "", c));
    }
    event.start = read_trigger(e, "StartTrigger", c);
    maneuver.events.push_back(std::move(event));
  }
  return maneuver;
}

Storyboard read_storyboard(const xml::Element& board, ReadContext& c) {
  Storyboard out;
  auto names = element_names(board);
  c.elements_ = &names;
  const xml::Element init = board.required_child("Init");
  for (const xml::Element& actions : init.children("Actions"))
    for (const xml::Element& child : actions.children()) {
      require_supported("InitActions", child.name(), child.where());
      if (child.name() == "GlobalAction") {
        out.init.push_back(read_global_action(child, c));
        continue;
      }
      const std::string actor = c.entity_ref(child, "entityRef");
      for (const xml::Element& pa : child.children("PrivateAction"))
        out.init.push_back(detail::read_private_action(pa, actor, c));
    }
  for (const xml::Element& s : board.children("Story")) {
    ParameterScope story_scope(&c.scope());
    declare_parameters(s, story_scope, c, {});
    const ReadContext sc = c.with(story_scope);
    Story story{sc.text(s, "name"), {}};
    for (const xml::Element& a : s.children("Act")) {
      Act act;
      act.name = sc.text(a, "name");
      for (const xml::Element& g : a.children("ManeuverGroup")) {
        ManeuverGroup group;
        group.name = sc.text(g, "name");
        group.max_executions = max_executions(g, sc);
        const xml::Element actors = g.required_child("Actors");
        if (sc.boolean(actors, "selectTriggeringEntities", false))
          actors.fail("selectTriggeringEntities", "selectTriggeringEntities: true is not supported (name the actors)");
        for (const xml::Element& ref : actors.children("EntityRef"))
          group.actors.push_back(sc.entity_ref(ref, "entityRef"));
        for (const xml::Element& m : g.children()) {
          if (m.name() == "Maneuver") {
            group.maneuvers.push_back(read_maneuver(m, group.actors, sc));
          } else if (m.name() == "CatalogReference") {
            const detail::CatalogEntry entry = detail::resolve_catalog_reference(m, sc);
            if (entry.element.name() != "Maneuver")
              m.fail(fmt::format("the catalog entry is a {}, not a Maneuver", entry.element.name()));
            group.maneuvers.push_back(read_maneuver(entry.element, group.actors, sc.with(*entry.scope)));
          }
        }
        act.groups.push_back(std::move(group));
      }
      act.start = read_trigger(a, "StartTrigger", sc);
      act.stop = read_trigger(a, "StopTrigger", sc);
      story.acts.push_back(std::move(act));
    }
    out.stories.push_back(std::move(story));
  }
  out.stop = read_trigger(board, "StopTrigger", c);
  c.elements_ = nullptr;
  return out;
}

void declare_globals(const Document& d, ParameterScope& scope, const detail::Catalogs& catalogs,
                     const std::filesystem::path& dir, const ParameterOverrides& overrides) {
  std::set<std::string> none;
  detail::Catalogs unused = catalogs;
  const ReadContext c(scope, dir, unused, none, nullptr);
  detail::declare_parameters(d.root, scope, c, overrides);
  for (const auto& [name, value] : overrides)
    if (scope.find(name) == nullptr)
      throw InputError({d.document.file(), 0, 0},
                       fmt::format("parameter override '{}': the scenario declares no parameter of that name", name));
}

}  // namespace

std::vector<Parameter> declared_parameters(const std::filesystem::path& file) {
  const Document d = open(file);
  ParameterScope scope;
  declare_globals(d, scope, {}, file.parent_path(), {});
  return scope.declared();
}

std::vector<std::string> Scenario::element_names() const {
  std::vector<std::string> out;
  for (const Story& story : storyboard.stories) {
    out.push_back(story.name);
    for (const Act& act : story.acts) {
      out.push_back(act.name);
      for (const ManeuverGroup& group : act.groups) {
        out.push_back(group.name);
        for (const Maneuver& maneuver : group.maneuvers) {
          out.push_back(maneuver.name);
          for (const Event& event : maneuver.events) {
            out.push_back(event.name);
            for (const Action& action : event.actions) out.push_back(action.name);
          }
        }
      }
    }
  }
  return out;
}

Scenario load_openscenario(const std::filesystem::path& file, const ReadOptions& options) {
  const ParameterOverrides& overrides = options.overrides;
  const Document d = open(file);
  const std::filesystem::path dir = file.parent_path();
  Scenario scenario;
  scenario.file = file;
  scenario.overrides = overrides;
  ParameterScope scope;
  detail::Catalogs catalogs;
  declare_globals(d, scope, catalogs, dir, overrides);
  scenario.parameters = scope.declared();

  std::set<std::string> names;
  ReadContext c(scope, dir, catalogs, names, nullptr);
  c.rev_minor = d.rev_minor;
  if (const auto locations = d.root.child("CatalogLocations"))
    for (const xml::Element& location : locations->children())
      catalogs.directories[std::string(location.name())] = dir / c.text(location.required_child("Directory"), "path");

  if (const auto network = d.root.child("RoadNetwork"))
    if (const auto logic = network->child("LogicFile")) {
      const std::filesystem::path road_file = dir / c.text(*logic, "filepath");
      scenario.network = std::make_shared<const opendrive::RoadNetwork>(opendrive::load_opendrive(road_file));
      scenario.roads = road_access(scenario.network);
    }
  ReadContext rc(scope, dir, catalogs, names, scenario.roads.get());
  rc.rev_minor = d.rev_minor;
  rc.global_ = &scope;
  rc.uses_ = &scenario.uses;

  const xml::Element entities = d.root.required_child("Entities");
  for (const xml::Element& object : entities.children()) {
    if (object.name() != "ScenarioObject")
      object.fail(fmt::format("{} is not supported in Entities (supported: ScenarioObject)", object.name()));
    const std::string name = rc.text(object, "name");
    if (!names.insert(name).second) object.fail("name", fmt::format("name: entity '{}' is declared twice", name));
  }
  for (const xml::Element& object : entities.children("ScenarioObject"))
    scenario.entities.push_back(detail::read_entity(object, rc));
  if (!options.ego.empty()) {
    if (scenario.find_entity(options.ego) == nullptr) {
      std::vector<std::string> all;
      for (const Entity& e : scenario.entities) all.push_back(e.name);
      throw InputError(entities.where(), fmt::format("the ego '{}' is no entity of the scenario (it has {})",
                                                     options.ego, fmt::join(all, ", ")));
    }
    scenario.ego = options.ego;
  } else if (const Entity* ego = default_ego(scenario.entities)) {
    scenario.ego = ego->name;
  }
  scenario.storyboard = read_storyboard(d.root.required_child("Storyboard"), rc);
  detail::check_controllers(scenario);
  return scenario;
}

}  // namespace emrm::openscenario
