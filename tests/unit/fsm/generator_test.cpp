#include "emrm/fsm/generator.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emrm/fsm/load.hpp"

namespace emrm::fsm {
namespace generator_test {

using Word = std::vector<std::string>;

Generator shipped_emrm() { return load_generator(std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/emrm_fsm.yaml"); }

/// s0 --a--> s1 and s0 --a--> s2 (non-deterministic), s2 --b--> s3; s3 marked.
Generator forked() {
  Generator g("forked");
  g.add_event("a");
  g.add_event("b");
  for (const char* s : {"s0", "s1", "s2", "s3"}) g.add_state(s);
  g.add_transition("s0", "a", "s1");
  g.add_transition("s0", "a", "s2");
  g.add_transition("s2", "b", "s3");
  g.set_initial("s0");
  g.mark("s3");
  return g;
}

TEST(Generator, StepFollowsTheTransitionFunction) {
  const Generator g = shipped_emrm();
  EXPECT_EQ(g.step("S1", "hazard_detected"), "S2");
  EXPECT_EQ(g.step("S2", "high_risk"), "S3");
  EXPECT_EQ(g.step("S4", "timeout_error"), "S5");
  EXPECT_EQ(g.step("S1", "no_risk"), std::nullopt);  // δ is partial
  EXPECT_EQ(g.step("S9", "hazard_detected"), std::nullopt);
  EXPECT_EQ(g.step("S1", "no_such_event"), std::nullopt);
}

TEST(Generator, ExtendedTransitionFollowsWord) {
  const Generator g = shipped_emrm();
  EXPECT_EQ(g.run("S1", {}), "S1");  // δ*(s, ε) = s
  EXPECT_EQ(g.run("S1", {"hazard_detected", "high_risk", "execute_maneuver"}), "S4");
  EXPECT_EQ(
      g.run("S1", {"hazard_detected", "high_risk", "execute_maneuver", "timeout_error", "post_incident_response"}),
      "S6");
  EXPECT_EQ(g.run("S3", {"execute_maneuver", "emrm_done"}), "S1");
  EXPECT_EQ(g.run("S1", {"hazard_detected", "high_risk", "emrm_done"}), std::nullopt);  // S3 has no emrm_done
}

TEST(Generator, HighRiskPrefixIsGeneratedButNotMarked) {
  const Generator g = shipped_emrm();
  EXPECT_TRUE(g.generates({"hazard_detected", "high_risk"}));
  EXPECT_FALSE(g.marks({"hazard_detected", "high_risk"}));
  EXPECT_TRUE(g.generates({"hazard_detected", "no_risk"}));
  EXPECT_TRUE(g.marks({"hazard_detected", "no_risk"}));
  const Word loss{"hazard_detected", "high_risk", "execute_maneuver", "timeout_error", "post_incident_response"};
  EXPECT_TRUE(g.marks(loss));  // S6 is marked: the loss was responded to
  EXPECT_TRUE(g.marks({}));    // ε reaches S1, which is marked
}

TEST(Generator, WordsOutsideTheLanguageAreRejected) {
  const Generator g = shipped_emrm();
  EXPECT_FALSE(g.generates({"no_risk"}));
  EXPECT_FALSE(g.generates({"hazard_detected", "safe"}));
  EXPECT_FALSE(g.generates({"hazard_detected", "unknown_event"}));
  EXPECT_FALSE(g.marks({"hazard_detected", "safe"}));
}

TEST(Generator, KeepsTheShippedMachineInFileOrder) {
  const Generator g = shipped_emrm();
  ASSERT_EQ(g.states().size(), 6U);
  EXPECT_EQ(g.states().front().id, "S1");
  EXPECT_EQ(g.states().back().id, "S6");
  EXPECT_EQ(g.states().front().description, "normal driving (no obstacle present)");
  ASSERT_EQ(g.events().size(), 8U);
  EXPECT_EQ(g.events()[3].id, "execute_maneuver");
  ASSERT_EQ(g.transitions().size(), 8U);
  EXPECT_EQ(g.transitions()[5].from, "S4");
  EXPECT_EQ(g.transitions()[5].event, "timeout_error");
  EXPECT_EQ(g.transitions()[5].to, "S5");
  EXPECT_EQ(g.initial(), "S1");
  EXPECT_EQ(g.marked_states(), (std::vector<std::string>{"S1", "S6"}));
  EXPECT_TRUE(g.is_deterministic());
}

TEST(Generator, MembershipQueriesAnswerByName) {
  const Generator g = shipped_emrm();
  EXPECT_TRUE(g.has_state("S5"));
  EXPECT_FALSE(g.has_state("S7"));
  EXPECT_TRUE(g.has_event("safe"));
  EXPECT_FALSE(g.has_event("S1"));
  EXPECT_TRUE(g.has_transition("S6", "safe", "S1"));
  EXPECT_FALSE(g.has_transition("S6", "safe", "S2"));
  EXPECT_FALSE(g.has_transition("S1", "safe", "S1"));
  EXPECT_TRUE(g.is_marked("S6"));
  EXPECT_FALSE(g.is_marked("S5"));
  EXPECT_FALSE(g.is_marked("nope"));
}

TEST(Generator, IndexedStepAgreesWithNamedStep) {
  const Generator g = shipped_emrm();
  int defined = 0;
  for (int s = 0; s < g.state_count(); ++s)
    for (int e = 0; e < g.event_count(); ++e) {
      const auto& state = g.states()[static_cast<std::size_t>(s)].id;
      const auto& event = g.events()[static_cast<std::size_t>(e)].id;
      const int next = g.step_index(s, e);
      const auto named = g.step(state, event);
      ASSERT_EQ(next == Generator::kNone, !named.has_value()) << state << " " << event;
      if (next == Generator::kNone) continue;
      ++defined;
      EXPECT_EQ(g.states()[static_cast<std::size_t>(next)].id, *named);
      const int t = g.transition_index(s, e);
      ASSERT_NE(t, Generator::kNone);
      EXPECT_EQ(g.transitions()[static_cast<std::size_t>(t)].from, state);
      EXPECT_EQ(g.transitions()[static_cast<std::size_t>(t)].event, event);
    }
  EXPECT_EQ(defined, 8);  // one per transition of a deterministic machine
  EXPECT_EQ(g.state_index("S3"), 2);
  EXPECT_EQ(g.event_index("safe"), 7);
  EXPECT_EQ(g.state_index("S0"), Generator::kNone);
}

TEST(Generator, AddingAnEventLaterKeepsExistingTransitions) {
  Generator g("late");
  g.add_event("a");
  g.add_state("p");
  g.add_state("q");
  g.add_transition("p", "a", "q");
  g.add_event("b");  // the δ table is laid out again
  g.add_transition("q", "b", "p");
  g.set_initial("p");
  EXPECT_EQ(g.step("p", "a"), "q");
  EXPECT_EQ(g.step("q", "b"), "p");
  EXPECT_EQ(g.step("p", "b"), std::nullopt);
  EXPECT_EQ(g.run("p", {"a", "b", "a"}), "q");
}

TEST(Generator, RepresentsANonDeterministicChoice) {
  const Generator g = forked();
  EXPECT_FALSE(g.is_deterministic());
  EXPECT_EQ(g.transitions().size(), 3U);
  EXPECT_EQ(g.step("s0", "a"), "s1");  // δ picks the first-declared target
  EXPECT_TRUE(g.has_transition("s0", "a", "s2"));
  // Membership follows every path: "a b" is generated (through s2) although δ's path dies at s1.
  EXPECT_TRUE(g.generates({"a", "b"}));
  EXPECT_TRUE(g.marks({"a", "b"}));
  EXPECT_FALSE(g.marks({"a"}));
  EXPECT_EQ(g.run("s0", {"a", "b"}), std::nullopt);
}

TEST(Generator, WithoutInitialStateGeneratesNothing) {
  Generator g("empty");
  g.add_state("s");
  g.mark("s");
  EXPECT_EQ(g.initial(), std::nullopt);
  EXPECT_EQ(g.initial_index(), Generator::kNone);
  EXPECT_FALSE(g.generates({}));
  EXPECT_FALSE(g.marks({}));
}

TEST(Generator, BuildingRejectsDuplicatesAndUnknownNames) {
  Generator g("bad");
  g.add_state("s");
  g.add_event("e");
  EXPECT_THROW(g.add_state("s"), Error);
  EXPECT_THROW(g.add_state(""), Error);
  EXPECT_THROW(g.add_event("e"), Error);
  EXPECT_THROW(g.add_transition("s", "e", "t"), Error);
  EXPECT_THROW(g.add_transition("t", "e", "s"), Error);
  EXPECT_THROW(g.add_transition("s", "f", "s"), Error);
  g.add_transition("s", "e", "s");
  EXPECT_THROW(g.add_transition("s", "e", "s"), Error);  // identical transition
  EXPECT_THROW(g.set_initial("t"), Error);
  EXPECT_THROW(g.mark("t"), Error);
}

}  // namespace generator_test
}  // namespace emrm::fsm
