#include "emrm/fsm/operations.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "emrm/fsm/load.hpp"

namespace emrm::fsm {
namespace operations_test {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using Word = std::vector<std::string>;

std::string example(const std::string& name) { return std::string(EMRM_SOURCE_DIR) + "/examples/tjunction/" + name; }

struct Edge {
  std::string from, event, to;
};

/// A machine from lists, with events in the given order.
Generator make(const std::string& name, const std::vector<std::string>& states, const std::vector<std::string>& events,
               const std::vector<Edge>& edges, const std::string& initial, const std::vector<std::string>& marked) {
  Generator g(name);
  for (const auto& e : events) g.add_event(e);
  for (const auto& s : states) g.add_state(s);
  for (const auto& t : edges) g.add_transition(t.from, t.event, t.to);
  if (!initial.empty()) g.set_initial(initial);
  for (const auto& m : marked) g.mark(m);
  return g;
}

std::set<std::tuple<std::string, std::string, std::string>> transition_set(const Generator& g) {
  std::set<std::tuple<std::string, std::string, std::string>> out;
  for (const auto& t : g.transitions()) out.emplace(t.from, t.event, t.to);
  return out;
}

std::vector<std::string> state_ids(const Generator& g) {
  std::vector<std::string> out;
  for (const auto& s : g.states()) out.push_back(s.id);
  return out;
}

// ---- membership and enumeration ------------------------------------------------------------

TEST(Operations, SplitWordSeparatesEventsOnWhiteSpace) {
  EXPECT_THAT(split_word("  hazard_detected \t high_risk\n"), ElementsAre("hazard_detected", "high_risk"));
  EXPECT_THAT(split_word(""), IsEmpty());
  EXPECT_THAT(split_word("   "), IsEmpty());
}

TEST(Operations, EvaluateWordReportsStateReachedAndMarking) {
  const Generator g = load_generator(example("emrm_fsm.yaml"));
  const auto high = evaluate_word(g, {"hazard_detected", "high_risk"});
  EXPECT_TRUE(high.generated);
  EXPECT_FALSE(high.marked);
  EXPECT_THAT(high.reached, ElementsAre("S3"));
  const auto no_risk = evaluate_word(g, {"hazard_detected", "no_risk"});
  EXPECT_TRUE(no_risk.generated);
  EXPECT_TRUE(no_risk.marked);
  EXPECT_THAT(no_risk.reached, ElementsAre("S1"));
}

TEST(Operations, EvaluateWordNamesWhereAWordFails) {
  const Generator g = load_generator(example("emrm_fsm.yaml"));
  const auto stuck = evaluate_word(g, {"hazard_detected", "safe", "no_risk"});
  EXPECT_FALSE(stuck.generated);
  EXPECT_FALSE(stuck.marked);
  EXPECT_EQ(stuck.failed_at, 2U);
  EXPECT_EQ(stuck.failed_event, "safe");
  EXPECT_FALSE(stuck.unknown_event);
  EXPECT_THAT(stuck.failed_from, ElementsAre("S2"));
  const auto unknown = evaluate_word(g, {"brake"});
  EXPECT_FALSE(unknown.generated);
  EXPECT_EQ(unknown.failed_at, 1U);
  EXPECT_TRUE(unknown.unknown_event);
  EXPECT_THAT(unknown.failed_from, ElementsAre("S1"));
}

// By hand, counting words of length n by the state they end in (S1 = 1 at n = 0):
//   n=1: S2 1                     -> 1 word,  0 marked
//   n=2: S1 1, S3 1               -> 2 words, 1 marked
//   n=3: S2 1, S4 1               -> 2 words, 0 marked
//   n=4: S1 2, S3 1, S5 1         -> 4 words, 2 marked
//   n=5: S2 2, S4 1, S6 1         -> 4 words, 1 marked
//   n=6: S1 4, S3 2, S5 1         -> 7 words, 4 marked
TEST(Operations, CountsWordsOfTheShippedMachinePerLength) {
  const auto w = enumerate_words(load_generator(example("emrm_fsm.yaml")), 6);
  EXPECT_THAT(w.words_per_length, ElementsAre(1, 1, 2, 2, 4, 4, 7));
  EXPECT_THAT(w.marked_per_length, ElementsAre(1, 0, 1, 0, 2, 1, 4));
  EXPECT_FALSE(w.truncated);
  EXPECT_FALSE(w.counts_saturated);
  EXPECT_EQ(w.words.size(), 20U);
  const auto listed = std::find_if(w.words.begin(), w.words.end(), [](const ListedWord& word) {
    return word.events == Word{"hazard_detected", "high_risk", "execute_maneuver", "emrm_done"};
  });
  ASSERT_NE(listed, w.words.end());
  EXPECT_TRUE(listed->marked);
  EXPECT_THAT(listed->reached, ElementsAre("S1"));
}

TEST(Operations, ListsWordsByLengthThenEventOrder) {
  // p --a--> q (marked), p --b--> p, q --a--> p.
  const Generator g =
      make("m", {"p", "q"}, {"a", "b"}, {{"p", "a", "q"}, {"p", "b", "p"}, {"q", "a", "p"}}, "p", {"q"});
  const auto w = enumerate_words(g, 2);
  ASSERT_EQ(w.words.size(), 5U);  // a, b | aa, ba, bb
  EXPECT_EQ(w.words[0].events, (Word{"a"}));
  EXPECT_TRUE(w.words[0].marked);
  EXPECT_EQ(w.words[1].events, (Word{"b"}));
  EXPECT_FALSE(w.words[1].marked);
  EXPECT_EQ(w.words[2].events, (Word{"a", "a"}));
  EXPECT_EQ(w.words[3].events, (Word{"b", "a"}));
  EXPECT_TRUE(w.words[3].marked);
  EXPECT_EQ(w.words[4].events, (Word{"b", "b"}));
  EXPECT_THAT(w.words_per_length, ElementsAre(1, 2, 3));
  EXPECT_THAT(w.marked_per_length, ElementsAre(0, 1, 1));
}

TEST(Operations, FullTwoLetterLoopHasTwoToTheNWords) {
  const Generator g = make("loop", {"s"}, {"a", "b"}, {{"s", "a", "s"}, {"s", "b", "s"}}, "s", {"s"});
  const auto w = enumerate_words(g, 10);
  for (std::size_t n = 0; n <= 10; ++n) {
    EXPECT_EQ(w.words_per_length[n], std::uint64_t{1} << n);
    EXPECT_EQ(w.marked_per_length[n], std::uint64_t{1} << n);
  }
}

TEST(Operations, ListingStopsAtTheLimitButCountsStayExact) {
  const Generator g = make("loop", {"s"}, {"a", "b"}, {{"s", "a", "s"}, {"s", "b", "s"}}, "s", {});
  const auto w = enumerate_words(g, 8, 10);
  EXPECT_EQ(w.words.size(), 10U);
  EXPECT_TRUE(w.truncated);
  EXPECT_EQ(w.words_per_length[8], 256U);
  EXPECT_EQ(w.marked_per_length[8], 0U);
  EXPECT_EQ(w.words[9].events.size(), 3U);  // 2 of length 1, 4 of length 2, then length 3
}

TEST(Operations, WordCountsSaturateInsteadOfOverflowing) {
  std::vector<std::string> events;
  std::vector<Edge> loops;
  for (int i = 0; i < 16; ++i) {
    events.push_back("e" + std::to_string(i));
    loops.push_back({"s", events.back(), "s"});
  }
  const auto w = enumerate_words(make("wide", {"s"}, events, loops, "s", {"s"}), 20, 5);
  EXPECT_EQ(w.words_per_length[15], std::uint64_t{1} << 60);  // 16^15
  EXPECT_TRUE(w.counts_saturated);                            // 16^16 does not fit
  EXPECT_EQ(w.words_per_length[20], UINT64_MAX);
}

TEST(Operations, NonDeterministicWordsAreCountedOnce) {
  // Two paths read "a b"; it is one word.
  const Generator g = make("nd", {"s0", "s1", "s2", "s3"}, {"a", "b"},
                           {{"s0", "a", "s1"}, {"s0", "a", "s2"}, {"s1", "b", "s3"}, {"s2", "b", "s3"}}, "s0", {"s3"});
  const auto w = enumerate_words(g, 3);
  EXPECT_THAT(w.words_per_length, ElementsAre(1, 1, 1, 0));
  EXPECT_THAT(w.marked_per_length, ElementsAre(0, 0, 1, 0));
  ASSERT_EQ(w.words.size(), 2U);
  EXPECT_THAT(w.words[0].reached, ElementsAre("s1", "s2"));
}

TEST(Operations, NegativeWordLengthIsRejected) {
  EXPECT_THROW((void)enumerate_words(make("m", {"s"}, {}, {}, "s", {}), -1), Error);
}

// ---- accessibility, trim and the checks ----------------------------------------------------

// s0 --go--> ok (marked), ok --fail--> dead (unmarked, no way out), orphan --go--> s0 (unreachable).
Generator with_dead_end() {
  return make("dead_end", {"s0", "ok", "dead", "orphan"}, {"go", "fail"},
              {{"s0", "go", "ok"}, {"ok", "fail", "dead"}, {"orphan", "go", "s0"}}, "s0", {"ok"});
}

TEST(Operations, AccessibleAndCoaccessibleStatesAreFound) {
  const Generator g = with_dead_end();
  EXPECT_THAT(accessible_states(g), ElementsAre("s0", "ok", "dead"));
  EXPECT_THAT(coaccessible_states(g), ElementsAre("s0", "ok", "orphan"));
}

TEST(Operations, AccessiblePartDropsUnreachableStatesAndTheirTransitions) {
  const Generator ac = accessible_part(with_dead_end());
  EXPECT_THAT(state_ids(ac), ElementsAre("s0", "ok", "dead"));
  EXPECT_EQ(ac.transitions().size(), 2U);
  EXPECT_FALSE(ac.has_state("orphan"));
  EXPECT_EQ(ac.initial(), "s0");
  EXPECT_EQ(ac.events().size(), 2U);
}

TEST(Operations, CoaccessiblePartDropsStatesThatCannotFinish) {
  const Generator coac = coaccessible_part(with_dead_end());
  EXPECT_THAT(state_ids(coac), ElementsAre("s0", "ok", "orphan"));
  EXPECT_TRUE(coac.has_transition("orphan", "go", "s0"));
  EXPECT_TRUE(coac.has_event("fail"));  // Σ is kept; only the transition into "dead" is gone
  EXPECT_FALSE(coac.generates({"go", "fail"}));
}

TEST(Operations, CoaccessiblePartDropsAnInitialStateThatCannotFinish) {
  const Generator g = make("stuck", {"s0", "m"}, {"a"}, {{"m", "a", "m"}}, "s0", {"m"});
  const Generator coac = coaccessible_part(g);
  EXPECT_EQ(coac.initial(), std::nullopt);
  EXPECT_FALSE(coac.generates({}));
}

TEST(Operations, TrimKeepsOnlyStatesOnAPathToAMarkedState) {
  const Generator t = trim(with_dead_end());
  EXPECT_THAT(state_ids(t), ElementsAre("s0", "ok"));
  EXPECT_EQ(transition_set(t), (std::set<std::tuple<std::string, std::string, std::string>>{{"s0", "go", "ok"}}));
  EXPECT_TRUE(check_all(t).ok());
}

TEST(Operations, DeadEndStateIsReportedAsBlockingWithTheEventThatEntersIt) {
  const Generator g = with_dead_end();
  const auto nonblocking = check_nonblocking(g);
  EXPECT_FALSE(nonblocking.ok());
  EXPECT_THAT(nonblocking.blocking, ElementsAre("dead"));
  ASSERT_EQ(nonblocking.entering.size(), 1U);
  EXPECT_EQ(g.transitions()[nonblocking.entering[0]].event, "fail");
  EXPECT_EQ(g.transitions()[nonblocking.entering[0]].from, "ok");
  EXPECT_THAT(check_coaccessible(g).cannot_reach_marked, ElementsAre("dead"));
  EXPECT_THAT(check_accessible(g).unreachable, ElementsAre("orphan"));
  EXPECT_TRUE(check_deterministic(g).ok());
  EXPECT_FALSE(check_all(g).ok());
}

TEST(Operations, LivelockAwayFromMarkedStatesIsBlocking) {
  // s0 (marked) --a--> p <--b/c--> q : p and q cycle forever without a way back.
  const Generator g = make("livelock", {"s0", "p", "q"}, {"a", "b", "c"},
                           {{"s0", "a", "p"}, {"p", "b", "q"}, {"q", "c", "p"}}, "s0", {"s0"});
  EXPECT_THAT(check_nonblocking(g).blocking, ElementsAre("p", "q"));
}

TEST(Operations, UnreachableDeadEndDoesNotBlock) {
  // Blocking is about reachable states: the dead "u" fails co-accessibility but not non-blocking.
  const Generator g = make("g", {"s0", "u"}, {"a"}, {{"s0", "a", "s0"}}, "s0", {"s0"});
  EXPECT_TRUE(check_nonblocking(g).ok());
  EXPECT_THAT(check_coaccessible(g).cannot_reach_marked, ElementsAre("u"));
  EXPECT_THAT(check_accessible(g).unreachable, ElementsAre("u"));
}

TEST(Operations, NonDeterministicChoiceIsNamedWithItsTransitions) {
  Generator g = load_generator(example("emrm_fsm.yaml"));
  g.add_transition("S2", "high_risk", "S4");
  const auto det = check_deterministic(g);
  ASSERT_EQ(det.choices.size(), 1U);
  EXPECT_EQ(det.choices[0].state, "S2");
  EXPECT_EQ(det.choices[0].event, "high_risk");
  ASSERT_EQ(det.choices[0].transitions.size(), 2U);
  EXPECT_EQ(g.transitions()[det.choices[0].transitions[0]].to, "S3");
  EXPECT_EQ(g.transitions()[det.choices[0].transitions[1]].to, "S4");
  EXPECT_FALSE(check_all(g).ok());
}

TEST(Operations, ShippedMachinesPassEveryCheck) {
  for (const char* file : {"emrm_fsm.yaml", "loss_evaluation_fsm.yaml"}) {
    const auto report = check_all(load_generator(example(file)));
    EXPECT_TRUE(report.accessible.ok()) << file;
    EXPECT_TRUE(report.coaccessible.ok()) << file;
    EXPECT_TRUE(report.deterministic.ok()) << file;
    EXPECT_TRUE(report.nonblocking.ok()) << file;
  }
}

// ---- composition -------------------------------------------------------------------------

TEST(Operations, ComposeSynchronisesSharedEventsAndInterleavesPrivateOnes) {
  // G1: x0 --a--> x1 --c--> x0, x0 marked.   G2: y0 --b--> y1 --c--> y0, y0 marked.   c is shared.
  const Generator g1 = make("G1", {"x0", "x1"}, {"a", "c"}, {{"x0", "a", "x1"}, {"x1", "c", "x0"}}, "x0", {"x0"});
  const Generator g2 = make("G2", {"y0", "y1"}, {"b", "c"}, {{"y0", "b", "y1"}, {"y1", "c", "y0"}}, "y0", {"y0"});
  const Generator p = compose(g1, g2);
  // Expected product, built by hand: a and b interleave, c needs both machines ready.
  EXPECT_EQ(p.name(), "G1||G2");
  EXPECT_THAT(state_ids(p), ElementsAre("x0|y0", "x1|y0", "x0|y1", "x1|y1"));
  std::vector<std::string> events;
  for (const auto& e : p.events()) events.push_back(e.id);
  EXPECT_THAT(events, ElementsAre("a", "c", "b"));
  EXPECT_EQ(transition_set(p), (std::set<std::tuple<std::string, std::string, std::string>>{
                                   {"x0|y0", "a", "x1|y0"},
                                   {"x0|y0", "b", "x0|y1"},
                                   {"x1|y0", "b", "x1|y1"},
                                   {"x0|y1", "a", "x1|y1"},
                                   {"x1|y1", "c", "x0|y0"},
                               }));
  EXPECT_EQ(p.initial(), "x0|y0");
  EXPECT_THAT(p.marked_states(), ElementsAre("x0|y0"));
  EXPECT_TRUE(p.generates({"b", "a", "c"}));
  EXPECT_FALSE(p.generates({"a", "c"}));  // G2 is not ready for c
}

TEST(Operations, ComposeKeepsOnlyAccessiblePairs) {
  // s is shared, p is private to G2: after p, G2 can never take s, so G1 can never finish.
  const Generator g1 = make("G1", {"x0", "x1"}, {"s"}, {{"x0", "s", "x1"}}, "x0", {"x1"});
  const Generator g2 =
      make("G2", {"y0", "y1", "y2"}, {"s", "p"}, {{"y0", "s", "y1"}, {"y0", "p", "y2"}}, "y0", {"y1", "y2"});
  const Generator p = compose(g1, g2);
  EXPECT_THAT(state_ids(p), ElementsAre("x0|y0", "x1|y1", "x0|y2"));  // 3 of the 6 pairs
  EXPECT_THAT(p.marked_states(), ElementsAre("x1|y1"));
  EXPECT_THAT(check_nonblocking(p).blocking, ElementsAre("x0|y2"));  // G2 took p; G1 can never finish
}

TEST(Operations, ComposedLanguageOverACommonAlphabetIsTheIntersection) {
  const Generator g1 =
      make("G1", {"p", "q"}, {"a", "b"}, {{"p", "a", "q"}, {"q", "b", "p"}, {"q", "a", "q"}}, "p", {"p"});
  const Generator g2 =
      make("G2", {"u", "v"}, {"a", "b"}, {{"u", "a", "v"}, {"v", "a", "u"}, {"u", "b", "u"}}, "u", {"u"});
  const Generator p = compose(g1, g2);
  // Every word over {a, b} up to length 5 is in L(G1||G2) exactly when it is in both languages.
  int checked = 0;
  for (int length = 0; length <= 5; ++length)
    for (int bits = 0; bits < (1 << length); ++bits) {
      Word w;
      for (int i = 0; i < length; ++i) w.push_back(((bits >> i) & 1) != 0 ? "b" : "a");
      EXPECT_EQ(p.generates(w), g1.generates(w) && g2.generates(w));
      EXPECT_EQ(p.marks(w), g1.marks(w) && g2.marks(w));
      ++checked;
    }
  EXPECT_EQ(checked, 63);
}

TEST(Operations, ComposeWithAMachineWithoutInitialStateIsEmpty) {
  const Generator g1 = make("G1", {"x"}, {"a"}, {}, "x", {"x"});
  const Generator g2 = make("G2", {"y"}, {"a"}, {}, "", {});
  const Generator p = compose(g1, g2);
  EXPECT_TRUE(p.states().empty());
  EXPECT_FALSE(p.generates({}));
}

// ---- coverage ------------------------------------------------------------------------------

TEST(Operations, CoverageCountsTransitionsAndTheCoveredFraction) {
  const Generator g = load_generator(example("emrm_fsm.yaml"));
  const std::vector<Word> traces{
      {"hazard_detected", "high_risk", "execute_maneuver", "emrm_done"},
      {"hazard_detected", "no_risk"},
      {"hazard_detected", "no_risk", "hazard_detected", "high_risk", "execute_maneuver", "emrm_done"},
      {"hazard_detected", "safe"},  // not in L(G)
  };
  const auto c = transition_coverage(g, traces);
  // Transitions in file order: hd, no_risk, high_risk, execute, emrm_done, timeout, post_incident, safe.
  // hazard_detected: once in the first two traces, twice in the third; the rejected one adds nothing.
  EXPECT_THAT(c.counts, ElementsAre(4, 2, 2, 2, 2, 0, 0, 0));
  EXPECT_EQ(c.covered, 5U);
  EXPECT_DOUBLE_EQ(c.fraction(), 5.0 / 8.0);
  EXPECT_EQ(c.traces, 4U);
  EXPECT_EQ(c.accepted, 3U);
  ASSERT_EQ(c.rejected.size(), 1U);
  EXPECT_EQ(c.rejected[0].trace, 3U);
  EXPECT_EQ(c.rejected[0].evaluation.failed_at, 2U);
  EXPECT_EQ(c.rejected[0].evaluation.failed_event, "safe");
}

TEST(Operations, FullCoverageOfTheShippedMachine) {
  const Generator g = load_generator(example("emrm_fsm.yaml"));
  const auto c = transition_coverage(
      g, {{"hazard_detected", "no_risk"},
          {"hazard_detected", "high_risk", "execute_maneuver", "emrm_done"},
          {"hazard_detected", "high_risk", "execute_maneuver", "timeout_error", "post_incident_response", "safe"}});
  EXPECT_EQ(c.covered, 8U);
  EXPECT_DOUBLE_EQ(c.fraction(), 1.0);
  EXPECT_THAT(c.rejected, IsEmpty());
}

TEST(Operations, CoverageOfANonDeterministicMachineFollowsAPathThatReadsTheTrace) {
  // s0 --a--> s1 (declared first, dead end for b), s0 --a--> s2 --b--> s3.
  const Generator g = make("nd", {"s0", "s1", "s2", "s3"}, {"a", "b"},
                           {{"s0", "a", "s1"}, {"s0", "a", "s2"}, {"s2", "b", "s3"}}, "s0", {"s3"});
  EXPECT_THAT(transition_coverage(g, {{"a", "b"}}).counts, ElementsAre(0, 1, 1));
  EXPECT_THAT(transition_coverage(g, {{"a"}}).counts, ElementsAre(1, 0, 0));  // first path in file order
}

// ---- the loss-evaluation FSM ---------------------------------------------------------------

/// The decision rule of docs/fsm.md, written independently of the YAML.
std::string expected_strategy(int severity, int controllability, int maneuverability) {
  switch (controllability) {
    case 0:
      return "emergency_stop";
    case 1:
      return "dodge";
    case 2:
      return "drift_to_avoid";
    default:
      break;
  }
  if (severity == 1) return "emergency_stop";  // marginal: property damage only
  return maneuverability == 1 ? "emergency_stop" : "drift_to_accident";
}

TEST(Operations, LossEvaluationDecisionTableIsExhaustive) {
  const Generator g = load_generator(example("loss_evaluation_fsm.yaml"));
  std::map<std::string, int> per_strategy;
  int checked = 0;
  for (int se = 1; se <= 3; ++se)
    for (int e = 0; e <= 1; ++e)
      for (int c = 0; c <= 3; ++c)
        for (int mi = 1; mi <= 3; ++mi) {
          const Word w{"Se" + std::to_string(se), "E" + std::to_string(e), "C" + std::to_string(c),
                       "Mi" + std::to_string(mi)};
          const auto reached = g.run(*g.initial(), w);
          ASSERT_TRUE(reached.has_value()) << w[0] << w[1] << w[2] << w[3];
          EXPECT_EQ(*reached, expected_strategy(se, c, mi)) << w[0] << " " << w[1] << " " << w[2] << " " << w[3];
          EXPECT_TRUE(g.marks(w));
          ++per_strategy[*reached];
          ++checked;
        }
  EXPECT_EQ(checked, 72);
  // C0: 18 words plus C3 with Se1 (6) plus C3, Se2/Se3, Mi1 (4) = 28 emergency stops.
  EXPECT_EQ(per_strategy["emergency_stop"], 28);
  EXPECT_EQ(per_strategy["dodge"], 18);
  EXPECT_EQ(per_strategy["drift_to_avoid"], 18);
  EXPECT_EQ(per_strategy["drift_to_accident"], 8);
}

TEST(Operations, LossEvaluationMarksExactlyTheWordsOfLengthFour) {
  const auto w = enumerate_words(load_generator(example("loss_evaluation_fsm.yaml")), 6);
  EXPECT_THAT(w.words_per_length, ElementsAre(1, 3, 6, 24, 72, 0, 0));
  EXPECT_THAT(w.marked_per_length, ElementsAre(0, 0, 0, 0, 72, 0, 0));
}

TEST(Operations, LossEvaluationReadsTheRatingsInOrder) {
  const Generator g = load_generator(example("loss_evaluation_fsm.yaml"));
  EXPECT_FALSE(g.generates({"E0"}));                             // severity first
  EXPECT_FALSE(g.generates({"Se1", "C0"}));                      // exposure before controllability
  EXPECT_FALSE(g.generates({"Se1", "E0", "Mi1"}));               // controllability before maneuverability
  EXPECT_FALSE(g.generates({"Se1", "E0", "C0", "Mi1", "Se1"}));  // a strategy state is final
}

TEST(Operations, LossEvaluationIsMinimalWithTheStrategyAsOutput) {
  // Moore-style partition refinement: start from "which strategy (or none) a state is", split by
  // the classes of the successors on every event. Minimal means every state ends in its own class.
  const Generator g = load_generator(example("loss_evaluation_fsm.yaml"));
  std::vector<std::string> klass;
  for (const auto& s : g.states()) klass.push_back(g.is_marked(s.id) ? s.id : "-");
  for (int round = 0; round < g.state_count(); ++round) {
    std::map<std::vector<std::string>, std::string> signature_class;
    std::vector<std::string> next;
    for (int s = 0; s < g.state_count(); ++s) {
      std::vector<std::string> signature{klass[static_cast<std::size_t>(s)]};
      for (int e = 0; e < g.event_count(); ++e) {
        const int t = g.step_index(s, e);
        signature.push_back(t == Generator::kNone ? "x" : klass[static_cast<std::size_t>(t)]);
      }
      auto [it, inserted] = signature_class.emplace(signature, std::to_string(signature_class.size()));
      next.push_back(it->second);
    }
    klass = next;
  }
  EXPECT_EQ(std::set<std::string>(klass.begin(), klass.end()).size(), g.states().size());
  EXPECT_EQ(g.states().size(), 13U);
}

}  // namespace operations_test
}  // namespace emrm::fsm
