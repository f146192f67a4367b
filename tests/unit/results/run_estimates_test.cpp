// estimates.json's writer and typed reader (results/run_estimates.hpp, core/json_archive.hpp): every
// field written is read back, the layout is the one the report and scripts rely on, and a file that
// is not as `emrm run` writes it is refused with the file, line and column of what is wrong.

#include "emrm/results/run_estimates.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "emrm/core/error.hpp"
#include "scratch.hpp"

namespace emrm::results {
namespace run_estimates_test {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Every field unlike its default, the optional ones present.
RunEstimates every_field() {
  RunEstimates e;
  e.scenarios = 41;
  e.feasible = 37;
  e.confidence = 0.9;
  e.unsimulated_factors = {"weather"};
  e.weighted_success = {
      {"all", {.n = 41, .weight = 40.5, .n_eff = 33.25, .estimate = 0.875, .wilson = {0.7, 0.95}, .shortfall = {}}},
      {"brake_loss",
       {.n = 0, .weight = 0.0, .n_eff = 0.0, .estimate = {}, .wilson = {0.0, 1.0}, .shortfall = "no tests"}},
      {"aaa_first_by_name",
       {.n = 2, .weight = 1.5, .n_eff = 2.0, .estimate = 0.5, .wilson = {0.1, 0.9}, .shortfall = {}}}};
  e.widest_wilson_half_width = 0.45;
  e.tracked_cells = 1;
  e.widest_tracked_wilson_half_width = 0.125;
  e.epsilon = 0.2;
  e.cells = {{.cell = "c1.0",
              .levels = {{"speed_kph", "[44, 58)"}, {"mu", "dry"}},
              .n = 12,
              .successes = 9,
              .wilson = {0.5, 0.9},
              .hoeffding_epsilon = 0.39,
              .tracked = true},
             {.cell = "c0.2",
              .levels = {},
              .n = 3,
              .successes = 3,
              .wilson = {0.4, 1.0},
              .hoeffding_epsilon = 0.8,
              .tracked = false}};
  e.fsm_transitions = {.exercised = 9, .total = 11, .missed = {"S2 -fault-> S5", "S3 -timeout-> S6"}};
  e.traceability_rows = 7;
  e.shortfalls = {{"too_few_tests", "c0.2", "cell c0.2 has 3 tests of 5"}};
  e.acceptance = Acceptance{"emrm", "mitigated"};
  e.factors = std::vector<scenario::PlanFactor>{{.name = "speed_kph",
                                                 .unit = "km/h",
                                                 .type = scenario::FactorType::kInteger,
                                                 .levels = {{0, "[30, 44)", 0.25}, {1, "[44, 58)", 0.75}},
                                                 .influential = false,
                                                 .nominal = 50.0}};
  e.plan = PlanLocation{"../plan/scenarios.csv", "../plan/coverage.json"};
  return e;
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path dir = test::scratch_dir("run-estimates-test", name);
  fs::create_directories(dir);
  std::ofstream(dir / "estimates.json") << text;
  return dir / "estimates.json";
}

TEST(RunEstimates, EveryFieldWrittenIsReadBack) {
  const RunEstimates e = every_field();
  const std::string text = run_estimates_text(e);
  const RunEstimates back = read_run_estimates(write("every-field", text));
  EXPECT_EQ(run_estimates_text(back), text);
  // A few fields by value, so that a reader that drops what it reads would fail the comparison too.
  ASSERT_EQ(back.weighted_success.size(), 3U);
  EXPECT_EQ(back.weighted_success[2].first, "aaa_first_by_name");  // the writer's order, not sorted
  EXPECT_FALSE(back.weighted_success[1].second.estimate.has_value());
  EXPECT_EQ(back.weighted_success[1].second.shortfall, "no tests");
  EXPECT_DOUBLE_EQ(back.cells[0].wilson.high, 0.9);
  EXPECT_EQ(back.cells[0].levels[1], (std::pair<std::string, std::string>{"mu", "dry"}));
  EXPECT_EQ(back.factors->at(0).type, scenario::FactorType::kInteger);
  EXPECT_DOUBLE_EQ(back.factors->at(0).levels[1].prior, 0.75);
  EXPECT_EQ(back.plan->coverage, "../plan/coverage.json");
  EXPECT_EQ(back.fsm_transitions.missed.size(), 2U);
  EXPECT_EQ(back.shortfalls.at(0).subject, "c0.2");
}

TEST(RunEstimates, TheLayoutIsTheDocumentedOne) {
  const auto j = nlohmann::ordered_json::parse(run_estimates_text(every_field()));
  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"scenarios", "feasible", "confidence", "unsimulated_factors",
                                            "weighted_success", "widest_wilson_half_width", "tracked_cells",
                                            "widest_tracked_wilson_half_width", "epsilon", "cells", "fsm_transitions",
                                            "traceability_rows", "shortfalls", "acceptance", "factors", "plan"}));
  // An estimate of no test is null; a shortfall only where the plan has one; the interval a pair.
  EXPECT_TRUE(j["weighted_success"]["brake_loss"]["estimate"].is_null());
  EXPECT_FALSE(j["weighted_success"]["all"].contains("shortfall"));
  EXPECT_EQ(j["cells"][0]["wilson"], nlohmann::ordered_json({0.5, 0.9}));
  EXPECT_EQ(j["cells"][0]["levels"]["speed_kph"], "[44, 58)");
  // What the plan adds is left out when there is no plan; a plan without coverage says null.
  RunEstimates bare = every_field();
  bare.acceptance.reset();
  bare.factors.reset();
  bare.plan = PlanLocation{"scenarios.csv", {}};
  const auto b = nlohmann::ordered_json::parse(run_estimates_text(bare));
  EXPECT_FALSE(b.contains("acceptance"));
  EXPECT_FALSE(b.contains("factors"));
  EXPECT_TRUE(b["plan"]["coverage"].is_null());
  EXPECT_EQ(run_estimates_text(read_run_estimates(write("bare", b.dump(2)))), b.dump(2) + "\n");
}

