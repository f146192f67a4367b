// End-to-end tests of `emrm fsm`: the real binary on the shipped machines and on broken copies.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace fsm_cli_test {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// Qualified, so that argument-dependent lookup cannot pick std::quoted for a std::string.
std::string arg(const std::filesystem::path& path) { return emrm::e2e::quoted(path); }

std::string emrm_fsm() { return arg(example("emrm_fsm.yaml")); }
std::string loss_fsm() { return arg(example("loss_evaluation_fsm.yaml")); }

struct Edit {
  std::string from, to;
};

/// The shipped EMRM FSM with textual changes (asserts that each applied).
std::filesystem::path broken_copy(const std::string& test, const std::vector<Edit>& edits) {
  std::string text = read_text(example("emrm_fsm.yaml"));
  for (const auto& edit : edits) {
    const auto at = text.find(edit.from);
    EXPECT_NE(at, std::string::npos) << edit.from;
    if (at != std::string::npos) text.replace(at, edit.from.size(), edit.to);
  }
  const auto path = scratch_dir(test) / "fsm.yaml";
  write_text(path, text);
  return path;
}

TEST(FsmCli, ShippedMachinePassesChecksAndListsWords) {
  const auto r = run_emrm("fsm " + emrm_fsm() + " --check --words 6");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("accessible:     ok"));
  EXPECT_THAT(r.out, HasSubstr("co-accessible:  ok"));
  EXPECT_THAT(r.out, HasSubstr("deterministic:  ok"));
  EXPECT_THAT(r.out, HasSubstr("non-blocking:   ok"));
  EXPECT_THAT(r.out, HasSubstr("hazard_detected high_risk execute_maneuver emrm_done -> S1 (marked)"));
  EXPECT_THAT(r.out, HasSubstr("hazard_detected high_risk -> S3\n"));  // in L(G), not in L_m(G)
  EXPECT_THAT(r.out, HasSubstr("length 6: 7 words, 4 in L_m(G)"));
  EXPECT_THAT(r.out, Not(HasSubstr("FAILED")));
}

TEST(FsmCli, LossEvaluationMachinePassesChecks) {
  const auto r = run_emrm("fsm " + loss_fsm() + " --check --words 4");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, Not(HasSubstr("FAILED")));
  EXPECT_THAT(r.out, HasSubstr("length 4: 72 words, 72 in L_m(G)"));
  EXPECT_THAT(r.out, HasSubstr("Se3 E1 C3 Mi3 -> drift_to_accident (marked)"));
}

TEST(FsmCli, WithoutOptionsPrintsASummary) {
  const auto r = run_emrm("fsm " + emrm_fsm());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("6 states, 8 events, 8 transitions, deterministic"));
  EXPECT_THAT(r.out, HasSubstr("initial: S1"));
  EXPECT_THAT(r.out, HasSubstr("marked:  S1, S6"));
  EXPECT_THAT(r.out, HasSubstr("S4 --timeout_error--> S5"));
}

TEST(FsmCli, BlockingCopyFailsNamingTheStatesAndTheEventIntoThem) {
  // S6 no longer leads back and is no longer marked: after timeout_error the machine is trapped.
  const auto fsm = broken_copy("blocking", {{"marked: [S1, S6]", "marked: [S1]"},
                                            {"{from: S6, event: safe, to: S1}", "{from: S6, event: safe, to: S6}"}});
  const auto r = run_emrm("fsm " + arg(fsm) + " --check");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("co-accessible:  FAILED: cannot reach a marked state: S5, S6"));
  EXPECT_THAT(r.out, HasSubstr("non-blocking:   FAILED"));
  EXPECT_THAT(r.out, HasSubstr("S5, S6; entered by S4 --timeout_error--> S5"));
  EXPECT_THAT(r.out, HasSubstr("deterministic:  ok"));
}

TEST(FsmCli, MarkedTerminalStateIsNotBlockingButAnUnmarkedDeadEndIs) {
  // Without "safe", S6 has no way out, but it is marked: a terminating state, so all checks pass.
  const auto fsm = broken_copy("terminal", {{"  - {from: S6, event: safe, to: S1}\n", ""}});
  const auto r = run_emrm("fsm " + arg(fsm) + " --check");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  const auto unmarked = broken_copy("dead_end", {{"  - {from: S5, event: post_incident_response, to: S6}", ""}});
  const auto r2 = run_emrm("fsm " + arg(unmarked) + " --check");
  EXPECT_EQ(r2.exit_code, 1);
  EXPECT_THAT(r2.out, HasSubstr("blocking (reachable, cannot reach a marked state): S5"));
  EXPECT_THAT(r2.out, HasSubstr("accessible:     FAILED: not reachable from S1: S6"));
}

