// Elements outside the supported subset are InputErrors at the element that name the supported
// ones; docs/import.md lists exactly the code's table.

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "emrm/openscenario/reader.hpp"
#include "emrm/openscenario/supported.hpp"
#include "input_error.hpp"
#include "openscenario/xosc_builder.hpp"

namespace emrm::openscenario {
namespace {

using namespace test;

// The error of a scenario whose first event's action is `action`, and where `marker` is in the text.
void expect_unsupported(const std::string& name, const XoscParts& parts, const std::string& marker,
                        const std::string& expected) {
  const std::string text = xosc(parts);
  const auto file = write_scenario(name, parts);
  const InputError e = emrm::testing::input_error_of([&] { (void)load_openscenario(file); }, text);
  const std::size_t at = text.find(marker);
  ASSERT_NE(at, std::string::npos);
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + 1;
  const int column = static_cast<int>(at - (text.rfind('\n', at) + 1)) + 1;
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
  EXPECT_NE(e.message().find(expected), std::string::npos) << e.what();
}

XoscParts with_event_action(const std::string& action) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  parts.acts = act("Ego", fmt::format(R"(<Event name="e" priority="override"><Action name="a">{}</Action>
      <StartTrigger><ConditionGroup>{}</ConditionGroup></StartTrigger></Event>)",
                                      action, time_condition(1.0)));
  return parts;
}

XoscParts with_condition(const std::string& condition_text) {
  XoscParts parts;
  parts.entities = vehicle("Ego");
  parts.init = init_at("Ego", 0, 0, 0, 10);
  parts.acts = act("Ego", event("e", speed("0"), trigger("StartTrigger", condition_text)));
  return parts;
}

TEST(Unsupported, AGlobalActionOtherThanTheEnvironment) {
  expect_unsupported(
      "global",
      with_event_action(
          R"(<GlobalAction><EntityAction entityRef="Ego"><DeleteEntityAction/></EntityAction></GlobalAction>)"),
      "<EntityAction", "EntityAction is not supported in GlobalAction (supported: EnvironmentAction, ParameterAction)");
  expect_unsupported(
      "user_defined",
      with_event_action(
          R"(<UserDefinedAction><CustomCommandAction type="x">y</CustomCommandAction></UserDefinedAction>)"),
      "<UserDefinedAction", "UserDefinedAction is not supported in Action (supported: PrivateAction, GlobalAction)");
}

TEST(Unsupported, APrivateActionOutsideTheSubset) {
  expect_unsupported("trailer",
                     with_event_action(R"(<PrivateAction><TrailerAction><DisconnectTrailerAction/></TrailerAction>
                         </PrivateAction>)"),
                     "<TrailerAction",
                     "TrailerAction is not supported in PrivateAction (supported: LongitudinalAction, LateralAction, "
                     "TeleportAction, RoutingAction, ControllerAction, ActivateControllerAction, VisibilityAction, "
                     "AppearanceAction)");
  // Visibility changes nothing in the motion, unless other traffic cannot see the entity.
  const auto visible = play(load_openscenario(write_scenario(
                                "visibility", with_event_action(R"(<PrivateAction><VisibilityAction graphics="false"
                                    traffic="true" sensors="false"/></PrivateAction>)"))),
                            {.duration_s = 2.0});
  EXPECT_NEAR(visible.at("Ego").back().x_m, 20.0, 1e-9);
  expect_unsupported("invisible_to_traffic", with_event_action(R"(<PrivateAction><VisibilityAction graphics="true"
                         traffic="false" sensors="true"/></PrivateAction>)"),
                     "traffic=", "traffic: false is not supported");
  expect_unsupported(
      "acquire",
      with_event_action("<PrivateAction><RoutingAction><AcquirePositionAction>" + world_position(1, 2, 0) +
                        "</AcquirePositionAction></RoutingAction></PrivateAction>"),
      "<AcquirePositionAction",
      "AcquirePositionAction is not supported in RoutingAction (supported: FollowTrajectoryAction)");
  expect_unsupported("distance_action",
                     with_event_action(R"(<PrivateAction><LongitudinalAction><LongitudinalDistanceAction
      entityRef="Ego" freespace="false" continuous="false" distance="5"/></LongitudinalAction></PrivateAction>)"),
                     "<LongitudinalDistanceAction",
                     "LongitudinalDistanceAction is not supported in LongitudinalAction (supported: SpeedAction)");
}

TEST(Unsupported, OnlyTheEgoMayHaveAControllerOtherThanEsminisDefault) {
  const auto assign = [](const std::string& controller) {
    return fmt::format(R"(<PrivateAction><ControllerAction><AssignControllerAction><Controller name="c">
        <Properties><Property name="esminiController" value="{}"/></Properties></Controller>
        </AssignControllerAction></ControllerAction></PrivateAction>)",
                       controller);
  };
  // The default controller is what moves the entity anyway: the action has no effect.
  const XoscParts accepted = with_event_action(assign("DefaultController"));
  const auto played = play(load_openscenario(write_scenario("default_controller", accepted)), {.duration_s = 2.0});
  EXPECT_NEAR(played.at("Ego").back().x_m, 20.0, 1e-9);
  // On the ego (Ego by default) another controller is accepted: emrm drives the ego; until then it
  // follows its storyboard.
  const auto ego_file = write_scenario("ego_interactive", with_event_action(assign("InteractiveController")));
  const Scenario ego_scenario = load_openscenario(ego_file);
  EXPECT_EQ(ego_scenario.ego, "Ego");
  EXPECT_NEAR(play(ego_scenario, {.duration_s = 2.0}).at("Ego").back().x_m, 20.0, 1e-9);
  // On another entity it is refused at the controller's type, naming the entity.
  XoscParts other = with_event_action(assign("InteractiveController"));
  other.entities = vehicle("Lead") + vehicle("Ego");
  other.init += init_at("Lead", 30, 0, 0, 10);
  other.acts = act("Lead", fmt::format(R"(<Event name="e" priority="override"><Action name="a">{}</Action>
      <StartTrigger><ConditionGroup>{}</ConditionGroup></StartTrigger></Event>)",
                                       assign("InteractiveController"), time_condition(1.0)));
  expect_unsupported("other_interactive", other, "value=\"InteractiveController\"",
                     "controller InteractiveController on 'Lead' is not supported: only the ego (Ego)");
  // An ObjectController the same way; naming the other entity the ego accepts it.
  XoscParts object = with_condition(time_condition(1.0));
  object.entities =
      vehicle("Ego") + R"(<ScenarioObject name="Lead"><Vehicle name="Lead" vehicleCategory="car">)" + vehicle_body() +
      R"(</Vehicle><ObjectController><Controller name="ACCController"><Properties/></Controller></ObjectController>
                    </ScenarioObject>)";
  object.init += init_at("Lead", 30, 0, 0, 10);
  expect_unsupported("object_controller", object, "name=\"ACCController\"",
                     "controller ACCController on 'Lead' is not supported");
  const auto object_file = write_scenario("object_controller_lead", object);
  EXPECT_EQ(load_openscenario(object_file, {.overrides = {}, .ego = "Lead"}).ego, "Lead");
  const InputError e = emrm::testing::input_error_of(
      [&] { (void)load_openscenario(object_file, {.overrides = {}, .ego = "Nobody"}); }, xosc(object));
  EXPECT_NE(e.message().find("the ego 'Nobody' is no entity of the scenario (it has Ego, Lead)"), std::string::npos)
      << e.what();
}

