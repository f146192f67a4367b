// End-to-end: `emrm plan` as a user runs it, on the shipped example and on broken copies of it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "run_emrm.hpp"
#include "small_example.hpp"

namespace emrm::e2e {
namespace plan_cli_test {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::MatchesRegex;

// The shipped ODD with its `safety:` and `scene:` entries made absolute, so that a copy in a
// scratch folder still finds them.
std::string odd_text() {
  std::string text = read_text(example("odd.yaml"));
  for (const std::string name : {"safety", "scene"}) {
    const std::string from = name + ": " + name + ".yaml";
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), name + ": " + example(name + ".yaml"));
  }
  return text;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the example lacks '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// "LINE:COL" of the first occurrence of `needle` (plus `offset`) in `text`.
std::string line_col(const std::string& text, const std::string& needle, int offset = 0) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  if (at == std::string::npos) return "?";
  const std::size_t p = at + static_cast<std::size_t>(offset);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(p), '\n'));
  const auto start = p == 0 ? std::string::npos : text.rfind('\n', p - 1);
  const std::size_t column = start == std::string::npos ? p + 1 : p - start;
  return std::to_string(line) + ":" + std::to_string(column);
}

// Runs `emrm plan` on `text` written to a scratch folder: exit 2 and exactly one line on stderr,
// FILE:LINE:COL: error: ..., at `needle` (+ offset) and saying `words`.
void expect_bad_odd_at(const fs::path& odd, const std::string& text, const std::string& needle, int offset,
                       const std::string& words) {
  const fs::path dir = odd.parent_path();
  write_text(odd, text);
  const auto r = run_emrm("plan " + quoted(odd) + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  const std::string prefix = odd.string() + ":" + line_col(text, needle, offset) + ": error: ";
  EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << "stderr: " << r.err << "\nexpected it to start with " << prefix;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr(words));
  EXPECT_FALSE(fs::exists(dir / "out" / "scenarios.csv"));
}

void expect_bad_odd(const std::string& name, const std::string& text, const std::string& needle, int offset,
                    const std::string& words) {
  SCOPED_TRACE(name);
  expect_bad_odd_at(scratch_dir("plan-bad-" + name) / "odd.yaml", text, needle, offset, words);
}

// The small example (small_example.hpp) with one edit to one of its files; returns its folder.
fs::path edited_small_example(const std::string& name, const std::string& file, const std::string& from,
                              const std::string& to) {
  const fs::path dir = small_example(name);
  write_text(dir / file, replaced(read_text(dir / file), from, to));
  return dir;
}