TEST(FsmCli, NonDeterministicCopyFailsNamingTheStateAndEvent) {
  const auto fsm = broken_copy("nondeterministic", {{"  - {from: S2, event: high_risk, to: S3}",
                                                     "  - {from: S2, event: high_risk, to: S3}\n"
                                                     "  - {from: S2, event: high_risk, to: S5}"}});
  const auto r = run_emrm("fsm " + arg(fsm) + " --check");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("deterministic:  FAILED: S2 on 'high_risk' goes to S3"));
  EXPECT_THAT(r.out, HasSubstr("or S5 (" + fsm.string() + ":"));
}

TEST(FsmCli, WordQueriesReportMembershipAndWhereAWordFails) {
  const auto r = run_emrm("fsm " + emrm_fsm() + " --word 'hazard_detected high_risk' --word 'hazard_detected no_risk'" +
                          " --word 'hazard_detected safe'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("word \"hazard_detected high_risk\": in L(G), not in L_m(G); reaches S3"));
  EXPECT_THAT(r.out, HasSubstr("word \"hazard_detected no_risk\": in L(G), in L_m(G); reaches S1"));
  EXPECT_THAT(r.out,
              HasSubstr("word \"hazard_detected safe\": not in L(G): no transition on 'safe' (event 2) from S2"));
}