// The message of reading `text`, which must fail.
std::string refusal(const std::string& name, const std::string& text) {
  try {
    (void)read_run_estimates(write(name, text));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "read " << name;
  return {};
}

// `text` with its first `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The 1-based line of the first `what` in `text`.
int line_of(const std::string& text, const std::string& what) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(text.find(what)), '\n'));
}

TEST(RunEstimates, AFileNotAsEmrmRunWritesItIsRefusedWhereItIsWrong) {
  const std::string text = run_estimates_text(every_field());
  {  // a number that is text
    const std::string bad = replaced(text, "\"successes\": 9", "\"successes\": \"nine\"");
    const std::string message = refusal("wrong-type", bad);
    EXPECT_THAT(message, HasSubstr(fmt::format("estimates.json:{}:", line_of(bad, "\"nine\""))));
    EXPECT_THAT(message, HasSubstr("expected an integer"));
  }
  {  // a member missing
    const std::string message = refusal("missing", replaced(text, "\"epsilon\": 0.2,", ""));
    EXPECT_THAT(message, HasSubstr("epsilon"));
  }
  {  // a member misspelt: the one expected is missing; a member too many
    const std::string message = refusal("misspelt", replaced(text, "\"tracked_cells\"", "\"traced_cells\""));
    EXPECT_THAT(message, HasSubstr("missing required field 'tracked_cells'"));
    EXPECT_THAT(refusal("surplus", replaced(text, "\"epsilon\": 0.2,", "\"epsilon\": 0.2, \"epsilom\": 0.3,")),
                HasSubstr("epsilom"));
  }
  {  // an interval of three numbers, an unknown factor type, not an object, not JSON
    std::string three = text;
    three.insert(three.find('[', three.find("\"wilson\"", three.find("c1.0"))) + 1, " 0.0,");
    EXPECT_THAT(refusal("interval", three), HasSubstr("[low, high]"));
    EXPECT_THAT(refusal("type", replaced(text, "\"integer\"", "\"whole\"")), HasSubstr("whole"));
    EXPECT_THAT(refusal("array", "[1, 2]\n"), HasSubstr("expected a JSON object"));
    EXPECT_THAT(refusal("broken", text.substr(0, text.size() / 2)), HasSubstr("estimates.json:"));
  }
}

}  // namespace run_estimates_test
}  // namespace emrm::results