TEST(PlanCli, ShippedExampleWritesEveryFileAndHoldsC1ToC4) {
  const auto dir = scratch_dir("plan-example");
  const auto r = run_emrm("plan " + quoted(example("odd.yaml")) + " -o " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* f : {"scenarios.csv", "scenarios.json", "coverage.json", "coverage.csv", "coverage.md"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  EXPECT_THAT(r.out, HasSubstr("C1 holds, C2 holds, C3 holds, C4 holds"));

  const auto coverage = nlohmann::json::parse(read_text(dir / "coverage.json"));
  const auto& plan = coverage.at("plan");
  EXPECT_EQ(plan.at("name"), "emrm plan");
  for (const char* c : {"c1", "c2", "c3", "c4", "all"}) EXPECT_TRUE(plan.at(c).get<bool>()) << c;
  EXPECT_EQ(plan.at("inadmissible"), 0);
  EXPECT_EQ(plan.at("malfunctions").at("covered"), 4);
  EXPECT_EQ(plan.at("hazards").at("total"), 8);
  std::vector<std::string> names;
  for (const auto& b : coverage.at("baselines")) names.push_back(b.at("name").get<std::string>());
  EXPECT_EQ(names, (std::vector<std::string>{"HARA only", "STPA only", "manual grid"}));
  // The baselines are small and cover less: HARA has one scenario per hazard, STPA one per UCA,
  // the manual grid 5 x 6.
  const auto& baselines = coverage.at("baselines");
  EXPECT_EQ(baselines[0].at("scenarios"), 8);
  EXPECT_EQ(baselines[1].at("scenarios"), 4);
  EXPECT_EQ(baselines[2].at("scenarios"), 30);
  for (const auto& b : baselines) {
    EXPECT_FALSE(b.at("all").get<bool>()) << b.at("name");
    EXPECT_LT(b.at("cells").at("covered").get<int>(), plan.at("cells").at("covered").get<int>()) << b.at("name");
  }

  // scenarios.csv and scenarios.json agree on the scenarios.
  const std::string csv = read_text(dir / "scenarios.csv");
  EXPECT_EQ(
      csv.rfind("id,step,speed_kph,truck_speed_kph,ttc_s,mu,passage_m,cell,malfunctions,transitions,weight,seed\n", 0),
      0u);
  const auto rows = std::count(csv.begin(), csv.end(), '\n') - 1;
  const auto scenarios = nlohmann::json::parse(read_text(dir / "scenarios.json"));
  EXPECT_EQ(static_cast<long>(scenarios.at("scenarios").size()), rows);
  EXPECT_EQ(plan.at("scenarios").get<long>(), rows);
  std::set<std::string> ids;
  for (const auto& s : scenarios.at("scenarios")) ids.insert(s.at("id").get<std::string>());
  EXPECT_EQ(static_cast<long>(ids.size()), rows);
  EXPECT_TRUE(scenarios.at("stop").at("targets_met").get<bool>());

  // coverage.csv: a metric column then one per report; coverage.md is a Markdown table of the same.
  const std::string table = read_text(dir / "coverage.csv");
  EXPECT_EQ(table.rfind("metric,emrm plan,HARA only,STPA only,manual grid\n", 0), 0u) << table;
  EXPECT_THAT(table, HasSubstr("C1 cells,holds,"));
  EXPECT_THAT(read_text(dir / "coverage.md"),
              HasSubstr("| metric | emrm plan | HARA only | STPA only | manual grid |"));
}

TEST(PlanCli, SameCommandTwiceGivesIdenticalScenarios) {
  const auto a = scratch_dir("plan-twice-a");
  const auto b = scratch_dir("plan-twice-b");
  ASSERT_EQ(run_emrm("plan " + quoted(example("odd.yaml")) + " -o " + quoted(a)).exit_code, 0);
  ASSERT_EQ(run_emrm("plan " + quoted(example("odd.yaml")) + " --output " + quoted(b)).exit_code, 0);
  const std::string first = read_text(a / "scenarios.csv");
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, read_text(b / "scenarios.csv"));
  EXPECT_EQ(read_text(a / "coverage.json"), read_text(b / "coverage.json"));
}

TEST(PlanCli, SafetyOverride) {
  const auto dir = scratch_dir("plan-safety");
  const auto ok = run_emrm("plan " + quoted(example("odd.yaml")) + " --safety " + quoted(example("safety.yaml")) +
                           " -o " + quoted(dir / "ok"));
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  const auto missing = run_emrm("plan " + quoted(example("odd.yaml")) + " --safety " +
                                quoted(dir / "no_such_safety.yaml") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(missing.exit_code, 2) << missing.out << missing.err;
  EXPECT_THAT(missing.err, HasSubstr("no_such_safety.yaml"));
  EXPECT_FALSE(fs::exists(dir / "out" / "scenarios.csv"));
}

TEST(PlanCli, MissingOddOrOutputIsAUsageError) {
  const auto dir = scratch_dir("plan-usage");
  EXPECT_EQ(run_emrm("plan " + quoted(dir / "none.yaml") + " -o " + quoted(dir / "out")).exit_code, 2);
  EXPECT_EQ(run_emrm("plan " + quoted(example("odd.yaml"))).exit_code, 2);
}

TEST(PlanCli, CopyWithAbsolutePathsStillPlans) {
  // The scratch copies below differ from this one by a single edit.
  const auto dir = scratch_dir("plan-copy");
  write_text(dir / "odd.yaml", odd_text());
  const auto r = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(PlanCli, UnknownFactorInAPredicate) {
  const std::string text = replaced(odd_text(), "relevance: \"speed_kph / 3.6 * ttc_s <= 24.5\"",
                                    "relevance: \"speed_kph / 3.6 * ttc <= 24.5\"");
  expect_bad_odd("unknown-factor", text, "ttc <= 24.5", 0, "ttc");
}

TEST(PlanCli, OverlappingBinEdges) {
  const std::string text = replaced(odd_text(), "bins: [30, 44, 58, 72]", "bins: [30, 44, 44, 72]");
  expect_bad_odd("overlapping", text, "[30, 44, 44, 72]", 0, "increase");
}

TEST(PlanCli, UnsortedBinEdges) {
  const std::string text = replaced(odd_text(), "bins: [0.1, 0.35, 0.65, 1.0]", "bins: [0.1, 0.65, 0.35, 1.0]");
  expect_bad_odd("unsorted", text, "[0.1, 0.65, 0.35, 1.0]", 0, "increase");
}

TEST(PlanCli, PriorThatDoesNotNormalise) {
  const std::string text = replaced(odd_text(), "prior: [0.30, 0.45, 0.25]", "prior: [0.30, 0.45, 0.35]");
  expect_bad_odd("prior", text, "[0.30, 0.45, 0.35]", 0, "normalise");
}

TEST(PlanCli, StrengthLargerThanTheFactors) {
  // Four influential factors: strength 3 is fine, but a strength above the five factors is not.
  expect_bad_odd("strength-6", replaced(odd_text(), "strength: 2", "strength: 6"), "strength: 6", 10, "strength");
  // With only speed and passage width influential, strength 3 exceeds them.
  std::string text = replaced(odd_text(), "strength: 2", "strength: 3");
  text = replaced(text, "    kinks: [1.0]", "    kinks: [1.0]\n    influential: false");
  text = replaced(text, "    nominal: 1.0\n", "    nominal: 1.0\n    influential: false\n");
  expect_bad_odd("strength-3", text, "strength: 3", 10, "influential");
}

TEST(PlanCli, UnsatisfiableConstraintSet) {
  const std::string text =
      replaced(odd_text(), "\ntracked:", "\nconstraints:\n  - \"mu >= 0.1\"\n  - \"speed_kph > 80\"\ntracked:");
  expect_bad_odd("unsatisfiable", text, "\"speed_kph > 80\"", 0, "unsatisfiable");
}

// ---- checks across files: the safety case as `emrm analyze` checks it ------------------------------

TEST(PlanCli, SafetyCaseWithErrorFindingsIsRefusedUnlessAllowed) {
  const fs::path dir =
      edited_small_example("plan-findings", "safety.yaml", "hazards: [H8, H1, H9]", "hazards: [H8, H1, H9, H99]");
  const auto refused = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "refused"));
  EXPECT_EQ(refused.exit_code, 1) << refused.out << refused.err;
  EXPECT_THAT(refused.out, HasSubstr("1 error, "));
  EXPECT_THAT(refused.out, HasSubstr("error SAF001 [UCA1]: UCA 'UCA1' refers to hazard 'H99', which does not exist"));
  EXPECT_THAT(refused.out, HasSubstr("--allow-findings"));
  EXPECT_FALSE(fs::exists(dir / "refused" / "scenarios.csv"));

  // Allowed, the plan is built, but the phantom hazard is not one to cover: the case's hazards are.
  const auto allowed = run_emrm("plan " + quoted(dir / "odd.yaml") + " --allow-findings -o " + quoted(dir / "allowed"));
  EXPECT_EQ(allowed.exit_code, 0) << allowed.out << allowed.err;
  EXPECT_THAT(allowed.out, HasSubstr((dir / "safety.yaml").string() +
                                     ": warning: planned despite 1 error finding (--allow-findings)"));
  const std::string safety = read_text(dir / "safety.yaml");
  std::size_t hazards = 0;
  for (auto at = safety.find("\n  - id: H"); at != std::string::npos; at = safety.find("\n  - id: H", at + 1))
    ++hazards;
  const auto coverage = nlohmann::json::parse(read_text(dir / "allowed" / "coverage.json"));
  EXPECT_EQ(coverage.at("plan").at("hazards").at("total").get<std::size_t>(), hazards);
  EXPECT_THAT(coverage.at("plan").at("hazards").at("missing").dump(), ::testing::Not(HasSubstr("H99")));
}

TEST(PlanCli, UcaNamingATransitionTheFsmLacksIsRefused) {
  const fs::path dir = edited_small_example("plan-transition", "safety.yaml", "{from: S4, event: emrm_done, to: S1}",
                                            "{from: S4, event: emrm_finished, to: S1}");
  const auto r = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_THAT(r.out, HasSubstr("error SAF011 [UCA4]"));
  EXPECT_THAT(r.out, HasSubstr("S4 -emrm_finished-> S1"));
  EXPECT_FALSE(fs::exists(dir / "out" / "scenarios.csv"));
}

// ---- checks across files: the ODD against the scene, the simulator and the safety case --------------

TEST(PlanCli, FrictionAsAPercentageIsBadInputAtTheOdd) {
  const fs::path dir = small_example("plan-mu-percent");
  const std::string text =
      replaced(read_text(dir / "odd.yaml"), "type: constant, value: 1.0}", "type: constant, value: 50}");
  expect_bad_odd_at(dir / "odd.yaml", text, "50}", 0,
                    "mu 50: expected a friction coefficient in (0, 2]; a percentage?");
}

// An unknown strategy is found by `plan`, at its name in the ODD, not by `run` at the generated
// scenarios.json:1:1; likewise the acceptance's strategy.
TEST(PlanCli, AnUnknownStrategyIsBadInputAtItsName) {
  const fs::path dir = small_example("plan-strategy");
  const std::string odd = read_text(dir / "odd.yaml");
  expect_bad_odd_at(dir / "odd.yaml", odd + "strategies: [emergency_stpo, dodge]\n", "emergency_stpo", 0,
                    "unknown strategy 'emergency_stpo' (did you mean 'emergency_stop'?)");
  expect_bad_odd_at(dir / "odd.yaml", odd + "acceptance: {strategy: emmr, outcome: avoided}\n", "emmr", 0,
                    "acceptance: unknown strategy 'emmr'");
}

TEST(PlanCli, SpeedInAnotherUnitThanTheSimulatorsIsBadInputAtTheUnit) {
  const fs::path dir = small_example("plan-speed-unit");
  const std::string text =
      replaced(read_text(dir / "odd.yaml"), "{name: speed_kph, bins:", "{name: speed_kph, unit: m/s, bins:");
  expect_bad_odd_at(dir / "odd.yaml", text, "m/s", 0, "speed_kph: unit 'm/s': expected km/h");
}

TEST(PlanCli, WarnsWhereTheRelevanceRuleAdmitsWhatTheSceneCannotPlace) {
  const fs::path dir = edited_small_example("plan-relevance", "odd.yaml", "ttc_s <= 24.5", "ttc_s <= 40");
  const std::string odd = read_text(dir / "odd.yaml");
  const auto r = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "out"));
  EXPECT_NE(r.exit_code, 2) << r.out << r.err;
  const std::string at_relevance =
      (dir / "odd.yaml").string() + ":" + line_col(odd, "speed_kph / 3.6 * ttc_s <= 40") + ": warning: ";
  const std::string at_limit =
      (dir / "scene.yaml").string() + ":" + line_col(read_text(dir / "scene.yaml"), "max_initial_distance_m: 24.5", 24);
  EXPECT_THAT(r.out, HasSubstr(at_relevance)) << r.out;
  EXPECT_THAT(
      r.out, HasSubstr(" planned scenarios lie beyond the scene's max_initial_distance_m = 24.5 m (" + at_limit + ")"));
  EXPECT_THAT(r.out, HasSubstr("the relevance rule 'speed_kph / 3.6 * ttc_s <= 40' admits them"));
  EXPECT_THAT(r.out, HasSubstr("plan      1 warning\n"));
}

TEST(PlanCli, WarnsWhereTheOddReachesBeyondTheSafetyCasesRange) {
  const fs::path dir = edited_small_example("plan-ranges", "odd.yaml", "bins: [30, 51, 72]", "bins: [30, 51, 100]");
  const std::string odd = read_text(dir / "odd.yaml");
  const auto r = run_emrm("plan " + quoted(dir / "odd.yaml") + " -o " + quoted(dir / "out"));
  EXPECT_NE(r.exit_code, 2) << r.out << r.err;
  const std::string safety = read_text(dir / "safety.yaml");
  EXPECT_THAT(r.out, HasSubstr((dir / "odd.yaml").string() + ":" + line_col(odd, "100]") +
                               ": warning: speed_kph spans [30, 100] in the ODD, beyond [30, 72] of the safety case (" +
                               (dir / "safety.yaml").string() + ":" + line_col(safety, "{name: speed_kph") + ")"))
      << r.out;
}

}  // namespace plan_cli_test
}  // namespace emrm::e2e
