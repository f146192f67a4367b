// End-to-end: `emrm analyze` on the shipped safety case and on broken copies of it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "run_emrm.hpp"

namespace emrm::e2e {
namespace analyze_cli_test {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;

// A copy of the shipped case (and the FSM it names) with one edit applied, in a scratch folder.
std::filesystem::path edited_case(const std::string& test, const std::string& from, const std::string& to) {
  const auto dir = scratch_dir(test);
  std::string text = read_text(example("safety.yaml"));
  const auto pos = text.find(from);
  if (pos == std::string::npos) throw std::logic_error("edit did not apply: " + from);
  text.replace(pos, from.size(), to);
  write_text(dir / "safety.yaml", text);
  std::filesystem::copy_file(example("emrm_fsm.yaml"), dir / "emrm_fsm.yaml");
  return dir / "safety.yaml";
}

// Bad input: exit 2, nothing on stdout, exactly one line on stderr naming file:line:column.
void expect_safety_file_error(const RunResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, MatchesRegex(".*safety\\.yaml:[0-9]+:[0-9]+: error: .*\n"));
  EXPECT_THAT(r.err, HasSubstr(what));
}

TEST(AnalyzeCli, ShippedCasePassesAndWritesItsTables) {
  const auto out = scratch_dir("shipped");
  const auto r = run_emrm("analyze " + quoted(example("safety.yaml")) + " -o " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("Findings: 0 errors"));
  for (const char* file : {"traceability.csv", "traceability.md", "findings.json", "asil.csv"})
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;

  // Every UCA traces to at least one hazard and one loss.
  const std::string csv = read_text(out / "traceability.csv");
  for (const char* uca : {"UCA1,", "UCA2,", "UCA3,", "UCA4,"}) EXPECT_THAT(csv, HasSubstr(std::string("\n") + uca));
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    EXPECT_THAT(line, MatchesRegex("UCA[0-9],[a-z_]+,CA1,H[0-9],(QM|A|B|C|D),[A-F]?,L[0-9],.*"));
  }
  EXPECT_GT(rows, 4);
  const auto findings = nlohmann::json::parse(read_text(out / "findings.json"));
  for (const auto& f : findings) EXPECT_EQ(f["severity"], "warning");
}

TEST(AnalyzeCli, JsonOutputIsOneDocumentWithTheMapping) {
  const auto r = run_emrm("analyze " + quoted(example("safety.yaml")) + " --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["summary"]["ucas"], 4);
  EXPECT_EQ(j["mapping"].size(), 4u);
  for (const auto& m : j["mapping"]) {
    EXPECT_FALSE(m["hazards"].empty());
    EXPECT_FALSE(m["losses"].empty());
  }
}

TEST(AnalyzeCli, DanglingReferenceExitsOneAndNamesTheMissingId) {
  const auto file = edited_case("dangling", "hazards: [H2, H6]", "hazards: [H2, H42]");
  const auto r = run_emrm("analyze " + quoted(file));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("SAF001"));
  EXPECT_THAT(r.out, HasSubstr("'H42'"));
}

TEST(AnalyzeCli, TransitionMissingFromTheFsmExitsOne) {
  const auto file = edited_case("fsm-transition", "{from: S5, event: post_incident_response, to: S6}",
                                "{from: S5, event: safe, to: S6}");
  const auto r = run_emrm("analyze " + quoted(file));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("SAF011"));
  EXPECT_THAT(r.out, HasSubstr("S5 -safe-> S6"));
  EXPECT_EQ(run_emrm("analyze " + quoted(file) + " --no-fsm").exit_code, 0);
}

TEST(AnalyzeCli, StrictTurnsWarningsIntoFailure) {
  EXPECT_EQ(run_emrm("analyze " + quoted(example("safety.yaml")) + " --strict").exit_code, 1);
}

TEST(AnalyzeCli, MalformedYamlExitsTwo) {
  expect_safety_file_error(
      run_emrm("analyze " + quoted(edited_case("malformed", "losses: [L6, L7]", "losses: [L6, L7"))), "malformed YAML");
}

TEST(AnalyzeCli, WrongTypeExitsTwo) {
  expect_safety_file_error(run_emrm("analyze " + quoted(edited_case("type", "reversible: false", "reversible: 12"))),
                           "expected true or false");
}

TEST(AnalyzeCli, MissingFieldExitsTwo) {
  expect_safety_file_error(run_emrm("analyze " + quoted(edited_case("missing", "    context: >-\n      EMRM fails",
                                                                    "    contxt: >-\n      EMRM fails"))),
                           "missing required field 'context'");
}

TEST(AnalyzeCli, DuplicateIdExitsTwo) {
  expect_safety_file_error(run_emrm("analyze " + quoted(edited_case("duplicate", "id: UCA4", "id: UCA2"))),
                           "duplicate id 'UCA2'");
}

TEST(AnalyzeCli, UnknownUcaTypeExitsTwo) {
  expect_safety_file_error(
      run_emrm("analyze " + quoted(edited_case("uca-type", "type: not_provided", "type: not_provide"))),
      "got 'not_provide'");
}

TEST(AnalyzeCli, RatingOutOfRangeExitsTwo) {
  expect_safety_file_error(
      run_emrm("analyze " + quoted(edited_case("rating", "controllability: C3", "controllability: C4"))),
      "expected C0, C1, C2 or C3, got 'C4'");
}

TEST(AnalyzeCli, NanInAFactorRangeExitsTwo) {
  expect_safety_file_error(run_emrm("analyze " + quoted(edited_case("nan", "max: 1.0,", "max: .nan,"))),
                           "finite number");
}

TEST(AnalyzeCli, UnknownFactorInARegionExitsTwo) {
  expect_safety_file_error(
      run_emrm("analyze " + quoted(edited_case("factor", "region: \"ttc_s < 0.7\"", "region: \"ttc < 0.7\""))),
      "unknown name 'ttc'");
}

TEST(AnalyzeCli, BrokenFsmNamedByTheCaseExitsTwoNamingTheFsmFile) {
  const auto file = edited_case("broken-fsm", "name: EMRM T-junction", "name: EMRM T-junction");
  write_text(file.parent_path() / "emrm_fsm.yaml",
             "name: x\nstates: [S1]\nevents: [e]\ninitial: S9\nmarked: []\n"
             "transitions: []\n");
  const auto r = run_emrm("analyze " + quoted(file));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, MatchesRegex(".*emrm_fsm\\.yaml:4:[0-9]+: error: .*\n"));
}

TEST(AnalyzeCli, MissingFileIsAUsageError) {
  const auto r = run_emrm("analyze /nonexistent/safety.yaml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("/nonexistent/safety.yaml"));
}

TEST(AnalyzeCli, UnwritableOutputFolderExitsTwo) {
  const auto r = run_emrm("analyze " + quoted(example("safety.yaml")) + " -o /proc/emrm-no-such-dir");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("/proc/emrm-no-such-dir"));
}

}  // namespace analyze_cli_test
}  // namespace emrm::e2e