TEST(Unsupported, ConditionsOutsideTheSubset) {
  expect_unsupported("standstill", with_condition(entity_condition("Ego", R"(<StandStillCondition duration="1"/>)")),
                     "<StandStillCondition",
                     "StandStillCondition is not supported in EntityCondition (supported: TimeHeadwayCondition");
  expect_unsupported("time_of_day", with_condition(condition(R"(<ByValueCondition><TimeOfDayCondition rule="greaterThan"
                         dateTime="2026-01-01T12:00:00"/></ByValueCondition>)")),
                     "<TimeOfDayCondition",
                     "TimeOfDayCondition is not supported in ByValueCondition (supported: SimulationTimeCondition, "
                     "StoryboardElementStateCondition, ParameterCondition)");
  expect_unsupported(
      "parameter_condition",
      with_condition(condition(
          R"(<ByValueCondition><ParameterCondition parameterRef="x" value="1" rule="equalTo"/></ByValueCondition>)")),
      "parameterRef=", "parameterRef: no parameter 'x' is declared");
}

TEST(Unsupported, AReferenceToNothingIsAnErrorAtTheReference) {
  expect_unsupported("no_entity",
                     with_condition(entity_condition("Ghost", R"(<SpeedCondition value="1" rule="greaterThan"/>)")),
                     "entityRef=\"Ghost\"", "no entity named 'Ghost' (entities: Ego)");
  expect_unsupported(
      "no_event",
      with_condition(condition(R"(<ByValueCondition><StoryboardElementStateCondition storyboardElementType="event"
                         storyboardElementRef="nope" state="endTransition"/></ByValueCondition>)")),
      "storyboardElementRef=\"nope\"", "the storyboard has no event named 'nope'");
}

TEST(Unsupported, TheDocumentationListsExactlyTheSupportedTable) {
  std::ifstream in(std::string(EMRM_SOURCE_DIR) + "/docs/import.md");
  ASSERT_TRUE(in) << "docs/import.md";
  std::set<std::pair<std::string, std::string>> documented;
  std::string line;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (line.starts_with("| choice | element |")) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (!line.starts_with("|")) break;
    if (line.starts_with("|---")) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    std::string cell;
    while (std::getline(row, cell, '|')) {
      const auto a = cell.find_first_not_of(" `"), b = cell.find_last_not_of(" `");
      cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
    }
    ASSERT_GE(cells.size(), 2U) << line;
    documented.emplace(cells[0], cells[1]);
  }
  std::set<std::pair<std::string, std::string>> coded;
  for (const auto& e : supported_elements()) coded.emplace(std::string(e.choice), std::string(e.element));
  EXPECT_EQ(documented, coded);
}

}  // namespace
}  // namespace emrm::openscenario
