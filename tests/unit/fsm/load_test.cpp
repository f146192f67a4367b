#include "emrm/fsm/load.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace emrm::fsm {
namespace load_test {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::string example(const std::string& name) { return std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/" + name; }

/// Parses `text` as "fsm.yaml" and returns the InputError's message ("" if it loaded).
std::string load_error(const std::string& text) {
  try {
    (void)parse_generator(text, "fsm.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A valid two-state machine; each error test breaks one line of it.
const std::string kValid =
    "name: door\n"                                  // 1
    "states:\n"                                     // 2
    "  - {id: closed, description: door closed}\n"  // 3
    "  - open\n"                                    // 4
    "events:\n"                                     // 5
    "  - {id: push}\n"                              // 6
    "  - pull\n"                                    // 7
    "initial: closed\n"                             // 8
    "marked: [closed]\n"                            // 9
    "transitions:\n"                                // 10
    "  - {from: closed, event: push, to: open}\n"   // 11
    "  - {from: open, event: pull, to: closed}\n";  // 12

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(Load, ValidFileBuildsTheGenerator) {
  const Generator g = parse_generator(kValid, "fsm.yaml");
  EXPECT_EQ(g.name(), "door");
  ASSERT_EQ(g.states().size(), 2U);
  EXPECT_EQ(g.states()[0].description, "door closed");
  EXPECT_EQ(g.states()[1].id, "open");  // a plain string item
  EXPECT_EQ(g.states()[1].where.str(), "fsm.yaml:4:5");
  EXPECT_EQ(g.events()[1].id, "pull");
  EXPECT_EQ(g.initial(), "closed");
  EXPECT_THAT(g.marked_states(), ElementsAre("closed"));
  EXPECT_EQ(g.run("closed", {"push", "pull"}), "closed");
  EXPECT_EQ(g.transitions()[1].where.str(), "fsm.yaml:12:5");
}

TEST(Load, ShippedEmrmFsmIsTheDesignedMachine) {
  const Generator g = load_generator(example("emrm_fsm.yaml"));
  EXPECT_EQ(g.name(), "emrm");
  EXPECT_EQ(g.states().size(), 6U);
  EXPECT_EQ(g.events().size(), 8U);
  EXPECT_EQ(g.initial(), "S1");
  EXPECT_THAT(g.marked_states(), ElementsAre("S1", "S6"));
  ASSERT_EQ(g.transitions().size(), 8U);
  EXPECT_TRUE(g.has_transition("S1", "hazard_detected", "S2"));
  EXPECT_TRUE(g.has_transition("S2", "no_risk", "S1"));
  EXPECT_TRUE(g.has_transition("S2", "high_risk", "S3"));
  EXPECT_TRUE(g.has_transition("S3", "execute_maneuver", "S4"));
  EXPECT_TRUE(g.has_transition("S4", "emrm_done", "S1"));
  EXPECT_TRUE(g.has_transition("S4", "timeout_error", "S5"));
  EXPECT_TRUE(g.has_transition("S5", "post_incident_response", "S6"));
  EXPECT_TRUE(g.has_transition("S6", "safe", "S1"));
  for (const auto& s : g.states()) EXPECT_FALSE(s.description.empty()) << s.id;
}

TEST(Load, ShippedLossEvaluationFsmHasTheStrategiesAsMarkedStates) {
  const Generator g = load_generator(example("loss_evaluation_fsm.yaml"));
  EXPECT_THAT(g.marked_states(), ElementsAre("emergency_stop", "dodge", "drift_to_avoid", "drift_to_accident"));
  EXPECT_EQ(g.events().size(), 12U);
  EXPECT_EQ(g.transitions().size(), 27U);
}

TEST(Load, NonDeterministicPairIsNotAnInputError) {
  const Generator g = parse_generator(kValid + "  - {from: closed, event: push, to: closed}\n", "fsm.yaml");
  EXPECT_FALSE(g.is_deterministic());
  EXPECT_EQ(g.transitions().size(), 3U);
}

TEST(Load, MalformedYamlNamesLineAndColumn) {
  const auto message = load_error(replace(kValid, "  - {id: push}\n", "  - {id: push}}\n"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:6:15"));  // the stray '}'
  EXPECT_THAT(load_error(replace(kValid, "name: door", "name: door: x")), HasSubstr("fsm.yaml:1:11"));
  EXPECT_THAT(message, HasSubstr("malformed YAML"));
}

TEST(Load, WrongTypeNamesTheValueAndWhatWasExpected) {
  const auto message = load_error(replace(kValid, "marked: [closed]", "marked: closed"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:9:9"));
  EXPECT_THAT(message, HasSubstr("expected a list"));
  const auto nested = load_error(replace(kValid, "  - {id: push}", "  - [push]"));
  EXPECT_THAT(nested, HasSubstr("fsm.yaml:6:5"));
  EXPECT_THAT(nested, HasSubstr("expected an id or a mapping"));
}

TEST(Load, MissingFieldIsReportedAtItsMapping) {
  const auto message = load_error(replace(kValid, "initial: closed\n", ""));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:1:1"));
  EXPECT_THAT(message, HasSubstr("missing required field 'initial'"));
  const auto in_transition =
      load_error(replace(kValid, "{from: open, event: pull, to: closed}", "{from: open, event: pull}"));
  EXPECT_THAT(in_transition, HasSubstr("fsm.yaml:12:5"));
  EXPECT_THAT(in_transition, HasSubstr("missing required field 'to'"));
}

TEST(Load, UnknownFieldIsRejected) {
  const auto message = load_error(replace(kValid, "{id: push}", "{id: push, colour: red}"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:6:16"));
  EXPECT_THAT(message, HasSubstr("unknown field 'colour'"));
  const auto top = load_error(kValid + "start: closed\n");
  EXPECT_THAT(top, HasSubstr("fsm.yaml:13:1"));
  EXPECT_THAT(top, HasSubstr("unknown field 'start'"));
}

TEST(Load, DuplicateStateIdNamesBothPlaces) {
  const auto message = load_error(replace(kValid, "  - open\n", "  - closed\n"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:4:5"));
  EXPECT_THAT(message, HasSubstr("duplicate state id 'closed'"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:3:5"));
}

TEST(Load, DuplicateEventIdIsRejected) {
  const auto message = load_error(replace(kValid, "  - pull\n", "  - push\n"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:7:5"));
  EXPECT_THAT(message, HasSubstr("duplicate event id 'push'"));
}

TEST(Load, UnknownEventInTransitionListsTheDeclaredEvents) {
  const auto message = load_error(replace(kValid, "event: pull", "event: slam"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:12:25"));
  EXPECT_THAT(message, HasSubstr("transition event 'slam' is not a declared event; expected one of: push, pull"));
}

TEST(Load, UnknownStateInTransitionIsRejected) {
  const auto target = load_error(replace(kValid, "to: open}", "to: ajar}"));
  EXPECT_THAT(target, HasSubstr("fsm.yaml:11:37"));
  EXPECT_THAT(target, HasSubstr("transition target 'ajar' is not a declared state"));
  const auto source = load_error(replace(kValid, "{from: open", "{from: ajar"));
  EXPECT_THAT(source, HasSubstr("fsm.yaml:12:12"));
  EXPECT_THAT(source, HasSubstr("transition source 'ajar'"));
}

TEST(Load, UnknownInitialOrMarkedStateIsRejected) {
  EXPECT_THAT(load_error(replace(kValid, "initial: closed", "initial: shut")),
              HasSubstr("fsm.yaml:8:10: error: initial state 'shut' is not a declared state"));
  EXPECT_THAT(load_error(replace(kValid, "marked: [closed]", "marked: [closed, shut]")),
              HasSubstr("fsm.yaml:9:18: error: marked state 'shut'"));
  EXPECT_THAT(load_error(replace(kValid, "marked: [closed]", "marked: [closed, closed]")),
              HasSubstr("fsm.yaml:9:18: error: state 'closed' is marked twice"));
}

TEST(Load, ExactDuplicateTransitionIsRejected) {
  const auto message = load_error(kValid + "  - {from: open, event: pull, to: closed}\n");
  EXPECT_THAT(message, HasSubstr("fsm.yaml:13:5"));
  EXPECT_THAT(message, HasSubstr("duplicate transition open --pull--> closed (first at fsm.yaml:12:5)"));
}

TEST(Load, IdsThatCannotBeWrittenInAWordAreRejected) {
  const auto message = load_error(replace(kValid, "  - pull\n", "  - \"pull hard\"\n"));
  EXPECT_THAT(message, HasSubstr("fsm.yaml:7:5"));
  EXPECT_THAT(message, HasSubstr("invalid event id 'pull hard'"));
}

TEST(Load, EmptyOrMissingFileIsAnInputError) {
  EXPECT_THAT(load_error(""), HasSubstr("fsm.yaml:1:1"));
  EXPECT_THROW((void)load_generator("/no/such/dir/fsm.yaml"), InputError);
}

TEST(Load, TracesSkipCommentsAndBlankLines) {
  const auto traces = parse_traces(
      "# campaign traces\n"
      "hazard_detected no_risk\n"
      "\n"
      "   hazard_detected  high_risk   # escalated\n"
      "#\n",
      "t.txt");
  ASSERT_EQ(traces.size(), 2U);
  EXPECT_THAT(traces[0].events, ElementsAre("hazard_detected", "no_risk"));
  EXPECT_EQ(traces[0].where.str(), "t.txt:2:1");
  EXPECT_THAT(traces[1].events, ElementsAre("hazard_detected", "high_risk"));
  EXPECT_EQ(traces[1].where.line, 4);
  EXPECT_THROW((void)load_traces("/no/such/traces.txt"), InputError);
}

}  // namespace load_test
}  // namespace emrm::fsm