TEST(FsmCli, TracesReportCoverageAndRejectedTracesFailTheRun) {
  const auto dir = scratch_dir("traces");
  write_text(dir / "ok.txt",
             "# two recorded cells\n"
             "hazard_detected high_risk execute_maneuver emrm_done\n"
             "\n"
             "hazard_detected no_risk   # no evasive action needed\n");
  const auto ok = run_emrm("fsm " + emrm_fsm() + " --traces " + arg(dir / "ok.txt"));
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_THAT(ok.out, HasSubstr("5 of 8 transitions covered (62.5 %)"));
  EXPECT_THAT(ok.out, HasSubstr("0  S6 --safe--> S1  (not covered)"));

  write_text(dir / "bad.txt", "hazard_detected no_risk\nhazard_detected emrm_done\n");
  const auto bad = run_emrm("fsm " + emrm_fsm() + " --traces " + arg(dir / "bad.txt"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_THAT(bad.out, HasSubstr((dir / "bad.txt").string() + ":2:1: \"hazard_detected emrm_done\""));
  EXPECT_THAT(bad.out, HasSubstr("no transition on 'emrm_done' (event 2) from S2"));
}

TEST(FsmCli, SvgFileStartsWithAnSvgHeader) {
  const auto dir = scratch_dir("svg");
  const auto r = run_emrm("fsm " + emrm_fsm() + " --svg " + arg(dir / "emrm.svg") + " --dot " + arg(dir / "emrm.dot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = read_text(dir / "emrm.svg");
  EXPECT_THAT(svg, StartsWith("<?xml"));
  EXPECT_THAT(svg, HasSubstr("<svg"));
  EXPECT_THAT(read_text(dir / "emrm.dot"), HasSubstr("\"S6\" [shape=doublecircle"));
}

TEST(FsmCli, DiagramWithTracesColoursTheUncoveredTransitions) {
  const auto dir = scratch_dir("dot_traces");
  write_text(dir / "t.txt", "hazard_detected no_risk\n");
  const auto r = run_emrm("fsm " + emrm_fsm() + " --traces " + arg(dir / "t.txt") + " --dot " + arg(dir / "g.dot"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string dot = read_text(dir / "g.dot");
  EXPECT_THAT(dot, HasSubstr("label=\"no_risk (1)\""));
  EXPECT_THAT(dot, HasSubstr("label=\"safe (0)\", color=\"#d62728\""));
}

TEST(FsmCli, ComposeWorksOnTheProduct) {
  // A monitor that allows at most one maneuver before the system is back to normal (shares events).
  const auto dir = scratch_dir("compose");
  write_text(dir / "monitor.yaml",
             "name: monitor\n"
             "states: [idle, busy]\n"
             "events: [execute_maneuver, emrm_done, safe]\n"
             "initial: idle\n"
             "marked: [idle]\n"
             "transitions:\n"
             "  - {from: idle, event: execute_maneuver, to: busy}\n"
             "  - {from: busy, event: emrm_done, to: idle}\n"
             "  - {from: busy, event: safe, to: idle}\n");
  const auto r = run_emrm("fsm " + emrm_fsm() + " --compose " + arg(dir / "monitor.yaml") +
                          " --check --word 'hazard_detected high_risk execute_maneuver emrm_done'");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("checks of emrm||monitor:"));
  EXPECT_THAT(r.out, HasSubstr("in L(G), in L_m(G); reaches S1|idle"));
}

TEST(FsmCli, JsonOutputCarriesTheSameResults) {
  const auto r = run_emrm("fsm " + emrm_fsm() + " --check --words 2 --word 'hazard_detected high_risk' --format json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, StartsWith("{"));
  EXPECT_THAT(r.out, HasSubstr("\"name\": \"emrm\""));
  EXPECT_THAT(r.out, HasSubstr("\"nonblocking\": {\n      \"ok\": true"));
  EXPECT_THAT(r.out, HasSubstr("\"word\": \"hazard_detected no_risk\",\n        \"marked\": true"));
  EXPECT_THAT(r.out, Not(HasSubstr("checks of")));
}

TEST(FsmCli, BadInputFilesExitTwoWithFileLineAndColumn) {
  const auto unknown_state = broken_copy(
      "bad_state", {{"{from: S3, event: execute_maneuver, to: S4}", "{from: S3, event: execute_maneuver, to: S7}"}});
  auto r = run_emrm("fsm " + arg(unknown_state) + " --check");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr(unknown_state.string() + ":"));
  EXPECT_THAT(r.err, HasSubstr("transition target 'S7' is not a declared state"));
  EXPECT_THAT(r.err, testing::ContainsRegex(":[0-9]+:[0-9]+: error:"));

  const auto malformed = broken_copy("malformed", {{"marked: [S1, S6]", "marked: [S1, S6"}});
  r = run_emrm("fsm " + arg(malformed));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("malformed YAML"));
  EXPECT_THAT(r.err, testing::ContainsRegex(":[0-9]+:[0-9]+: error:"));

  const auto unknown_field = broken_copy("unknown_field", {{"initial: S1", "initial: S1\nfinal: S6"}});
  r = run_emrm("fsm " + arg(unknown_field));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("unknown field 'final'"));

  r = run_emrm("fsm " + arg(scratch_dir("missing") / "none.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("none.yaml: error: the file does not exist"));
}

TEST(FsmCli, InvalidOptionValuesExitTwo) {
  EXPECT_EQ(run_emrm("fsm " + emrm_fsm() + " --words 21").exit_code, 2);
  EXPECT_EQ(run_emrm("fsm " + emrm_fsm() + " --words -1").exit_code, 2);
  EXPECT_EQ(run_emrm("fsm " + emrm_fsm() + " --format xml").exit_code, 2);
  EXPECT_EQ(run_emrm("fsm").exit_code, 2);
  EXPECT_EQ(run_emrm("fsm " + emrm_fsm() + " --traces /no/such/traces.txt").exit_code, 2);
}

// Two machines of a thousand states each, on disjoint events: the product has a million states and
// used to take gigabytes. The composition stops at the documented limit (exit 2, naming the flag);
// the flag raises it.
TEST(FsmCli, ComposingTwoLargeMachinesStopsAtTheStateLimit) {
  const auto dir = scratch_dir("fsm-large");
  const auto ring = [&](const std::string& name, const std::string& event) {
    std::string yaml = "name: " + name + "\nstates:\n";
    for (int i = 0; i < 1000; ++i) yaml += "  - {id: " + name + std::to_string(i) + "}\n";
    yaml += "events:\n  - {id: " + event + "}\ninitial: " + name + "0\nmarked: [" + name + "0]\ntransitions:\n";
    for (int i = 0; i < 1000; ++i)
      yaml += "  - {from: " + name + std::to_string(i) + ", event: " + event + ", to: " + name +
              std::to_string((i + 1) % 1000) + "}\n";
    const auto file = dir / (name + ".yaml");
    write_text(file, yaml);
    return file;
  };
  const auto a = ring("a", "tick");
  const auto b = ring("b", "tock");
  const auto r = run_emrm("fsm " + arg(a) + " --compose " + arg(b));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("has more than 100000 states or 1000000 transitions; --max-states raises the limit"));
  const auto small = run_emrm("fsm " + emrm_fsm() + " --compose " + emrm_fsm() + " --max-states 5");
  EXPECT_EQ(small.exit_code, 2);
  EXPECT_EQ(run_emrm("fsm " + emrm_fsm() + " --compose " + emrm_fsm()).exit_code, 0);
}

}  // namespace fsm_cli_test
}  // namespace emrm::e2e
